//! Helpers for the node library's tests: cook a network given as node entries.
#![allow(dead_code)]

use std::sync::Arc;

use geode_geo::Geometry;
use geode_graph::{load_str, Cache, CookOptions, Engine};
use geode_op::Value;

/// A network document from `"name": {node}` entries and an output name.
pub fn net(nodes: &str, output: &str) -> String {
    format!(r#"{{"geode": "network", "version": 1, "output": "{output}", "nodes": {{{nodes}}}}}"#)
}

fn joined<E: ToString>(errors: Vec<E>) -> String {
    errors
        .iter()
        .map(|e| e.to_string())
        .collect::<Vec<_>>()
        .join("\n")
}

/// Cooks `output` at `frame` (cache off); errors joined one per line.
pub fn cook_at(nodes: &str, output: &str, frame: f64) -> Result<Value, String> {
    let net = load_str(&net(nodes, output), &geode_nodes::registry()).map_err(joined)?;
    let cache = Cache::disabled();
    Engine::new(net, &cache)
        .cook_output(&CookOptions::at_frame(frame))
        .map(|r| r.value)
        .map_err(joined)
}

/// The geometry `output` cooks to at frame 1.
pub fn geo(nodes: &str, output: &str) -> Arc<Geometry> {
    cook_at(nodes, output, 1.0)
        .unwrap_or_else(|e| panic!("{e}"))
        .as_geometry()
        .unwrap()
        .clone()
}

/// The error `output` fails with at frame 1.
pub fn err(nodes: &str, output: &str) -> String {
    cook_at(nodes, output, 1.0).expect_err("an error")
}

/// The typed errors `output` fails with at frame 1 (the network must load).
pub fn cook_errors(nodes: &str, output: &str) -> Vec<geode_op::CookError> {
    let net = load_str(&net(nodes, output), &geode_nodes::registry())
        .unwrap_or_else(|e| panic!("{}", joined(e)));
    let cache = Cache::disabled();
    match Engine::new(net, &cache).cook_output(&CookOptions::at_frame(1.0)) {
        Ok(_) => panic!("expected an error"),
        Err(e) => e,
    }
}

/// The geometry of `output` cooked with `threads` worker threads, no cache.
pub fn cook_on(threads: usize, nodes: &str, output: &str) -> Arc<Geometry> {
    let net = load_str(&net(nodes, output), &geode_nodes::registry()).unwrap();
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| {
            let cache = Cache::disabled();
            Engine::new(net, &cache)
                .cook_output(&CookOptions::at_frame(1.0))
                .unwrap()
                .value
                .as_geometry()
                .unwrap()
                .clone()
        })
}

/// The warnings node `output` (a path like "/v") gave at frame 1.
pub fn warnings(nodes: &str, output: &str) -> Vec<String> {
    let name = output.trim_start_matches('/');
    let net = load_str(&net(nodes, name), &geode_nodes::registry()).unwrap();
    let cache = Cache::disabled();
    let r = Engine::new(net, &cache)
        .cook(output, &CookOptions::at_frame(1.0))
        .unwrap();
    r.events
        .iter()
        .find(|e| e.path == output)
        .map(|e| e.warnings.to_vec())
        .unwrap_or_default()
}
