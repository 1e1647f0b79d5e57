//! `geode.Network` (native half): a network document edited through geode's own edit functions, validated as it is built, and cooked with the engine's cache.

use std::path::PathBuf;
use std::sync::{Mutex, MutexGuard};

use geode_graph::document::Document;
use geode_graph::edit::{split_path, Edit};
use geode_graph::{CookOptions, LoadError};
use geode_op::Value;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use serde_json::Value as Json;

use crate::cancel::run_interruptibly;
use crate::errors::{cook_errors, edit_error, file_error, invalid, load_errors, not_found, usage};
use crate::geometry::PyGeometry;
use crate::json::{to_json, to_py};
use crate::state::{flag_of, join, network_at, param_value_to_py, parse, registry, State};

/// A network being built or cooked from Python.
#[pyclass(frozen, name = "Network", module = "geode._geode", subclass)]
pub struct PyNetwork {
    state: Mutex<State>,
}

impl PyNetwork {
    fn lock(&self) -> MutexGuard<'_, State> {
        // A panic inside an edit would poison the lock; the document is
        // written only by edits that check before they write.
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    fn from_document(doc: Document, path: Option<PathBuf>) -> PyNetwork {
        PyNetwork {
            state: Mutex::new(State::new(doc, path)),
        }
    }

    fn checked(self, strict: bool) -> PyResult<PyNetwork> {
        if strict {
            let problems = {
                let mut s = self.lock();
                match &*s.engine()? {
                    Ok(e) => e.network().problems().to_vec(),
                    Err(errors) => errors.clone(),
                }
            };
            if !problems.is_empty() {
                return Err(load_errors(&problems));
            }
        }
        Ok(self)
    }

    /// Sets one parameter in the document (a geometry is held and named by
    /// its hash); the caller checks and undoes.
    fn write_param(
        s: &mut State,
        path: &str,
        param: &str,
        value: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let json = if let Ok(g) = value.cast::<PyGeometry>() {
            let geo = g.get().geo.clone();
            let hash = geo.content_hash();
            crate::state::hold(hash, &geo);
            s.held.insert(hash, geo);
            Json::String(geode_nodes::held::format_hash(hash))
        } else {
            to_json(value, path, param)?
        };
        s.edit(&Edit::SetParam {
            path: path.to_owned(),
            param: param.to_owned(),
            value: json,
        })
    }
}

#[pymethods]
impl PyNetwork {
    #[new]
    fn new() -> PyNetwork {
        PyNetwork::from_document(Document::new(), None)
    }

    /// Reads a network file; with `strict`, any load problem raises LoadError.
    #[staticmethod]
    #[pyo3(signature = (path, strict = true))]
    fn load(py: Python<'_>, path: PathBuf, strict: bool) -> PyResult<PyNetwork> {
        let text = py
            .detach(|| std::fs::read_to_string(&path))
            .map_err(|e| file_error(&path, e))?;
        let doc = parse(&text, &path.display().to_string())?;
        PyNetwork::from_document(doc, Some(path)).checked(strict)
    }

    /// A network from the text of a network file.
    #[staticmethod]
    #[pyo3(signature = (text, strict = true))]
    fn from_json(text: &str, strict: bool) -> PyResult<PyNetwork> {
        PyNetwork::from_document(parse(text, "<text>")?, None).checked(strict)
    }

    /// The document as its file writes it (canonical form, as `geode fmt`).
    fn to_json(&self) -> String {
        self.lock().doc.to_json()
    }

    /// Writes the document atomically to `path` (or where it came from).
    #[pyo3(signature = (path = None))]
    fn save(&self, path: Option<PathBuf>) -> PyResult<()> {
        let mut s = self.lock();
        let path = path
            .or_else(|| s.path.clone())
            .ok_or_else(|| invalid("the network has no file yet: save(path)"))?;
        let text = s.doc.to_json();
        geode_io::write_atomic(&path, |w| {
            std::io::Write::write_all(w, text.as_bytes())
                .map_err(|e| geode_io::IoError::os(&path, e))
        })
        .map_err(|e| file_error(&path, e))?;
        s.path = Some(path);
        Ok(())
    }

    /// The file the network was loaded from or last saved to.
    #[getter]
    fn path(&self) -> Option<PathBuf> {
        self.lock().path.clone()
    }

    /// Adds a node of `ty` in `parent` (`/` or a subnet or block's path),
    /// named `name` or after its type, with `params`; returns its path.
    /// A parameter the node cannot take undoes the whole addition.
    #[pyo3(signature = (parent, ty, name = None, params = None))]
    fn _create(
        &self,
        parent: &str,
        ty: &str,
        name: Option<&str>,
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<String> {
        let mut s = self.lock();
        let before: Vec<String> = network_at(&s.doc.network, parent)
            .ok_or_else(|| not_found("node", parent, None, "no such subnet or block"))?
            .nodes
            .keys()
            .cloned()
            .collect();
        if let Some(n) = name {
            if before.iter().any(|b| b == n) {
                return Err(edit_error(
                    &geode_graph::edit::EditError {
                        path: join(parent, n),
                        message: "a node of that name is already there".into(),
                    },
                    None,
                ));
            }
        }
        s.edit(&Edit::AddNode {
            parent: parent.to_owned(),
            ty: ty.to_owned(),
            name: name.map(str::to_owned),
            pos: None,
            after: None,
        })?;
        let made = network_at(&s.doc.network, parent)
            .and_then(|net| net.nodes.keys().find(|k| !before.contains(k)).cloned())
            .ok_or_else(|| invalid("the node was not added"))?;
        let path = join(parent, &made);
        if let Some(params) = params {
            let result = (|| -> PyResult<()> {
                let mut written = Vec::new();
                for (k, v) in params.iter() {
                    let k: String = k.extract()?;
                    PyNetwork::write_param(&mut s, &path, &k, &v)?;
                    written.push(k);
                }
                let problems: Vec<LoadError> = s
                    .problems_of(&path, None)?
                    .into_iter()
                    .filter(|e| e.param.as_ref().is_some_and(|p| written.contains(p)))
                    .collect();
                if problems.is_empty() {
                    Ok(())
                } else {
                    Err(load_errors(&problems))
                }
            })();
            if let Err(e) = result {
                // The node goes again, its wires and values with it (no copy
                // of the document is kept for this: a build stays linear).
                s.edit(&Edit::RemoveNodes {
                    paths: vec![path.clone()],
                })?;
                s.prune_held();
                return Err(e);
            }
        }
        Ok(path)
    }

    /// Sets a parameter; a value the parameter cannot take is refused
    /// (LoadError naming node and parameter) and the old value kept.
    fn _set_param(&self, path: &str, param: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let mut s = self.lock();
        let old = s.node(path)?.params.get(param).cloned();
        PyNetwork::write_param(&mut s, path, param, value)?;
        let problems = s.problems_of(path, Some(param))?;
        if !problems.is_empty() {
            s.edit(&Edit::SetParam {
                path: path.to_owned(),
                param: param.to_owned(),
                value: old.unwrap_or(Json::Null),
            })?;
            s.prune_held();
            return Err(load_errors(&problems));
        }
        s.prune_held();
        Ok(())
    }

    /// The parameter as the document writes it (None for its default).
    fn _raw_param<'py>(
        &self,
        py: Python<'py>,
        path: &str,
        param: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let s = self.lock();
        match s.node(path)?.params.get(param) {
            Some(j) => to_py(py, j),
            None => Ok(py.None().into_bound(py)),
        }
    }

    /// The parameter's value at `frame` as the cook sees it (expressions and keys evaluated).
    fn _eval_param<'py>(
        &self,
        py: Python<'py>,
        path: &str,
        param: &str,
        frame: f64,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (engine, env) = {
            let mut s = self.lock();
            s.node(path)?;
            (s.engine()?, s.env())
        };
        let net = match &*engine {
            Ok(e) => e.network(),
            Err(errors) => return Err(load_errors(errors)),
        };
        let values = net
            .param_values(path, frame, &env)
            .ok_or_else(|| not_found("node", path, None, "no such node"))?;
        let (_, v) = values
            .into_iter()
            .find(|(n, _)| n == param)
            .ok_or_else(|| usage("parameter", path, Some(param), "no such parameter"))?;
        match v {
            Ok(v) => param_value_to_py(py, &v),
            Err(e) => Err(load_errors(&[e])),
        }
    }

    fn _set_key(
        &self,
        path: &str,
        param: &str,
        component: usize,
        frame: f64,
        value: f64,
    ) -> PyResult<()> {
        self.lock().edit(&Edit::SetKey {
            path: path.to_owned(),
            param: param.to_owned(),
            component,
            frame,
            value,
        })
    }

    fn _delete_key(&self, path: &str, param: &str, component: usize, frame: f64) -> PyResult<()> {
        self.lock().edit(&Edit::DeleteKey {
            path: path.to_owned(),
            param: param.to_owned(),
            component,
            frame,
        })
    }

    #[pyo3(signature = (path, name, ty))]
    fn _set_spare(&self, path: &str, name: &str, ty: Option<&str>) -> PyResult<()> {
        self.lock().edit(&Edit::SetSpare {
            path: path.to_owned(),
            name: name.to_owned(),
            ty: ty.map(str::to_owned),
        })
    }

    /// Wires `source` (a sibling's path, or `@N` / `@meta` inside a
    /// subnet or block) into input `input` of `path`; None unwires it.
    #[pyo3(signature = (path, input, source))]
    fn _connect(&self, path: &str, input: usize, source: Option<&str>) -> PyResult<()> {
        let mut s = self.lock();
        match source {
            None => s.edit(&Edit::Disconnect {
                to: path.to_owned(),
                input,
            }),
            Some(src) => {
                let from = if src.starts_with('@') {
                    let parent = split_path(path).map_or("/", |(p, _)| p);
                    join(parent, src)
                } else {
                    src.to_owned()
                };
                s.edit(&Edit::Connect {
                    from,
                    to: path.to_owned(),
                    input,
                })
            }
        }
    }

    fn _remove(&self, path: &str) -> PyResult<()> {
        let mut s = self.lock();
        s.edit(&Edit::RemoveNodes {
            paths: vec![path.to_owned()],
        })?;
        s.prune_held();
        Ok(())
    }

    fn _rename(&self, path: &str, name: &str) -> PyResult<String> {
        self.lock().edit(&Edit::Rename {
            path: path.to_owned(),
            name: name.to_owned(),
        })?;
        let parent = split_path(path).map_or("/", |(p, _)| p);
        Ok(join(parent, name))
    }

    fn _set_flag(&self, path: &str, flag: &str, on: bool) -> PyResult<()> {
        self.lock().edit(&Edit::SetFlag {
            path: path.to_owned(),
            flag: flag_of(flag)?,
            on,
        })
    }

    #[pyo3(signature = (parent, name))]
    fn _set_output(&self, parent: &str, name: Option<&str>) -> PyResult<()> {
        self.lock().edit(&Edit::SetOutput {
            parent: parent.to_owned(),
            node: name.map(str::to_owned),
        })
    }

    /// Another network with this one's document, file (its `$HIP`) and
    /// geometry, to edit apart (one per thread of a wedge).
    fn copy(&self) -> PyNetwork {
        let s = self.lock();
        let mut state = State::new(s.doc.clone(), s.path.clone());
        state.held = s.held.clone();
        state.engine = s.engine.clone();
        PyNetwork {
            state: Mutex::new(state),
        }
    }

    /// The path of the node the network's result comes from: the one
    /// `output` names, else the one with the display flag; None without either.
    fn _effective_output(&self) -> PyResult<Option<String>> {
        let engine = self.lock().engine()?;
        Ok(match &*engine {
            Ok(e) => e.network().output().map(str::to_owned),
            Err(_) => None,
        })
    }

    /// The name of `parent`'s output node, if it names one.
    fn _output(&self, parent: &str) -> PyResult<Option<String>> {
        let s = self.lock();
        let net = network_at(&s.doc.network, parent)
            .ok_or_else(|| not_found("node", parent, None, "no such subnet or block"))?;
        Ok(net.output.clone())
    }

    /// Names of the nodes in `parent`.
    fn _children(&self, parent: &str) -> PyResult<Vec<String>> {
        let s = self.lock();
        let net = network_at(&s.doc.network, parent)
            .ok_or_else(|| not_found("node", parent, None, "no such subnet or block"))?;
        Ok(net.nodes.keys().cloned().collect())
    }

    /// A node's type, inputs, flags, spare parameters and whether it holds a network.
    fn _node_info<'py>(&self, py: Python<'py>, path: &str) -> PyResult<Bound<'py, PyDict>> {
        let s = self.lock();
        let n = s.node(path)?;
        let d = PyDict::new(py);
        d.set_item("type", &n.ty)?;
        d.set_item("inputs", n.inputs.clone())?;
        d.set_item("bypass", n.bypass)?;
        d.set_item("display", n.display)?;
        d.set_item("template", n.template)?;
        d.set_item("spare", n.spare.clone())?;
        d.set_item("has_network", n.network.is_some())?;
        Ok(d)
    }

    /// A parameter's declaration (type, default, range, menu items, help) as
    /// the studio reads it; a promoted one names the inner parameter.
    fn _param_template<'py>(
        &self,
        py: Python<'py>,
        path: &str,
        param: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let s = self.lock();
        let n = s.node(path)?;
        if let Some(inner) = n.promote.get(param) {
            return to_py(py, &serde_json::json!({"name": param, "promoted": inner}));
        }
        let spec = geode_graph::node_spec(registry(), &n.ty)
            .and_then(|spec| spec.param(param))
            .or_else(|| {
                n.spare
                    .get(param)
                    .and_then(|ty| geode_op::ParamSpec::spare(ty))
            })
            .ok_or_else(|| not_found("parameter", path, Some(param), "no such parameter"))?;
        let mut j = geode_graph::catalogue::param_json(spec);
        if n.spare.contains_key(param) {
            j["name"] = Json::String(param.to_owned());
            j["label"] = Json::String(param.to_owned());
            j["spare"] = Json::Bool(true);
        }
        to_py(py, &j)
    }

    /// Every parameter the node takes: its type's, then its spare ones.
    fn _param_names(&self, path: &str) -> PyResult<Vec<String>> {
        let s = self.lock();
        let n = s.node(path)?;
        let mut names: Vec<String> = geode_graph::node_spec(registry(), &n.ty)
            .map(|spec| spec.params.iter().map(|p| p.name.to_owned()).collect())
            .unwrap_or_default();
        names.extend(n.spare.keys().cloned());
        names.extend(n.promote.keys().cloned());
        Ok(names)
    }

    /// Every load problem, as dicts of kind, path, param and message.
    fn problems<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let engine = self.lock().engine()?;
        let problems: Vec<LoadError> = match &*engine {
            Ok(e) => e.network().problems().to_vec(),
            Err(errors) => errors.clone(),
        };
        let out = PyList::empty(py);
        for p in &problems {
            let d = PyDict::new(py);
            d.set_item(
                "kind",
                if p.param.is_some() {
                    "parameter"
                } else {
                    "network"
                },
            )?;
            d.set_item("path", &p.path)?;
            d.set_item("param", p.param.as_deref())?;
            d.set_item("message", &p.message)?;
            out.append(d)?;
        }
        Ok(out)
    }

    /// Cooks `node` (the network's output when None) at `frame`: a
    /// Geometry, or for a bundle a dict of them. The GIL is released while
    /// it cooks and Ctrl-C cancels it (KeyboardInterrupt).
    #[pyo3(signature = (node = None, frame = 1.0))]
    fn cook<'py>(
        &self,
        py: Python<'py>,
        node: Option<&str>,
        frame: f64,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (engine, env, target) = {
            let mut s = self.lock();
            let engine = s.engine()?;
            let target = match node {
                Some(n) if n.starts_with('/') => n.to_owned(),
                Some(n) => format!("/{n}"),
                None => match &*engine {
                    Ok(e) => e.network().output().map(str::to_owned).ok_or_else(|| {
                        usage(
                            "network",
                            "/",
                            None,
                            "the network names no output node: cook(node=...) or set net.output",
                        )
                    })?,
                    Err(errors) => return Err(load_errors(errors)),
                },
            };
            (engine, s.env(), target)
        };
        let outcome = run_interruptibly(py, move |cancel| {
            let engine = match &*engine {
                Ok(e) => e,
                Err(errors) => return Outcome::Load(errors.clone()),
            };
            if engine.network().node_type(&target).is_none() {
                let known: Vec<&str> = engine.network().paths().collect();
                return Outcome::NoNode(target, known.join(", "));
            }
            let opts = CookOptions {
                frame,
                cancel,
                progress: None,
                env,
                writes: true,
            };
            match engine.cook(&target, &opts) {
                Ok(r) => Outcome::Value(r.value),
                Err(errors) => Outcome::Cook(errors),
            }
        })?;
        match outcome {
            Outcome::Value(v) => value_to_py(py, v),
            Outcome::Load(errors) => Err(load_errors(&errors)),
            Outcome::Cook(errors) => Err(cook_errors(&errors)),
            Outcome::NoNode(target, known) => Err(not_found(
                "node",
                &target,
                None,
                format!("no such node (nodes: {known})"),
            )),
        }
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        let Ok(o) = other.cast::<PyNetwork>() else {
            return false;
        };
        let o = o.get();
        if std::ptr::eq(self, o) {
            return true;
        }
        self.lock().doc == o.lock().doc
    }
}

/// What a cook thread hands back.
enum Outcome {
    Value(Value),
    Load(Vec<LoadError>),
    Cook(Vec<geode_op::CookError>),
    NoNode(String, String),
}

fn value_to_py(py: Python<'_>, v: Value) -> PyResult<Bound<'_, PyAny>> {
    match v {
        Value::Geometry(g) => Ok(Bound::new(py, PyGeometry::new(g))?.into_any()),
        Value::Bundle(b) => {
            let d = PyDict::new(py);
            for (name, g) in b.entries.iter() {
                d.set_item(name, Bound::new(py, PyGeometry::new(g.clone()))?)?;
            }
            Ok(d.into_any())
        }
        Value::Field(_) => Err(usage(
            "network",
            "",
            None,
            "the node gives a field: mesh it with a polygonise node to read it as geometry",
        )),
    }
}
