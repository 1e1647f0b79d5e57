//! Cooking nodes of another network file (object_merge's `file`): the file
//! is read through the cook's file access, loaded with this library's
//! registry and cooked by an engine of its own at the same frame.
//!
//! The other file's results go through a process-wide memory cache, so the
//! cook that computes object_merge's key (the merged values' content
//! hashes, which cover whatever the other network reads) and the cook that
//! builds its result cook the other network once. A file that reaches
//! itself through such merges is refused by the chain in
//! [`CookEnv::nesting`], before it recurses.

use std::sync::OnceLock;

use geode_graph::{Cache, CookOptions, Engine};
use geode_op::{network_identity, CancelToken, CookEnv, CookError, ErrorKind, Registry, Value, MB};

/// Most network files deep a chain of merges may go.
pub const MAX_NESTING: usize = 16;

/// Where and when the other network is cooked: the cook's own place.
pub(crate) struct Outer<'a> {
    pub path: &'a str,
    pub param: &'a geode_op::ParamSpec,
    pub frame: f64,
    pub env: &'a CookEnv,
    pub cancel: &'a CancelToken,
}

impl<'a> Outer<'a> {
    /// A cook's place, `param` (naming the file) blamed for what fails.
    pub fn new(
        path: &'a str,
        param: &'a geode_op::ParamSpec,
        frame: f64,
        env: &'a CookEnv,
        cancel: &'a CancelToken,
    ) -> Self {
        Outer {
            path,
            param,
            frame,
            env,
            cancel,
        }
    }
}

fn registry() -> &'static Registry {
    static REGISTRY: OnceLock<Registry> = OnceLock::new();
    REGISTRY.get_or_init(crate::registry)
}

fn cache() -> &'static Cache {
    static CACHE: OnceLock<Cache> = OnceLock::new();
    CACHE.get_or_init(|| Cache::new(512 * MB as usize))
}

/// The values of nodes `paths` (absolute, or from the other network's top
/// level) of network file `file`, in order.
pub(crate) fn cook_nodes(
    outer: &Outer,
    file: &str,
    paths: &[&str],
) -> Result<Vec<Value>, CookError> {
    let (net, env) = load(outer, file)?;
    let opts = CookOptions {
        frame: outer.frame,
        cancel: outer.cancel.clone(),
        progress: None,
        env,
        writes: false,
    };
    let engine = Engine::new(net, cache());
    paths
        .iter()
        .map(|p| {
            let at = node_path(p).map_err(|why| {
                refuse(outer, ErrorKind::Parameter, format!("in `{file}`: {why}"))
            })?;
            engine.cook(&at, &opts).map(|r| r.value).map_err(|errors| {
                if errors.iter().any(|e| e.kind == ErrorKind::Cancelled) {
                    return CookError::cancelled(outer.path);
                }
                let first = &errors[0];
                refuse(outer, first.kind, format!("in `{file}`: {first}"))
                    .with_source(first.clone())
            })
        })
        .collect()
}

/// What `geode check` can say without cooking: the file is readable, not
/// one being cooked, loads, and holds the nodes named without load
/// problems of their own.
pub(crate) fn check_nodes(outer: &Outer, file: &str, paths: &[&str]) -> Result<(), CookError> {
    let (net, _) = load(outer, file)?;
    for p in paths {
        let at = node_path(p)
            .map_err(|why| refuse(outer, ErrorKind::Parameter, format!("in `{file}`: {why}")))?;
        if !net.paths().any(|known| known == at) {
            return Err(refuse(
                outer,
                ErrorKind::Parameter,
                format!("in `{file}`: {at}: no such node"),
            ));
        }
        if let Some(problem) = net.node_problems(&at).first() {
            return Err(refuse(
                outer,
                ErrorKind::Network,
                format!("in `{file}`: {problem}"),
            ));
        }
    }
    Ok(())
}

fn refuse(outer: &Outer, kind: ErrorKind, message: String) -> CookError {
    CookError::new(outer.path, kind, message).at_param(outer.param.name)
}

/// The other network, loaded with its problems kept on their nodes (as
/// a network opened here: only a merge that reads a broken node fails),
/// and the environment it cooks in: its own `$HIP`, the chain of files
/// one longer.
fn load(outer: &Outer, file: &str) -> Result<(geode_graph::Network, CookEnv), CookError> {
    let real = outer
        .env
        .files
        .readable(std::path::Path::new(file))
        .map_err(|e| refuse(outer, ErrorKind::Io, e.to_string()))?;
    let identity = network_identity(&real);
    if outer.env.nesting.contains(&identity) {
        let chain = outer.env.nesting.join(" -> ");
        return Err(refuse(
            outer,
            ErrorKind::Network,
            format!("`{file}` is already being cooked ({chain} -> {identity}): a network file may not merge from itself"),
        ));
    }
    if outer.env.nesting.len() >= MAX_NESTING {
        return Err(refuse(
            outer,
            ErrorKind::Resource,
            format!("`{file}` would be the {}th network file merged into another; at most {MAX_NESTING} may nest", outer.env.nesting.len() + 1),
        ));
    }
    let text = outer
        .env
        .files
        .read_text(&real, outer.env.memory_budget, &|| {
            outer.cancel.is_cancelled()
        })
        .map_err(|e| match e {
            geode_op::FileRefusal::Cancelled => CookError::cancelled(outer.path),
            e => refuse(outer, ErrorKind::Io, e.to_string()),
        })?;
    let net = geode_graph::Document::from_json(&text)
        .map_err(|e| {
            refuse(
                outer,
                ErrorKind::Network,
                format!("`{file}` does not load: {e}"),
            )
        })
        .and_then(|doc| {
            geode_graph::Network::load_partial(&doc, registry()).map_err(|errors| {
                let all: Vec<String> = errors.iter().map(ToString::to_string).collect();
                refuse(
                    outer,
                    ErrorKind::Network,
                    format!("`{file}` does not load: {}", all.join("; ")),
                )
            })
        })?;
    let mut env = outer.env.clone();
    env.nesting.push(identity);
    if let Some(dir) = real.parent() {
        env.hip = dir.to_string_lossy().into_owned();
    }
    Ok((net, env))
}

/// A path of the other network from its top level (`a`, `/a`, `sub/a`,
/// `sub/../a`); patterns and paths above the top are refused.
fn node_path(p: &str) -> Result<String, String> {
    if p.contains(['*', '?', '[']) {
        return Err(format!(
            "`{p}`: objects are named by exact paths, not patterns"
        ));
    }
    let mut at = Vec::new();
    for part in p.split('/').filter(|s| !s.is_empty() && *s != ".") {
        if part == ".." {
            if at.pop().is_none() {
                return Err(format!("`{p}` goes above the network's top level"));
            }
        } else {
            at.push(part);
        }
    }
    Ok(format!("/{}", at.join("/")))
}
