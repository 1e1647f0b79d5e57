//! The document behind a Python `Network`: edits through geode's own edit functions, each parameter checked as it is set, the loaded network and engine made when a cook needs them.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock, Weak};

use geode_geo::Geometry;
use geode_graph::document::{Document, NetworkDoc, NodeDoc};
use geode_graph::edit::{apply_in_place, Edit, Flag};
use geode_graph::{Cache, Engine, LoadError, Network};
use geode_op::{CookEnv, HeldGeometry, ParamValue, Registry};
use pyo3::prelude::*;
use pyo3::types::PyList;
use serde_json::Value as Json;

use crate::errors::{edit_error, file_error, invalid, load_errors, not_found};

/// The node types a Python session knows: geode's whole library.
pub fn registry() -> &'static Registry {
    static REGISTRY: OnceLock<Registry> = OnceLock::new();
    REGISTRY.get_or_init(geode_nodes::registry)
}

/// The process's cook cache, as `geode cook` makes it: memory bounded by
/// `GEODE_CACHE_MB`, with `GEODE_CACHE_DIR`'s disk cache behind it.
fn cache() -> PyResult<&'static Cache> {
    static CACHE: OnceLock<Cache> = OnceLock::new();
    if let Some(c) = CACHE.get() {
        return Ok(c);
    }
    let cache = geode_store::DiskCache::cook_cache_from_env()
        .map_err(|e| file_error(Path::new("GEODE_CACHE_DIR"), e))?;
    Ok(CACHE.get_or_init(|| cache))
}

/// The name a node is loaded under when its parameters are checked alone.
const ALONE: &str = "checked";

pub struct State {
    pub doc: Document,
    /// The file it was loaded from or saved to (its folder is `$HIP`).
    pub path: Option<PathBuf>,
    /// Geometry given to `python_input` nodes, by content hash.
    pub held: BTreeMap<u128, Arc<Geometry>>,
    /// The loaded network of `doc` with its engine, made when first needed
    /// after an edit and shared by the cooks that run at once.
    pub engine: Option<Arc<Result<Engine<'static>, Vec<LoadError>>>>,
}

impl State {
    pub fn new(doc: Document, path: Option<PathBuf>) -> State {
        State {
            doc,
            path,
            held: BTreeMap::new(),
            engine: None,
        }
    }

    pub fn edit(&mut self, edit: &Edit) -> PyResult<()> {
        let param = match edit {
            Edit::SetParam { param, .. }
            | Edit::SetKey { param, .. }
            | Edit::DeleteKey { param, .. } => Some(param.as_str()),
            Edit::SetSpare { name, .. } => Some(name.as_str()),
            _ => None,
        };
        apply_in_place(&mut self.doc, edit, registry()).map_err(|e| edit_error(&e, param))?;
        self.engine = None;
        Ok(())
    }

    pub fn engine(&mut self) -> PyResult<Arc<Result<Engine<'static>, Vec<LoadError>>>> {
        if let Some(e) = &self.engine {
            return Ok(e.clone());
        }
        let cache = cache()?;
        let loaded =
            Network::load_partial(&self.doc, registry()).map(|net| Engine::new(net, cache));
        let e = Arc::new(loaded);
        self.engine = Some(e.clone());
        Ok(e)
    }

    /// The load problems of `path`'s parameter `param` (all of the node's
    /// for none). The node is first loaded alone, with its parameters and
    /// without its wires, which costs the same whatever the network's size;
    /// only a problem found there is confirmed against the whole network
    /// (an expression may name a node the lone copy lacks).
    pub fn problems_of(&mut self, path: &str, param: Option<&str>) -> PyResult<Vec<LoadError>> {
        let node = self.node(path)?.clone();
        let alone = Document {
            network: NetworkDoc {
                nodes: BTreeMap::from([(
                    ALONE.to_owned(),
                    NodeDoc {
                        inputs: Vec::new(),
                        ..node
                    },
                )]),
                ..NetworkDoc::default()
            },
            ..Document::new()
        };
        let lone_problem = match Network::load_partial(&alone, registry()) {
            Ok(net) => net
                .node_problems(&format!("/{ALONE}"))
                .iter()
                .any(|e| e.param.is_some() && (param.is_none() || e.param.as_deref() == param)),
            Err(_) => true,
        };
        if !lone_problem {
            return Ok(Vec::new());
        }
        let engine = self.engine()?;
        let all: Vec<LoadError> = match &*engine {
            Ok(e) => e.network().node_problems(path).to_vec(),
            Err(errors) => errors.iter().filter(|e| e.path == path).cloned().collect(),
        };
        Ok(all
            .into_iter()
            .filter(|e| param.is_none() || e.param.as_deref() == param)
            .collect())
    }

    pub fn node(&self, path: &str) -> PyResult<&NodeDoc> {
        node_at(&self.doc.network, path)
            .ok_or_else(|| not_found("node", path, None, "no such node"))
    }

    /// Keeps only the held geometry some `python_input` still names.
    pub fn prune_held(&mut self) {
        let named = held_hashes(&self.doc.network);
        self.held.retain(|h, _| named.contains(h));
    }
}

pub fn node_at<'d>(root: &'d NetworkDoc, path: &str) -> Option<&'d NodeDoc> {
    let mut net = root;
    let mut node = None;
    for name in path.split('/').filter(|s| !s.is_empty()) {
        let n = net.nodes.get(name)?;
        node = Some(n);
        if let Some(inner) = n.network.as_deref() {
            net = inner;
        }
    }
    node
}

pub fn network_at<'d>(root: &'d NetworkDoc, parent: &str) -> Option<&'d NetworkDoc> {
    if parent == "/" || parent.is_empty() {
        return Some(root);
    }
    node_at(root, parent)?.network.as_deref()
}

/// The content hashes the `python_input` nodes of `net` (subnets included) name.
pub fn held_hashes(net: &NetworkDoc) -> Vec<u128> {
    let mut out = Vec::new();
    let mut stack = vec![net];
    while let Some(net) = stack.pop() {
        for n in net.nodes.values() {
            if n.ty == "python_input" {
                let named = n.params.get("geometry").and_then(Json::as_str);
                out.extend(named.and_then(geode_nodes::held::parse_hash));
            }
            stack.extend(n.network.as_deref());
        }
    }
    out
}

/// Every geometry Python has handed a `python_input`, by content hash, for
/// as long as it lives anywhere: a network loaded from a file, or copied,
/// cooks the geometry another network was given.
static LIVE: Mutex<BTreeMap<u128, Weak<Geometry>>> = Mutex::new(BTreeMap::new());

/// Records `geo` as live (and forgets the geometry no one holds any more).
pub fn hold(hash: u128, geo: &Arc<Geometry>) {
    let mut live = LIVE.lock().unwrap_or_else(|p| p.into_inner());
    live.retain(|_, g| g.strong_count() > 0);
    live.insert(hash, Arc::downgrade(geo));
}

fn live(hash: u128) -> Option<Arc<Geometry>> {
    let live = LIVE.lock().unwrap_or_else(|p| p.into_inner());
    live.get(&hash).and_then(Weak::upgrade)
}

pub fn join(parent: &str, name: &str) -> String {
    if parent == "/" || parent.is_empty() {
        format!("/{name}")
    } else {
        format!("{parent}/{name}")
    }
}

pub fn flag_of(name: &str) -> PyResult<Flag> {
    Ok(match name {
        "bypass" => Flag::Bypass,
        "display" => Flag::Display,
        "template" => Flag::Template,
        _ => {
            return Err(invalid(format!(
                "`{name}` is not a flag (bypass, display, template)"
            )))
        }
    })
}

pub fn param_value_to_py<'py>(py: Python<'py>, v: &ParamValue) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        ParamValue::Float(x) => x.into_pyobject(py)?.into_any(),
        ParamValue::Int(i) => i.into_pyobject(py)?.into_any(),
        ParamValue::Toggle(b) => pyo3::types::PyBool::new(py, *b).to_owned().into_any(),
        ParamValue::Vector(v) => pyo3::types::PyTuple::new(py, v)?.into_any(),
        ParamValue::String(s) => s.into_pyobject(py)?.into_any(),
        ParamValue::List(rows) => {
            let out = PyList::empty(py);
            for row in rows {
                let r = PyList::empty(py);
                for f in row {
                    r.append(param_value_to_py(py, f)?)?;
                }
                out.append(r)?;
            }
            out.into_any()
        }
        ParamValue::Ramp(ramp) => {
            let out = PyList::empty(py);
            for k in ramp.keys() {
                out.append((
                    k.pos,
                    k.value.to_vec(),
                    format!("{:?}", k.basis).to_lowercase(),
                ))?;
            }
            out.into_any()
        }
    })
}

impl State {
    /// The cook's environment: `$HIP` is the network file's folder, and
    /// the held geometry goes with it.
    pub fn env(&self) -> CookEnv {
        let env = match &self.path {
            Some(p) => CookEnv::for_network(p),
            None => CookEnv::from_process(),
        };
        // Its own geometry, and what its python_inputs name that lives elsewhere.
        let named = held_hashes(&self.doc.network);
        let elsewhere = named
            .into_iter()
            .filter(|h| !self.held.contains_key(h))
            .filter_map(live);
        CookEnv {
            held: HeldGeometry::new(self.held.values().cloned().chain(elsewhere)),
            ..env
        }
    }
}

/// Parses a document; a syntax error names the line, column, node and parameter.
pub fn parse(text: &str, origin: &str) -> PyResult<Document> {
    Document::from_json(text).map_err(|e| {
        load_errors(&[LoadError {
            path: e.node.clone().unwrap_or_else(|| "/".into()),
            param: e.param.clone(),
            message: format!(
                "{origin}: line {}, column {}: {}",
                e.line, e.column, e.message
            ),
            position: None,
        }])
    })
}
