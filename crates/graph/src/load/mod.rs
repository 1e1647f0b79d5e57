//! Turns a document into a checked, flattened network, reporting every
//! problem at once: nodes collected by path, inputs and references
//! resolved, parameters compiled (`params`), wires type-checked, cycles
//! found.

mod params;
pub(crate) use params::closest;

use std::collections::HashMap;
use std::sync::Arc;

use geode_op::{PortType, Registry, TextPosition};
use serde_json::Value as Json;

use crate::document::{Document, NetworkDoc, NodeDoc, VERSION};
use crate::network::{Network, Node, NodeKind, Promotion};

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

impl Network {
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
