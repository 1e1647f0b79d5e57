//! Turns a document into a checked, flattened network, reporting every problem at once.

use std::collections::{BTreeMap, HashMap};
use std::sync::Arc;

use geode_op::{
    CookEnv, ListSpec, Operator, ParamSpec, ParamType, ParamValue, Params, PortType, Registry,
    TextPosition, SPARE_TYPES,
};
use serde_json::Value as Json;

use crate::channel::{Channel, Key};
use crate::document::{Document, NetworkDoc, NodeDoc, VERSION};
use crate::expr::{EvalCx, ExprComponent, Piece};

/// A problem found while loading a network.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{path}: {}{message}", param.as_ref().map(|p| format!("parameter `{p}`: ")).unwrap_or_default())]
pub struct LoadError {
    /// The node path (`/` for the document itself).
    pub path: String,
    pub param: Option<String>,
    pub message: String,
    /// Where in the parameter's text (an expression) the problem is.
    pub position: Option<TextPosition>,
}

impl LoadError {
    pub(crate) fn node(path: &str, message: impl Into<String>) -> LoadError {
        LoadError {
            path: path.to_owned(),
            param: None,
            message: message.into(),
            position: None,
        }
    }

    pub(crate) fn param(path: &str, param: &str, message: impl Into<String>) -> LoadError {
        LoadError {
            path: path.to_owned(),
            param: Some(param.to_owned()),
            message: message.into(),
            position: None,
        }
    }

    /// At a position of the parameter's text.
    pub(crate) fn at(mut self, position: Option<TextPosition>) -> LoadError {
        self.position = position;
        self
    }
}

/// One numeric component of a parameter: fixed, keyframed or an expression.
#[derive(Clone, Debug)]
pub(crate) enum Component {
    Const(f64),
    Channel(Channel),
    Expr(ExprComponent),
}

#[derive(Clone, Debug)]
pub(crate) enum ParamSource {
    Text(String),
    /// A string with variables or backtick expressions.
    Template(Vec<Piece>),
    Components(Vec<Component>),
    /// A list parameter's rows, each field compiled like a parameter.
    List(Vec<Vec<CompiledParam>>),
}

#[derive(Clone, Debug)]
pub(crate) struct CompiledParam {
    pub spec: &'static ParamSpec,
    pub source: ParamSource,
}

impl CompiledParam {
    /// The value at `cx`'s frame; `name` is how errors call the parameter.
    pub(crate) fn eval_named(&self, cx: &EvalCx, name: &str) -> Result<ParamValue, LoadError> {
        let path = &cx.net.nodes[cx.node].path;
        let fail = |e: geode_op::ExprError| LoadError::param(path, name, e.message).at(e.position);
        match &self.source {
            ParamSource::Text(s) => Ok(ParamValue::String(s.clone())),
            ParamSource::Template(pieces) => {
                cx.template(pieces).map(ParamValue::String).map_err(fail)
            }
            ParamSource::List(rows) => {
                let rows: Vec<Vec<ParamValue>> = rows
                    .iter()
                    .enumerate()
                    .map(|(k, r)| {
                        r.iter()
                            .map(|f| f.eval_named(cx, &format!("{name}[{k}].{}", f.spec.name)))
                            .collect()
                    })
                    .collect::<Result<_, _>>()?;
                match self.spec.ty {
                    // A ramp's rows are its keys: sorted, checked and built here.
                    ParamType::Ramp(kind) => geode_op::ramp_from_rows(kind, &rows)
                        .map(ParamValue::Ramp)
                        .map_err(|m| LoadError::param(path, name, m)),
                    _ => Ok(ParamValue::List(rows)),
                }
            }
            ParamSource::Components(c) => {
                let v = (0..c.len())
                    .map(|k| self.component_at(cx, name, k))
                    .collect::<Result<Vec<f64>, LoadError>>()?;
                Ok(self.spec.from_components(&v))
            }
        }
    }

    /// Component `k` of a numeric parameter at `cx`'s frame (None-like 0
    /// for text and lists, which have no components).
    pub(crate) fn component_at(&self, cx: &EvalCx, name: &str, k: usize) -> Result<f64, LoadError> {
        let path = &cx.net.nodes[cx.node].path;
        let ParamSource::Components(c) = &self.source else {
            return Err(LoadError::param(path, name, "not a numeric parameter"));
        };
        match c.get(k) {
            None => Err(LoadError::param(
                path,
                name,
                format!("has no component {k}"),
            )),
            Some(Component::Const(x)) => Ok(*x),
            Some(Component::Channel(ch)) => Ok(ch.eval(cx.frame)),
            Some(Component::Expr(e)) => {
                let value = cx
                    .expression(e)
                    .map_err(|e| LoadError::param(path, name, e.message).at(e.position))?;
                self.checked(&value, cx.frame)
                    .map_err(|m| LoadError::param(path, name, m))
            }
        }
    }

    /// The value at `cx`'s frame, errors naming the declared parameter.
    pub(crate) fn eval(&self, cx: &EvalCx) -> Result<ParamValue, LoadError> {
        self.eval_named(cx, self.spec.name)
    }

    /// An expression's value as one component, within the declared range.
    fn checked(&self, value: &geode_op::ExprValue, frame: f64) -> Result<f64, String> {
        let x = match value {
            geode_op::ExprValue::Num(v) if v.len() == 1 => v[0],
            geode_op::ExprValue::Num(v) => {
                return Err(format!(
                    "the expression gives {} numbers at frame {frame}; a component takes one (write one expression per component, or .x)",
                    v.len()
                ))
            }
            geode_op::ExprValue::Str(s) => {
                return Err(format!(
                    "the expression gives the text {s:?} at frame {frame}; this parameter takes a number"
                ))
            }
        };
        if !x.is_finite() {
            return Err(format!("the expression gives {x} at frame {frame}"));
        }
        // Expressions compute in VEX's 32-bit floats: shown as such.
        let shown = x as f32;
        if let Some(min) = self.spec.min.filter(|m| x < *m) {
            return Err(format!(
                "the expression gives {shown} at frame {frame}, below the minimum {min}"
            ));
        }
        if let Some(max) = self.spec.max.filter(|m| x > *m) {
            return Err(format!(
                "the expression gives {shown} at frame {frame}, above the maximum {max}"
            ));
        }
        Ok(x)
    }
}

#[derive(Clone)]
pub(crate) enum NodeKind {
    Op {
        op: Arc<dyn Operator>,
        params: Vec<CompiledParam>,
        /// Spare parameters the network declared, by name.
        spare: Vec<(String, CompiledParam)>,
    },
    /// A subnetwork: its value is its output node's; a loop or solver
    /// (`block`) cooks it repeatedly.
    Subnet {
        output: Option<usize>,
        block: Option<crate::block::Block>,
        /// Spare parameters declared on the subnet: inner nodes that take
        /// spare parameters read them as `../name`.
        spare: Vec<(String, CompiledParam)>,
    },
    /// Inside a loop or solver: what `@N` or `@meta` gives on each pass.
    Feed {
        block: usize,
        slot: crate::block::FeedSlot,
    },
    /// A node of an unknown type (only while loading: load then fails).
    Invalid,
}

#[derive(Clone)]
pub(crate) struct Node {
    pub path: String,
    pub kind: NodeKind,
    pub inputs: Vec<Option<usize>>,
    pub bypass: bool,
    /// For nodes inside a subnetwork: the subnet's index.
    pub parent: Option<usize>,
    /// What the loader found wrong with this node: cooking it (or anything
    /// that reads it) fails with these, and nothing else is held back.
    pub problems: Vec<LoadError>,
}

/// A promoted parameter: the subnet parameter and the inner node it drives
/// (the tag solo view's auto mode follows).
#[derive(Clone, Debug, PartialEq)]
pub struct Promotion {
    pub subnet: String,
    pub name: String,
    pub target: String,
    pub target_param: String,
}

/// A checked network: nodes flattened by path (subnet contents included),
/// inputs resolved, parameters parsed, no cycles.
#[derive(Clone)]
pub struct Network {
    pub(crate) nodes: Vec<Node>,
    by_path: HashMap<String, usize>,
    output: Option<usize>,
    promotions: Vec<Promotion>,
    notes: Vec<LoadError>,
    /// Every problem found, sorted by path (each node's also on the node).
    problems: Vec<LoadError>,
    /// The document's frame rate (`fps`), if it sets one.
    fps: Option<f64>,
}

impl Network {
    /// What loading changed without failing (old text forms converted to
    /// list parameters), to show the user.
    pub fn notes(&self) -> &[LoadError] {
        &self.notes
    }

    pub(crate) fn index(&self, path: &str) -> Option<usize> {
        self.by_path.get(path).copied()
    }

    /// Every node path, in document order (parents before their contents).
    pub fn paths(&self) -> impl Iterator<Item = &str> {
        self.nodes.iter().map(|n| n.path.as_str())
    }

    /// The path of the network's output node, if it names one.
    pub fn output(&self) -> Option<&str> {
        self.output.map(|i| self.nodes[i].path.as_str())
    }

    pub fn promotions(&self) -> &[Promotion] {
        &self.promotions
    }

    /// The type name of a node (`subnet` for subnetworks).
    pub fn node_type(&self, path: &str) -> Option<&str> {
        self.index(path).map(|i| match &self.nodes[i].kind {
            NodeKind::Op { op, .. } => op.spec().name,
            NodeKind::Subnet { block: Some(b), .. } => b.kind.name(),
            NodeKind::Subnet { .. } => crate::container::SUBNET.name,
            NodeKind::Feed { .. } => "feed",
            NodeKind::Invalid => "invalid",
        })
    }

    /// A node's parameters evaluated at `frame`: expressions evaluated and
    /// strings expanded (`$HIP`, `$F`...), so that what a cook reads of its
    /// environment and of other nodes is in its parameters, and so in its key.
    pub(crate) fn params_at(
        &self,
        i: usize,
        frame: f64,
        env: &CookEnv,
    ) -> Result<Params, LoadError> {
        let cx = EvalCx {
            net: self,
            node: i,
            frame,
            env,
            depth: 0,
        };
        let path = &self.nodes[i].path;
        Ok(match &self.nodes[i].kind {
            NodeKind::Op { params, spare, .. } => Params::declared(
                path,
                params
                    .iter()
                    .map(|p| Ok((p.spec, p.eval(&cx)?)))
                    .collect::<Result<_, LoadError>>()?,
            )
            .with_spare(self.spares_at(i, spare, &cx)?),
            NodeKind::Subnet { block: Some(b), .. } => Params::declared(
                path,
                b.params
                    .iter()
                    .map(|p| Ok((p.spec, p.eval(&cx)?)))
                    .collect::<Result<_, LoadError>>()?,
            ),
            NodeKind::Subnet { .. } | NodeKind::Feed { .. } | NodeKind::Invalid => {
                Params::new(path, Vec::new())
            }
        })
    }

    /// A node's spare parameters at `frame`, then (for node types that take
    /// them) each enclosing subnet's as `../name`, `../../name`...
    fn spares_at(
        &self,
        i: usize,
        own: &[(String, CompiledParam)],
        cx: &EvalCx,
    ) -> Result<Vec<(String, ParamValue)>, LoadError> {
        let mut out: Vec<(String, ParamValue)> = own
            .iter()
            .map(|(n, p)| Ok((n.clone(), p.eval_named(cx, n)?)))
            .collect::<Result<_, LoadError>>()?;
        let takes = matches!(&self.nodes[i].kind, NodeKind::Op { op, .. } if op.spec().spare);
        let mut up = String::new();
        let mut at = self.nodes[i].parent;
        while let (true, Some(p)) = (takes, at) {
            up.push_str("../");
            if let NodeKind::Subnet { spare, .. } = &self.nodes[p].kind {
                let outer = EvalCx { node: p, ..*cx };
                for (n, c) in spare {
                    out.push((format!("{up}{n}"), c.eval_named(&outer, n)?));
                }
            }
            at = self.nodes[p].parent;
        }
        Ok(out)
    }

    /// The node a parameter is tagged with: the inner node a promoted subnet
    /// parameter drives, or the one its declaration's tag names (solo view's
    /// auto mode); None for an untagged parameter.
    pub fn tagged_target(&self, node: &str, param: &str) -> Option<String> {
        self.promotions
            .iter()
            .find(|p| p.subnet == node && p.name == param)
            .map(|p| p.target.clone())
            .or_else(|| self.param_affects(node, param))
    }

    /// The inner node a parameter's tag names (`ParamSpec::affects`), as a path.
    pub fn param_affects(&self, node: &str, param: &str) -> Option<String> {
        let NodeKind::Op { op, .. } = &self.nodes[self.index(node)?].kind else {
            return None;
        };
        let inner = op.spec().param(param)?.affects?;
        let path = format!("{node}/{inner}");
        self.index(&path).map(|_| path)
    }

    /// Whether any parameter of node `path` is animated (keys, or an
    /// expression that reads the time or an animated parameter).
    pub fn is_animated(&self, path: &str) -> bool {
        self.index(path).is_some_and(|i| {
            self.params_of(i)
                .iter()
                .any(|(_, p)| self.param_animated(i, p, 0))
        })
    }

    /// The network's frame rate, where its document sets one.
    pub fn fps(&self) -> Option<f64> {
        self.fps
    }

    /// A node's parameters as evaluated at `frame` (expressions and
    /// expanded strings as the cook would see them), by name; spare
    /// parameters included. For showing values beside their expressions.
    pub fn param_values(
        &self,
        path: &str,
        frame: f64,
        env: &CookEnv,
    ) -> Option<Vec<(String, Result<ParamValue, LoadError>)>> {
        let node = self.index(path)?;
        let env = env.clone().with_fps(self.fps.unwrap_or(env.fps));
        let cx = EvalCx {
            net: self,
            node,
            frame,
            env: &env,
            depth: 0,
        };
        Some(
            self.params_of(node)
                .into_iter()
                .map(|(name, p)| (name.to_owned(), p.eval_named(&cx, name)))
                .collect(),
        )
    }

    /// Every problem the loader found, sorted by node path (document-level
    /// first). A node with problems fails when cooked, and so does anything
    /// downstream of it; the rest of the network cooks.
    pub fn problems(&self) -> &[LoadError] {
        &self.problems
    }

    /// The problems of node `path` itself (not of what it reads).
    pub fn node_problems(&self, path: &str) -> &[LoadError] {
        self.index(path).map_or(&[], |i| &self.nodes[i].problems)
    }

    /// What cooking at `frame` would refuse, found without cooking (`geode
    /// check`): every node's parameters are evaluated (expressions
    /// included), then each operator checks its own ([`Operator::check`]:
    /// a wrangle compiles its snippet). Bypassed nodes and nodes with load
    /// problems (reported by the loader) are skipped; sorted by path.
    pub fn check(&self, frame: f64, env: &CookEnv) -> Vec<LoadError> {
        let env = env.clone().with_fps(self.fps.unwrap_or(env.fps));
        let mut found = Vec::new();
        for (i, node) in self.nodes.iter().enumerate() {
            if !node.problems.is_empty() {
                continue;
            }
            if let NodeKind::Feed { .. } | NodeKind::Invalid = node.kind {
                continue;
            }
            let params = match self.params_at(i, frame, &env) {
                Ok(p) => p,
                Err(e) => {
                    found.push(e);
                    continue;
                }
            };
            let NodeKind::Op { op, .. } = &node.kind else {
                continue;
            };
            if node.bypass {
                continue;
            }
            let wired: Vec<bool> = node.inputs.iter().map(Option::is_some).collect();
            let ctx = geode_op::CheckContext {
                path: &node.path,
                frame,
                env: &env,
                wired: &wired,
            };
            if let Err(e) = op.check(&ctx, &params) {
                found.push(LoadError {
                    path: e.path,
                    param: e.param,
                    message: e.message,
                    position: e.position,
                });
            }
        }
        found.sort_by(|a, b| a.path.cmp(&b.path));
        found
    }

    /// Loads and checks a document against the registry's node types,
    /// failing on any problem (`geode check`).
    pub fn load(doc: &Document, registry: &Registry) -> Result<Network, Vec<LoadError>> {
        let net = Network::load_partial(doc, registry)?;
        if net.problems.is_empty() {
            Ok(net)
        } else {
            Err(net.problems)
        }
    }

    /// Loads a document keeping its problems local: each node's problems are
    /// attached to it ([`Network::node_problems`]) and listed in
    /// [`Network::problems`], and only what reads a broken node fails to
    /// cook (as Houdini and Blender fail only the broken branch). Fails only
    /// when the document is not a network this geode can read.
    pub fn load_partial(doc: &Document, registry: &Registry) -> Result<Network, Vec<LoadError>> {
        let mut b = Builder {
            registry,
            nodes: Vec::new(),
            docs: Vec::new(),
            by_path: HashMap::new(),
            errors: Vec::new(),
            notes: Vec::new(),
            promotions: Vec::new(),
        };
        let mut fatal = Vec::new();
        if doc.geode != "network" {
            fatal.push(LoadError::node(
                "/",
                format!(
                    "not a geode network (\"geode\" is \"{}\", expected \"network\")",
                    doc.geode
                ),
            ));
        }
        if doc.version > VERSION {
            fatal.push(LoadError::node(
                "/",
                format!(
                    "network version {} is newer than this geode understands ({VERSION})",
                    doc.version
                ),
            ));
        }
        if !fatal.is_empty() {
            return Err(fatal);
        }
        b.collect(&doc.network, "", None);
        b.resolve_inputs();
        b.compile_params();
        b.check_wires();
        let output = b.network_output(&doc.network, "", None);
        let mut net = Network {
            nodes: b.nodes,
            by_path: b.by_path,
            output,
            promotions: b.promotions,
            notes: b.notes,
            problems: Vec::new(),
            fps: doc
                .extra
                .get("fps")
                .and_then(Json::as_f64)
                .filter(|f| f.is_finite() && *f > 0.0),
        };
        let mut errors = b.errors;
        errors.extend(crate::expr::check_references(&net));
        let (cycle_errors, on_cycles) = find_cycles(&net);
        for (i, e) in on_cycles {
            net.nodes[i].problems.push(e);
        }
        errors.extend(cycle_errors);
        // Grouped by node (document-level first), each node's in check order.
        errors.sort_by(|a, b| a.path.cmp(&b.path));
        for e in &errors {
            if let Some(i) = net.index(&e.path) {
                if !net.nodes[i].problems.contains(e) {
                    net.nodes[i].problems.push(e.clone());
                }
            }
        }
        net.problems = errors;
        Ok(net)
    }
}

struct Builder<'a> {
    registry: &'a Registry,
    nodes: Vec<Node>,
    docs: Vec<NodeDoc>,
    by_path: HashMap<String, usize>,
    errors: Vec<LoadError>,
    notes: Vec<LoadError>,
    promotions: Vec<Promotion>,
}

fn describe(j: &Json) -> String {
    match j {
        Json::Null => "null".into(),
        Json::Bool(b) => format!("boolean {b}"),
        Json::Number(n) => format!("number {n}"),
        Json::String(s) => format!("string {s:?}"),
        Json::Array(a) => format!("an array of {}", a.len()),
        Json::Object(_) => "an object".into(),
    }
}

impl Builder<'_> {
    fn collect(&mut self, net: &NetworkDoc, prefix: &str, parent: Option<usize>) {
        for (name, doc) in &net.nodes {
            let path = format!("{prefix}/{name}");
            if name.is_empty() || name.contains('/') || name.starts_with('@') {
                self.errors.push(LoadError::node(
                    &path,
                    "a node name must be non-empty and contain neither `/` nor a leading `@`",
                ));
                continue;
            }
            let block = crate::block::BlockKind::from_type(&doc.ty);
            let kind = if crate::container_spec(&doc.ty).is_some() {
                if doc.network.is_none() && crate::container::holds_network(&doc.ty) {
                    self.errors.push(LoadError::node(
                        &path,
                        format!("a {} needs a \"network\"", doc.ty),
                    ));
                }
                NodeKind::Subnet {
                    output: None,
                    block: block.map(crate::block::Block::new),
                    spare: Vec::new(),
                }
            } else {
                match self.registry.get(&doc.ty) {
                    Some(op) => NodeKind::Op {
                        op: Arc::clone(op),
                        params: Vec::new(),
                        spare: Vec::new(),
                    },
                    None => {
                        let near = crate::container::closest_types(self.registry, &doc.ty);
                        let hint = if near.is_empty() {
                            String::new()
                        } else {
                            format!(" (did you mean {}?)", near.join(", "))
                        };
                        self.errors.push(LoadError::node(
                            &path,
                            format!("unknown node type `{}`{hint}", doc.ty),
                        ));
                        // Kept as a placeholder so references to it do not add errors.
                        NodeKind::Invalid
                    }
                }
            };
            if !crate::container::holds_network(&doc.ty)
                && (doc.network.is_some() || !doc.promote.is_empty())
            {
                self.errors.push(LoadError::node(
                    &path,
                    "only subnets have a \"network\" or \"promote\"",
                ));
            }
            let idx = self.nodes.len();
            self.by_path.insert(path.clone(), idx);
            self.nodes.push(Node {
                path: path.clone(),
                kind,
                inputs: Vec::new(),
                bypass: doc.bypass,
                parent,
                problems: Vec::new(),
            });
            self.docs.push(doc.clone());
            if let Some(inner) = &doc.network {
                self.collect(inner, &path, Some(idx));
                let out = self.network_output(inner, &path, Some(idx));
                if let NodeKind::Subnet { output, .. } = &mut self.nodes[idx].kind {
                    *output = out;
                }
            }
        }
    }

    /// The output node of a (sub)network: `output`, else the display flag.
    fn network_output(
        &mut self,
        net: &NetworkDoc,
        prefix: &str,
        subnet: Option<usize>,
    ) -> Option<usize> {
        let name = net.output.clone().or_else(|| {
            net.nodes
                .iter()
                .find(|(_, d)| d.display)
                .map(|(n, _)| n.clone())
        })?;
        let path = format!("{prefix}/{name}");
        match self.by_path.get(&path) {
            Some(&i) => Some(i),
            None => {
                let at = subnet.map_or("/".to_owned(), |s| self.nodes[s].path.clone());
                if !self.errors.iter().any(|e| e.path == path) {
                    self.errors.push(LoadError::node(
                        &at,
                        format!("output `{name}` is not a node of this network"),
                    ));
                }
                None
            }
        }
    }

    /// Whether node `i` sits directly inside a loop or solver.
    fn in_block(&self, i: usize) -> bool {
        self.nodes[i]
            .parent
            .is_some_and(|p| matches!(self.nodes[p].kind, NodeKind::Subnet { block: Some(_), .. }))
    }

    /// The feed node a reference `@N` or `@meta` inside a block resolves to
    /// (made on first use, one per block and slot).
    fn feed(&mut self, i: usize, k: usize, s: &str) -> Option<usize> {
        use crate::block::FeedSlot;
        let block = self.nodes[i].parent.expect("inside a block");
        let path = self.nodes[i].path.clone();
        let slot = match &s[1..] {
            "meta" => FeedSlot::Meta,
            n => match n.parse::<usize>() {
                Ok(n) if n < self.nodes[block].inputs.len() => FeedSlot::Input(n),
                Ok(_) => {
                    self.errors.push(LoadError::node(
                        &path,
                        format!(
                            "input {} refers to `{s}` but the {} has {} inputs",
                            k + 1,
                            self.docs[block].ty,
                            self.nodes[block].inputs.len()
                        ),
                    ));
                    return None;
                }
                Err(_) => {
                    self.errors.push(LoadError::node(
                        &path,
                        format!(
                            "input {} refers to `{s}`, expected `@` and a number, or `@meta`",
                            k + 1
                        ),
                    ));
                    return None;
                }
            },
        };
        let feed_path = format!("{}/{s}", self.nodes[block].path);
        if let Some(&j) = self.by_path.get(&feed_path) {
            return Some(j);
        }
        let j = self.nodes.len();
        self.by_path.insert(feed_path.clone(), j);
        self.nodes.push(Node {
            path: feed_path,
            kind: NodeKind::Feed { block, slot },
            inputs: Vec::new(),
            bypass: false,
            parent: Some(block),
            problems: Vec::new(),
        });
        let mut doc = self.docs[block].clone();
        doc.ty = "feed".into();
        doc.params.clear();
        doc.inputs.clear();
        doc.network = None;
        self.docs.push(doc);
        Some(j)
    }

    fn resolve_inputs(&mut self) {
        let count = self.nodes.len();
        for i in 0..count {
            let path = self.nodes[i].path.clone();
            let prefix = &path[..path.rfind('/').unwrap_or(0)];
            let mut inputs = Vec::new();
            let given = self.docs[i].inputs.clone();
            for (k, inp) in given.iter().enumerate() {
                let resolved = match inp {
                    None => None,
                    Some(s) if s.starts_with('@') && self.in_block(i) => self.feed(i, k, s),
                    Some(s) if s.starts_with('@') => {
                        let parent = self.nodes[i].parent;
                        match (parent, s[1..].parse::<usize>()) {
                            (Some(p), Ok(n)) => {
                                match self.nodes[p].inputs.get(n) {
                                    Some(src) => *src,
                                    None => {
                                        self.errors.push(LoadError::node(&path, format!("input {} refers to `{s}` but the subnet has {} inputs", k + 1, self.nodes[p].inputs.len())));
                                        None
                                    }
                                }
                            }
                            (None, _) => {
                                self.errors.push(LoadError::node(
                                    &path,
                                    format!("input {} refers to `{s}` outside a subnet", k + 1),
                                ));
                                None
                            }
                            (_, Err(_)) => {
                                self.errors.push(LoadError::node(
                                    &path,
                                    format!(
                                        "input {} refers to `{s}`, expected `@` and a number",
                                        k + 1
                                    ),
                                ));
                                None
                            }
                        }
                    }
                    Some(s) => {
                        match self.by_path.get(&format!("{prefix}/{s}")) {
                            Some(&j) => Some(j),
                            None => {
                                self.errors.push(LoadError::node(&path, format!("input {} refers to `{s}`, which is not a node of this network", k + 1)));
                                None
                            }
                        }
                    }
                };
                inputs.push(resolved);
            }
            if let NodeKind::Op { op, .. } = &self.nodes[i].kind {
                let spec = op.spec();
                let elsewhere = !spec.references_unless.is_empty()
                    && matches!(self.docs[i].params.get(spec.references_unless), Some(Json::String(s)) if !s.is_empty());
                if !spec.references.is_empty() && !elsewhere {
                    inputs.resize(inputs.len().max(spec.inputs.len()), None);
                    let refs = self.references(i, spec.references);
                    inputs.extend(refs.into_iter().map(Some));
                }
            }
            self.nodes[i].inputs = inputs;
        }
    }

    /// The nodes node `i`'s parameter `param` names: paths separated by
    /// spaces, absolute (`/a/b`) or from the node's own network (`b`,
    /// `sub/b`, `../b`). The value must be plain text: what a node reads
    /// is fixed when the network loads.
    fn references(&mut self, i: usize, param: &str) -> Vec<usize> {
        let path = self.nodes[i].path.clone();
        let text = match self.docs[i].params.get(param) {
            None => return Vec::new(),
            Some(Json::String(t)) => t.clone(),
            Some(other) => {
                self.errors.push(LoadError::param(&path, param, format!("expected node paths as plain text (read when the network loads), found {other}")));
                return Vec::new();
            }
        };
        let mut out = Vec::new();
        for name in text.split_whitespace() {
            let mut at: Vec<&str> = if name.starts_with('/') {
                Vec::new()
            } else {
                path.split('/').filter(|s| !s.is_empty()).collect()
            };
            if !name.starts_with('/') {
                at.pop(); // the node itself: names are from its network
            }
            let mut ok = true;
            for part in name.split('/').filter(|s| !s.is_empty() && *s != ".") {
                if part == ".." {
                    ok &= at.pop().is_some();
                } else {
                    at.push(part);
                }
            }
            let full = format!("/{}", at.join("/"));
            if !ok {
                self.errors.push(LoadError::param(
                    &path,
                    param,
                    format!("`{name}` goes above the network's top level"),
                ));
                continue;
            }
            match self.by_path.get(&full) {
                Some(&j) if ok && j != i => out.push(j),
                Some(_) if ok => self.errors.push(LoadError::param(
                    &path,
                    param,
                    format!("`{name}` is this node itself"),
                )),
                _ => self.errors.push(LoadError::param(
                    &path,
                    param,
                    if name.contains(['*', '?', '[']) {
                        format!("`{name}`: nodes are named by exact paths, not patterns")
                    } else {
                        format!("`{name}` ({full}) is not a node of this network")
                    },
                )),
            }
        }
        out
    }

    fn parse_param(
        &mut self,
        path: &str,
        spec: &'static ParamSpec,
        j: &Json,
    ) -> Option<ParamSource> {
        self.parse_named(path, spec.name, spec, j)
    }

    /// The rows of a list parameter: an array of objects keyed by field
    /// (missing fields take their defaults), or, where the parameter had
    /// one, its old text form, converted with a note.
    fn parse_list(
        &mut self,
        path: &str,
        name: &str,
        rows: &'static ListSpec,
        j: &Json,
    ) -> Option<ParamSource> {
        let err = |m: String| LoadError::param(path, name, m);
        let noun = if std::ptr::eq(rows, &geode_op::FLOAT_RAMP_ROWS)
            || std::ptr::eq(rows, &geode_op::COLOR_RAMP_ROWS)
        {
            "a ramp's keys"
        } else {
            "a list of rows"
        };
        let items = match j {
            Json::Array(items) => items,
            Json::String(text) => {
                let Some(legacy) = rows.legacy else {
                    self.errors.push(err(format!(
                        "expected {noun} (an array of objects with fields {}), found {}",
                        field_names(rows),
                        describe(j)
                    )));
                    return None;
                };
                return match legacy(text) {
                    Ok(values) => {
                        self.notes.push(err(format!(
                            "read from the old text form as {} row{}; write it as a list of objects with fields {}",
                            values.len(),
                            if values.len() == 1 { "" } else { "s" },
                            field_names(rows)
                        )));
                        Some(ParamSource::List(
                            values
                                .into_iter()
                                .map(|row| {
                                    rows.fields
                                        .iter()
                                        .zip(row)
                                        .map(|(f, v)| CompiledParam {
                                            spec: f,
                                            source: constant_source(v),
                                        })
                                        .collect()
                                })
                                .collect(),
                        ))
                    }
                    Err(why) => {
                        self.errors.push(err(why));
                        None
                    }
                };
            }
            other => {
                self.errors.push(err(format!(
                    "expected {noun} (an array of objects with fields {}), found {}",
                    field_names(rows),
                    describe(other)
                )));
                return None;
            }
        };
        let mut out = Vec::with_capacity(items.len());
        let mut ok = true;
        for (k, item) in items.iter().enumerate() {
            let row_name = format!("{name}[{k}]");
            let Json::Object(obj) = item else {
                self.errors.push(LoadError::param(
                    path,
                    &row_name,
                    format!(
                        "expected an object with fields {}, found {}",
                        field_names(rows),
                        describe(item)
                    ),
                ));
                ok = false;
                continue;
            };
            for key in obj.keys() {
                if rows.field(key).is_none() {
                    let hint = closest(key, rows.fields.iter().map(|f| f.name));
                    self.errors.push(LoadError::param(
                        path,
                        &row_name,
                        format!(
                            "unknown field `{key}`{hint} (fields: {})",
                            field_names(rows)
                        ),
                    ));
                    ok = false;
                }
            }
            let mut row = Vec::with_capacity(rows.fields.len());
            for f in rows.fields {
                let source = match obj.get(f.name) {
                    Some(j) => {
                        match self.parse_named(path, &format!("{row_name}.{}", f.name), f, j) {
                            Some(s) => s,
                            None => {
                                ok = false;
                                continue;
                            }
                        }
                    }
                    None => default_source(f),
                };
                row.push(CompiledParam { spec: f, source });
            }
            out.push(row);
        }
        ok.then_some(ParamSource::List(out))
    }

    fn parse_named(
        &mut self,
        path: &str,
        name: &str,
        spec: &'static ParamSpec,
        j: &Json,
    ) -> Option<ParamSource> {
        let err = |m: String| LoadError::param(path, name, m);
        if let ParamType::List(rows) = spec.ty {
            return self.parse_list(path, name, rows, j);
        }
        if let Some(rows) = spec.ty.ramp_rows() {
            // A ramp is written as list rows, one per key.
            return self.parse_list(path, name, rows, j);
        }
        if spec.ty.is_textual() {
            let Json::String(s) = j else {
                self.errors.push(err(format!(
                    "expected a {} (a string), found {}",
                    spec.ty,
                    describe(j)
                )));
                return None;
            };
            if let ParamType::Menu(items) = spec.ty {
                if !items.contains(&s.as_str()) {
                    self.errors
                        .push(err(format!("`{s}` is not one of {}", items.join(", "))));
                    return None;
                }
            }
            if !crate::expr::expands(spec) {
                return Some(ParamSource::Text(s.clone()));
            }
            return match crate::expr::parse_template(s, self.registry.expressions()) {
                Ok(pieces) => Some(text_source(pieces)),
                Err(e) => {
                    self.errors.push(err(e.message).at(e.position));
                    None
                }
            };
        }
        let n = spec.ty.components();
        let parts: Vec<&Json> = match (n, j) {
            (1, Json::Array(_)) | (2.., Json::Number(_)) => {
                self.errors.push(err(format!(
                    "expected {}, found {}",
                    expectation(spec.ty),
                    describe(j)
                )));
                return None;
            }
            (1, j) => vec![j],
            (_, Json::Array(a)) if a.len() == n => a.iter().collect(),
            _ => {
                self.errors.push(err(format!(
                    "expected {}, found {}",
                    expectation(spec.ty),
                    describe(j)
                )));
                return None;
            }
        };
        let mut comps = Vec::new();
        for p in parts {
            let c = match p {
                Json::Number(x) => Component::Const(x.as_f64().unwrap_or(f64::NAN)),
                Json::Bool(b) if spec.ty == ParamType::Toggle => {
                    Component::Const(if *b { 1.0 } else { 0.0 })
                }
                Json::Object(o) if o.contains_key("keys") => {
                    if !spec.animatable {
                        self.errors
                            .push(err("this parameter cannot be animated".into()));
                        return None;
                    }
                    let keys: Result<Vec<Key>, _> = serde_json::from_value(o["keys"].clone());
                    match keys.map_err(|e| e.to_string()).and_then(Channel::new) {
                        Ok(ch) => Component::Channel(ch),
                        Err(e) => {
                            self.errors.push(err(format!("bad channel: {e}")));
                            return None;
                        }
                    }
                }
                Json::Object(o) if o.contains_key("expr") => {
                    let Some(text) = o["expr"].as_str() else {
                        self.errors
                            .push(err("an expression (\"expr\") must be a string".into()));
                        return None;
                    };
                    if !spec.animatable {
                        self.errors
                            .push(err("this parameter takes no expression".into()));
                        return None;
                    }
                    match crate::expr::parse(text, self.registry.expressions()) {
                        Ok(e) => Component::Expr(e),
                        Err(e) => {
                            self.errors.push(err(e.message).at(e.position));
                            return None;
                        }
                    }
                }
                other => {
                    self.errors.push(err(format!(
                        "expected {}, found {}",
                        expectation(spec.ty),
                        describe(other)
                    )));
                    return None;
                }
            };
            let values: Vec<f64> = match &c {
                Component::Const(x) => vec![*x],
                Component::Channel(ch) => ch.keys().iter().map(|k| k.value).collect(),
                // Checked when evaluated, at each frame.
                Component::Expr(_) => Vec::new(),
            };
            for v in values {
                if !v.is_finite() {
                    self.errors
                        .push(err("values must be finite numbers".into()));
                    return None;
                }
                if spec.ty == ParamType::Int && v.fract() != 0.0 {
                    self.errors
                        .push(err(format!("expected an integer, found {v}")));
                    return None;
                }
                if let Some(min) = spec.min.filter(|m| v < *m) {
                    self.errors
                        .push(err(format!("value {v} is below the minimum {min}")));
                    return None;
                }
                if let Some(max) = spec.max.filter(|m| v > *m) {
                    self.errors
                        .push(err(format!("value {v} is above the maximum {max}")));
                    return None;
                }
            }
            comps.push(c);
        }
        Some(ParamSource::Components(comps))
    }

    /// The spare parameters `doc` declares on a node of type `spec`, with
    /// their values from `params` (each type's default when absent).
    fn spare_params(
        &mut self,
        path: &str,
        accepts: Option<&str>,
        own: &dyn Fn(&str) -> bool,
        doc: &NodeDoc,
    ) -> Vec<(String, CompiledParam)> {
        let mut out = Vec::new();
        if let (false, Some(ty)) = (doc.spare.is_empty(), accepts) {
            self.errors.push(LoadError::node(
                path,
                format!("a {ty} node takes no spare parameters"),
            ));
            return out;
        }
        for (name, ty) in &doc.spare {
            if own(name) {
                self.errors.push(LoadError::param(
                    path,
                    name,
                    "a spare parameter cannot reuse the name of one of the node's own parameters",
                ));
                continue;
            }
            let Some(pspec) = ParamSpec::spare(ty) else {
                self.errors.push(LoadError::param(
                    path,
                    name,
                    format!(
                        "unknown spare parameter type `{ty}`: expected one of {}",
                        SPARE_TYPES.join(", ")
                    ),
                ));
                continue;
            };
            let source = match doc.params.get(name) {
                Some(j) => self.parse_named(path, name, pspec, j),
                None => None,
            };
            let source = source.unwrap_or_else(|| default_source(pspec));
            out.push((
                name.clone(),
                CompiledParam {
                    spec: pspec,
                    source,
                },
            ));
        }
        out
    }

    fn compile_params(&mut self) {
        // Promoted values, applied to their target after the target's own parameters.
        let mut overrides: BTreeMap<(usize, String), (String, Json)> = BTreeMap::new();
        for i in 0..self.nodes.len() {
            let path = self.nodes[i].path.clone();
            let doc = self.docs[i].clone();
            match self.nodes[i].kind.clone() {
                NodeKind::Op { op, .. } => {
                    let spec = op.spec();
                    let mut given: BTreeMap<&str, &Json> = BTreeMap::new();
                    let refuses = (!spec.spare).then_some(spec.name);
                    let spare =
                        self.spare_params(&path, refuses, &|n| spec.param(n).is_some(), &doc);
                    for (name, j) in &doc.params {
                        match spec.param(name) {
                            Some(_) => {
                                given.insert(name.as_str(), j);
                            }
                            None if spare.iter().any(|(n, _)| n == name) => {}
                            None => {
                                let hint = closest(name, spec.params.iter().map(|p| p.name));
                                self.errors.push(LoadError::node(
                                    &path,
                                    format!("unknown parameter `{name}`{hint}"),
                                ));
                            }
                        }
                    }
                    let mut params = Vec::new();
                    for spec in spec.params {
                        let source = match given.get(spec.name) {
                            Some(j) => self.parse_param(&path, spec, j),
                            None => None,
                        };
                        let source = source.unwrap_or_else(|| default_source(spec));
                        params.push(CompiledParam { spec, source });
                    }
                    self.nodes[i].kind = NodeKind::Op { op, params, spare };
                }
                NodeKind::Invalid | NodeKind::Feed { .. } => {}
                NodeKind::Subnet { block, .. } => {
                    let own: Vec<&'static ParamSpec> = block
                        .as_ref()
                        .map_or(Vec::new(), |b| b.kind.params().iter().collect());
                    let mut compiled = Vec::new();
                    for spec in &own {
                        let source = doc
                            .params
                            .get(spec.name)
                            .and_then(|j| self.parse_param(&path, spec, j));
                        compiled.push(CompiledParam {
                            spec,
                            source: source.unwrap_or_else(|| default_source(spec)),
                        });
                    }
                    let taken: Vec<String> = own
                        .iter()
                        .map(|p| p.name.to_owned())
                        .chain(doc.promote.keys().cloned())
                        .collect();
                    let spare =
                        self.spare_params(&path, None, &|n| taken.iter().any(|t| t == n), &doc);
                    if let NodeKind::Subnet {
                        block: b, spare: s, ..
                    } = &mut self.nodes[i].kind
                    {
                        if let Some(b) = b {
                            b.params = compiled;
                        }
                        *s = spare.clone();
                    }
                    for (name, target) in &doc.promote {
                        let Some((inner, param)) = target.rsplit_once('/') else {
                            self.errors.push(LoadError::node(&path, format!("promoted parameter `{name}` must name `node/parameter`, found `{target}`")));
                            continue;
                        };
                        let inner_path = format!("{path}/{inner}");
                        let Some(&t) = self.by_path.get(&inner_path) else {
                            self.errors.push(LoadError::node(&path, format!("promoted parameter `{name}` targets `{inner}`, which is not a node of the subnet")));
                            continue;
                        };
                        self.promotions.push(Promotion {
                            subnet: path.clone(),
                            name: name.clone(),
                            target: inner_path,
                            target_param: param.to_owned(),
                        });
                        if let Some(j) = doc.params.get(name) {
                            overrides.insert((t, param.to_owned()), (name.clone(), j.clone()));
                        }
                    }
                    for name in doc.params.keys() {
                        if !doc.promote.contains_key(name)
                            && !own.iter().any(|s| s.name == name)
                            && !spare.iter().any(|(n, _)| n == name)
                        {
                            self.errors.push(LoadError::node(&path, format!("unknown parameter `{name}` (a subnet has only its promoted parameters)")));
                        }
                    }
                }
            }
        }
        for ((t, param), (promoted, j)) in overrides {
            let NodeKind::Op { op, .. } = &self.nodes[t].kind else {
                let p = self.nodes[t].path.clone();
                self.errors.push(LoadError::node(&p, format!("promoted parameter `{promoted}` targets a subnet, not a node with parameters")));
                continue;
            };
            let path = self.nodes[t].path.clone();
            let Some(spec) = op.spec().param(&param) else {
                let sub = self.nodes[self.nodes[t].parent.unwrap_or(t)].path.clone();
                self.errors.push(LoadError::node(
                    &sub,
                    format!(
                        "promoted parameter `{promoted}` targets `{param}`, which {} does not have",
                        path
                    ),
                ));
                continue;
            };
            if let Some(source) = self.parse_param(&path, spec, &j) {
                if let NodeKind::Op { params, .. } = &mut self.nodes[t].kind {
                    if let Some(p) = params.iter_mut().find(|p| p.spec.name == param) {
                        p.source = source;
                    }
                }
            }
        }
    }

    fn output_type(&self, i: usize) -> Option<PortType> {
        let mut i = i;
        for _ in 0..=self.nodes.len() {
            let n = &self.nodes[i];
            if n.bypass {
                i = (*n.inputs.first()?)?;
                continue;
            }
            match &n.kind {
                NodeKind::Op { op, .. } => return Some(op.spec().output),
                NodeKind::Feed { block, slot } => match slot {
                    crate::block::FeedSlot::Meta => return Some(PortType::Geometry),
                    crate::block::FeedSlot::Input(n) => {
                        i = self.nodes[*block].inputs.get(*n).copied().flatten()?
                    }
                },
                NodeKind::Subnet { output, .. } => i = (*output)?,
                NodeKind::Invalid => return None,
            }
        }
        None
    }

    fn check_wires(&mut self) {
        for i in 0..self.nodes.len() {
            let NodeKind::Op { op, .. } = &self.nodes[i].kind else {
                continue;
            };
            let spec = op.spec();
            let path = self.nodes[i].path.clone();
            let given = &self.docs[i].inputs;
            let n = self.nodes[i].inputs.len().max(spec.inputs.len());
            if !spec.variadic && given.len() > spec.inputs.len() {
                self.errors.push(LoadError::node(
                    &path,
                    format!(
                        "{} inputs connected but `{}` takes {}",
                        given.len(),
                        spec.name,
                        spec.inputs.len()
                    ),
                ));
                continue;
            }
            for k in 0..n {
                let Some(decl) = spec.inputs.get(k).or(if spec.variadic {
                    spec.inputs.last()
                } else {
                    None
                }) else {
                    continue;
                };
                let src = self.nodes[i].inputs.get(k).copied().flatten();
                let connected_in_doc = given.get(k).is_some_and(|g| g.is_some());
                match src {
                    None if decl.required && !connected_in_doc && k < spec.inputs.len() => {
                        self.errors.push(LoadError::node(
                            &path,
                            format!(
                                "input {} ({}) is required but not connected",
                                k + 1,
                                decl.name
                            ),
                        ));
                    }
                    None if decl.required && k < spec.inputs.len() => {
                        // Wired to an unconnected subnet input: the op would
                        // cook without a geometry it cannot do without.
                        if let Some(Some(at)) = given
                            .get(k)
                            .filter(|g| g.as_deref().is_some_and(|g| g.starts_with('@')))
                        {
                            let parent = self.nodes[i]
                                .parent
                                .map_or_else(String::new, |p| self.nodes[p].path.clone());
                            self.errors.push(LoadError::node(
                                &path,
                                format!(
                                    "input {} ({}) is required but is wired to `{at}`, and that input of subnet {parent} is not connected",
                                    k + 1,
                                    decl.name,
                                ),
                            ));
                        }
                    }
                    Some(s) => {
                        if let Some(t) = self.output_type(s) {
                            if t != decl.ty {
                                self.errors.push(LoadError::node(
                                    &path,
                                    format!(
                                        "input {} ({}) expects {} but {} gives {}",
                                        k + 1,
                                        decl.name,
                                        decl.ty,
                                        self.nodes[s].path,
                                        t
                                    ),
                                ));
                            }
                        }
                    }
                    None => {}
                }
            }
        }
    }
}

fn expectation(ty: ParamType) -> String {
    match ty.components() {
        1 if ty == ParamType::Toggle => {
            "a toggle (true/false, a number, a channel or {\"expr\": ...})".into()
        }
        1 => format!("{ty} (a number, a channel or {{\"expr\": ...}})"),
        n => format!("{ty} (an array of {n} numbers, channels or expressions)"),
    }
}

/// `a`, `b` and `c`: a list's field names for messages.
fn field_names(rows: &ListSpec) -> String {
    let names: Vec<String> = rows
        .fields
        .iter()
        .map(|f| format!("`{}`", f.name))
        .collect();
    names.join(", ")
}

/// ` (did you mean `x`?)` for the known name nearest to `name`, if near.
fn closest<'k>(name: &str, known: impl Iterator<Item = &'k str>) -> String {
    let mut near: Vec<(usize, &str)> = known
        .map(|k| (geode_op::edit_distance(name, k), k))
        .filter(|(d, _)| *d <= 3)
        .collect();
    near.sort();
    near.first()
        .map(|(_, k)| format!(" (did you mean `{k}`?)"))
        .unwrap_or_default()
}

fn default_source(spec: &'static ParamSpec) -> ParamSource {
    match spec.default_value() {
        ParamValue::String(s) if crate::expr::expands(spec) => {
            crate::expr::parse_template(&s, None).map_or(ParamSource::Text(s), text_source)
        }
        v => constant_source(v),
    }
}

/// A string's pieces as a source: plain text when nothing expands.
fn text_source(pieces: Vec<Piece>) -> ParamSource {
    match pieces.as_slice() {
        [] => ParamSource::Text(String::new()),
        [Piece::Text(t)] => ParamSource::Text(t.clone()),
        _ => ParamSource::Template(pieces),
    }
}

/// A fixed value as a parameter source.
fn constant_source(v: ParamValue) -> ParamSource {
    match v {
        ParamValue::Float(x) => ParamSource::Components(vec![Component::Const(x)]),
        ParamValue::Int(x) => ParamSource::Components(vec![Component::Const(x as f64)]),
        ParamValue::Toggle(x) => {
            ParamSource::Components(vec![Component::Const(if x { 1.0 } else { 0.0 })])
        }
        ParamValue::Vector(v) => {
            ParamSource::Components(v.into_iter().map(Component::Const).collect())
        }
        ParamValue::String(s) => ParamSource::Text(s),
        // A list's default has no rows (legacy rows are built field by
        // field in `parse_list`, where the field declarations are known).
        ParamValue::List(_) => ParamSource::List(Vec::new()),
        // A ramp's keys as the rows it is written as.
        ParamValue::Ramp(r) => {
            let fields = ParamType::Ramp(r.kind())
                .ramp_rows()
                .map_or(&[][..], |l| l.fields);
            ParamSource::List(
                geode_op::ramp_to_rows(&r)
                    .into_iter()
                    .map(|row| {
                        fields
                            .iter()
                            .zip(row)
                            .map(|(spec, v)| CompiledParam {
                                spec,
                                source: constant_source(v),
                            })
                            .collect()
                    })
                    .collect(),
            )
        }
    }
}

/// Every cycle through inputs and subnet outputs, each named by its nodes;
/// and each node on a cycle with the problem it gets (a node on a cycle can
/// never cook, and the engine must not walk round it).
fn find_cycles(net: &Network) -> (Vec<LoadError>, Vec<(usize, LoadError)>) {
    let deps = |i: usize| -> Vec<usize> {
        let n = &net.nodes[i];
        let mut d: Vec<usize> = n.inputs.iter().flatten().copied().collect();
        if let NodeKind::Subnet {
            output: Some(o), ..
        } = n.kind
        {
            d.push(o);
        }
        d
    };
    // 0 unvisited, 1 on the stack, 2 done.
    let mut state = vec![0u8; net.nodes.len()];
    let mut errors = Vec::new();
    let mut members = Vec::new();
    for start in 0..net.nodes.len() {
        if state[start] != 0 {
            continue;
        }
        let mut stack: Vec<(usize, Vec<usize>)> = vec![(start, deps(start))];
        state[start] = 1;
        while let Some((node, pending)) = stack.last_mut() {
            match pending.pop() {
                Some(next) if state[next] == 0 => {
                    state[next] = 1;
                    let d = deps(next);
                    stack.push((next, d));
                }
                Some(next) if state[next] == 1 => {
                    let pos = stack
                        .iter()
                        .position(|(n, _)| *n == next)
                        .expect("on the stack");
                    // The stack runs against the data flow (each entry is an
                    // input of the one before): reversed, each node feeds the next.
                    let mut flow: Vec<&str> = stack[pos..]
                        .iter()
                        .rev()
                        .map(|(n, _)| net.nodes[*n].path.as_str())
                        .collect();
                    // Start at the smallest path so the message does not depend on the walk.
                    let first = (0..flow.len()).min_by_key(|&k| flow[k]).unwrap_or(0);
                    flow.rotate_left(first);
                    flow.push(flow[0]);
                    let e = LoadError::node(flow[0], format!("cycle: {}", flow.join(" -> ")));
                    members.extend(stack[pos..].iter().map(|(n, _)| (*n, e.clone())));
                    errors.push(e);
                }
                Some(_) => {}
                None => {
                    state[*node] = 2;
                    stack.pop();
                }
            }
        }
    }
    (errors, members)
}
