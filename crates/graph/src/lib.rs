//! geode's node networks: the versioned JSON document ([`Document`]),
//! keyframed channels, loading with every problem reported at once
//! ([`Network::load`]), and the cook [`Engine`]: inputs cooked in parallel waves,
//! content-hashed keys with early cut-off, a process-wide byte-bounded LRU
//! [`Cache`], solo view of any inner node, and a `tracing` span per cook.
//! Knows no concrete node: node types come from a [`geode_op::Registry`].

mod block;
pub mod cache;
pub mod catalogue;
pub mod channel;
mod compiled_param;
pub mod container;
pub mod document;
pub mod edit;
mod engine;
mod expr;
mod json_path;
mod load;
mod network;

pub use block::BlockKind;
pub use cache::{Cache, CacheStats, Cached, Store};
pub use container::{container_spec, has_meta, holds_network, node_spec, node_specs};
pub use document::{Document, SyntaxError};
pub use engine::{CookEvent, CookOptions, CookResult, Engine};
pub use load::LoadError;
pub use network::{Network, Promotion};

/// Parses and loads a network document in one step; syntax errors come back
/// as a single load error naming the line and column.
pub fn load_str(text: &str, registry: &geode_op::Registry) -> Result<Network, Vec<LoadError>> {
    let doc = Document::from_json(text).map_err(|e| {
        vec![LoadError {
            path: e.node.clone().unwrap_or_else(|| "/".into()),
            param: e.param.clone(),
            // The node and parameter are the error's own path and param.
            message: format!("line {}, column {}: {}", e.line, e.column, e.message),
            position: None,
        }]
    })?;
    Network::load(&doc, registry)
}
