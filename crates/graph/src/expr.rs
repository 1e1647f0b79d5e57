//! Expressions in parameters: numeric components written as an expression
//! (`{"expr": "sin($F) * ch(\"../grow/step\")"}`) and strings with `$HIP`,
//! `$F4` and `` `backtick expressions` ``. The language comes from the
//! registry (the node library plugs in the wrangle's); this module resolves
//! `ch()` paths between nodes, finds reference cycles at load time and
//! evaluates per frame, so a referenced value is part of the reader's
//! parameters and so of its cook key.

use std::cell::RefCell;
use std::sync::Arc;

use geode_op::{CookEnv, ExprScope, ExprValue, Expression, ParamValue, TextPosition};

use crate::compiled_param::{CompiledParam, Component, ParamSource};
use crate::load::LoadError;
use crate::network::{Network, NodeKind};

/// A numeric component given as an expression.
#[derive(Clone, Debug)]
pub(crate) struct ExprComponent {
    pub expr: Arc<dyn Expression>,
}

/// A piece of a string parameter.
#[derive(Clone, Debug)]
pub(crate) enum Piece {
    Text(String),
    /// `$F`, `$F4`, `$HIP`...: the variable and its zero padding.
    Var(Var, usize),
    /// `` `expression` ``.
    Expr(ExprComponent),
}

/// The variables a string may name.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Var {
    Frame,
    FractionalFrame,
    Time,
    Fps,
    Hip,
    NodeName,
}

impl Var {
    fn named(name: &str) -> Option<(Var, usize)> {
        Some(match name {
            "F" => (Var::Frame, 0),
            "FF" => (Var::FractionalFrame, 0),
            "T" => (Var::Time, 0),
            "FPS" => (Var::Fps, 0),
            "HIP" => (Var::Hip, 0),
            "OS" => (Var::NodeName, 0),
            _ => {
                let pad = name.strip_prefix('F')?.parse::<usize>().ok()?;
                ((1..=9).contains(&pad)).then_some((Var::Frame, pad))?
            }
        })
    }

    fn reads_time(self) -> bool {
        matches!(self, Var::Frame | Var::FractionalFrame | Var::Time)
    }
}

/// How deep `ch()` references may chain (cycles are refused at load; this
/// bounds the evaluation's recursion whatever happens).
const MAX_REFERENCE_DEPTH: u32 = 64;

/// Whether a string parameter of this declaration expands variables and
/// backticks (code and menus are taken as written, as in Houdini).
pub(crate) fn expands(spec: &geode_op::ParamSpec) -> bool {
    matches!(
        spec.ty,
        geode_op::ParamType::String | geode_op::ParamType::File
    ) && !spec.code
}

/// Splits a string parameter into text, variables and backtick
/// expressions. `\$` and `` \` `` are literal; an unknown `$NAME` stays as
/// written (it may be part of a pattern).
pub(crate) fn parse_template(
    text: &str,
    language: Option<&dyn geode_op::ExprLanguage>,
) -> Result<Vec<Piece>, geode_op::ExprError> {
    let chars: Vec<char> = text.chars().collect();
    let mut pieces = Vec::new();
    let mut literal = String::new();
    let mut i = 0;
    while i < chars.len() {
        match chars[i] {
            '\\' if matches!(chars.get(i + 1), Some('$' | '`')) => {
                literal.push(chars[i + 1]);
                i += 2;
            }
            '$' => {
                let braced = chars.get(i + 1) == Some(&'{');
                let start = i + 1 + usize::from(braced);
                let mut end = start;
                while end < chars.len() && (chars[end].is_ascii_alphanumeric() || chars[end] == '_')
                {
                    end += 1;
                }
                let name: String = chars[start..end].iter().collect();
                let closed = !braced || chars.get(end) == Some(&'}');
                match Var::named(&name).filter(|_| closed) {
                    Some((var, pad)) => {
                        if !literal.is_empty() {
                            pieces.push(Piece::Text(std::mem::take(&mut literal)));
                        }
                        pieces.push(Piece::Var(var, pad));
                        i = end + usize::from(braced);
                    }
                    None => {
                        literal.push('$');
                        i += 1;
                    }
                }
            }
            '`' => {
                let Some(len) = chars[i + 1..].iter().position(|c| *c == '`') else {
                    return Err(geode_op::ExprError {
                        position: Some(TextPosition {
                            line: 1,
                            column: i as u32 + 1,
                        }),
                        message: "a backtick expression is not closed".into(),
                    });
                };
                let inner: String = chars[i + 1..i + 1 + len].iter().collect();
                let expr = parse(&inner, language).map_err(|mut e| {
                    // Positions count from the string's start.
                    if let Some(p) = e.position.as_mut() {
                        p.column += i as u32 + 1;
                    }
                    e
                })?;
                if !literal.is_empty() {
                    pieces.push(Piece::Text(std::mem::take(&mut literal)));
                }
                pieces.push(Piece::Expr(expr));
                i += len + 2;
            }
            c => {
                literal.push(c);
                i += 1;
            }
        }
    }
    if !literal.is_empty() {
        pieces.push(Piece::Text(literal));
    }
    Ok(pieces)
}

/// Parses one expression with the registry's language.
pub(crate) fn parse(
    text: &str,
    language: Option<&dyn geode_op::ExprLanguage>,
) -> Result<ExprComponent, geode_op::ExprError> {
    let language = language
        .ok_or_else(|| geode_op::ExprError::new("this geode has no expression language"))?;
    Ok(ExprComponent {
        expr: language.parse(text)?,
    })
}

/// What evaluating a parameter needs: the network, the node it belongs to,
/// the frame and the environment.
#[derive(Clone, Copy)]
pub(crate) struct EvalCx<'a> {
    pub net: &'a Network,
    pub node: usize,
    pub frame: f64,
    pub env: &'a CookEnv,
    pub depth: u32,
}

impl EvalCx<'_> {
    /// The node's name (`$OS`).
    fn node_name(&self) -> &str {
        let path = &self.net.nodes[self.node].path;
        path.rsplit('/').next().unwrap_or(path)
    }

    /// The value of an expression component. When a `ch()` reference
    /// fails, the error is the referenced parameter's own (it belongs there).
    pub fn expression(&self, e: &ExprComponent) -> Result<ExprValue, geode_op::ExprError> {
        let failed: RefCell<Option<(String, LoadError)>> = RefCell::new(None);
        let channel = |reference: &str| self.reference(reference, &failed);
        let r = e.expr.eval(&ExprScope {
            frame: self.frame,
            fps: self.env.fps,
            hip: &self.env.hip,
            node: self.node_name(),
            channel: &channel,
        });
        match (r, failed.into_inner()) {
            (Err(mut err), Some((reference, cause))) => {
                err.message = format!(
                    "ch(\"{reference}\") fails: {}{}: {}",
                    cause.path,
                    cause.param.map(|p| format!(" `{p}`")).unwrap_or_default(),
                    cause.message
                );
                Err(err)
            }
            (r, _) => r,
        }
    }

    /// A `ch()` reference's value at this frame; when the referenced
    /// parameter fails, its error goes to `failed`.
    fn reference(
        &self,
        reference: &str,
        failed: &RefCell<Option<(String, LoadError)>>,
    ) -> Option<ExprValue> {
        if self.depth >= MAX_REFERENCE_DEPTH {
            return None;
        }
        let target = self.net.resolve_reference(self.node, reference)?;
        let param = self.net.param_named(target.node, &target.param)?;
        let cx = EvalCx {
            node: target.node,
            depth: self.depth + 1,
            ..*self
        };
        let fail = |e: LoadError| {
            failed.borrow_mut().get_or_insert((reference.to_owned(), e));
            None
        };
        if let Some(c) = target.component {
            return match param.component_at(&cx, &target.param, c) {
                Ok(x) => Some(ExprValue::Num(vec![x])),
                Err(e) => fail(e),
            };
        }
        match param.eval_named(&cx, &target.param) {
            Ok(ParamValue::String(s)) => Some(ExprValue::Str(s)),
            Ok(ParamValue::List(_) | ParamValue::Ramp(_)) => None,
            Ok(v) => Some(ExprValue::Num(v.as_components())),
            Err(e) => fail(e),
        }
    }

    /// A string parameter's pieces put together.
    pub fn template(&self, pieces: &[Piece]) -> Result<String, geode_op::ExprError> {
        let mut out = String::new();
        for p in pieces {
            match p {
                Piece::Text(t) => out.push_str(t),
                Piece::Var(v, pad) => out.push_str(&self.variable(*v, *pad)),
                Piece::Expr(e) => match self.expression(e)? {
                    ExprValue::Str(s) => out.push_str(&s),
                    ExprValue::Num(v) => out.push_str(
                        &v.iter()
                            .map(|x| format_number(*x))
                            .collect::<Vec<_>>()
                            .join(" "),
                    ),
                },
            }
        }
        Ok(out)
    }

    fn variable(&self, v: Var, pad: usize) -> String {
        match v {
            Var::Frame => format!("{:0pad$}", self.frame.round() as i64),
            Var::FractionalFrame => format_number(self.frame),
            Var::Time => format_number(self.env.time(self.frame)),
            Var::Fps => format_number(self.env.fps),
            Var::Hip => self.env.hip.clone(),
            Var::NodeName => self.node_name().to_owned(),
        }
    }
}

/// `3` for whole numbers, else the shortest form that reads back.
fn format_number(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        format!("{}", x as i64)
    } else {
        format!("{x}")
    }
}

/// Where a `ch()` path leads: a node, its parameter, maybe one component.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Target {
    pub node: usize,
    pub param: String,
    pub component: Option<usize>,
}

impl Network {
    /// Resolves `reference` (`step`, `../grow/step`, `/a/b/tx`) as read from
    /// node `from`: node paths are relative to the node itself, as in
    /// Houdini (`..` is the network it sits in).
    pub(crate) fn resolve_reference(&self, from: usize, reference: &str) -> Option<Target> {
        let (node_part, param) = match reference.rsplit_once('/') {
            Some((n, p)) => (n, p),
            None => (".", reference),
        };
        let mut at: Vec<&str> = if node_part.starts_with('/') {
            Vec::new()
        } else {
            self.nodes[from]
                .path
                .split('/')
                .filter(|s| !s.is_empty())
                .collect()
        };
        for seg in node_part.split('/') {
            match seg {
                "" | "." => {}
                ".." => {
                    at.pop()?;
                }
                s => at.push(s),
            }
        }
        let node = self.index(&format!("/{}", at.join("/")))?;
        if let Some(t) = self.promoted_target(node, param) {
            return Some(t);
        }
        if self.param_named(node, param).is_some() {
            return Some(Target {
                node,
                param: param.to_owned(),
                component: None,
            });
        }
        // `tx`, `ty`, `tz` (or `t1`...) name one component of vector `t`.
        let (base, last) = param.split_at(param.len().checked_sub(1)?);
        let component = "xyzw".find(last).or_else(|| "1234".find(last))?;
        let p = self.param_named(node, base)?;
        (component < p.spec.ty.components()).then(|| Target {
            node,
            param: base.to_owned(),
            component: Some(component),
        })
    }

    /// A subnet's promoted parameter as the inner parameter it drives.
    fn promoted_target(&self, node: usize, param: &str) -> Option<Target> {
        let p = self
            .promotions()
            .iter()
            .find(|p| p.subnet == self.nodes[node].path && p.name == param)?;
        Some(Target {
            node: self.index(&p.target)?,
            param: p.target_param.clone(),
            component: None,
        })
    }

    /// A node's parameter (declared, spare or a loop's) by name.
    pub(crate) fn param_named(&self, node: usize, name: &str) -> Option<&CompiledParam> {
        fn spare_named<'p>(
            spare: &'p [(String, CompiledParam)],
            name: &str,
        ) -> Option<&'p CompiledParam> {
            spare.iter().find(|(n, _)| n == name).map(|(_, p)| p)
        }
        match &self.nodes[node].kind {
            NodeKind::Op { params, spare, .. } => params
                .iter()
                .find(|p| p.spec.name == name)
                .or_else(|| spare_named(spare, name)),
            NodeKind::Subnet { block, spare, .. } => block
                .as_ref()
                .and_then(|b| b.params.iter().find(|p| p.spec.name == name))
                .or_else(|| spare_named(spare, name)),
            NodeKind::Feed { .. } | NodeKind::Invalid => None,
        }
    }

    /// Every parameter of a node with its name.
    pub(crate) fn params_of(&self, node: usize) -> Vec<(&str, &CompiledParam)> {
        fn spare(s: &[(String, CompiledParam)]) -> Vec<(&str, &CompiledParam)> {
            s.iter().map(|(n, p)| (n.as_str(), p)).collect()
        }
        match &self.nodes[node].kind {
            NodeKind::Op {
                params, spare: s, ..
            } => params
                .iter()
                .map(|p| (p.spec.name, p))
                .chain(spare(s))
                .collect(),
            NodeKind::Subnet {
                block, spare: s, ..
            } => block
                .iter()
                .flat_map(|b| b.params.iter().map(|p| (p.spec.name, p)))
                .chain(spare(s))
                .collect(),
            NodeKind::Feed { .. } | NodeKind::Invalid => Vec::new(),
        }
    }

    /// Whether a parameter changes with the frame: keys that differ, or an
    /// expression reading the time or a parameter that does.
    pub(crate) fn param_animated(&self, node: usize, p: &CompiledParam, depth: u32) -> bool {
        if depth >= MAX_REFERENCE_DEPTH {
            return false;
        }
        let expr = |e: &ExprComponent| {
            e.expr.reads_time()
                || e.expr.references().iter().any(|r| {
                    self.resolve_reference(node, r).is_some_and(|t| {
                        self.param_named(t.node, &t.param)
                            .is_some_and(|q| self.param_animated(t.node, q, depth + 1))
                    })
                })
        };
        match &p.source {
            ParamSource::Components(c) => c.iter().any(|c| match c {
                Component::Const(_) => false,
                Component::Channel(ch) => !ch.is_constant(),
                Component::Expr(e) => expr(e),
            }),
            ParamSource::List(rows) => rows
                .iter()
                .flatten()
                .any(|f| self.param_animated(node, f, depth)),
            ParamSource::Text(_) => false,
            ParamSource::Template(pieces) => pieces.iter().any(|piece| match piece {
                Piece::Text(_) => false,
                Piece::Var(v, _) => v.reads_time(),
                Piece::Expr(e) => expr(e),
            }),
        }
    }
}

/// The expressions of a parameter (list fields and backticks included),
/// each with the component it gives (0 for text and lists).
fn expressions_of(p: &CompiledParam) -> Vec<(usize, &ExprComponent)> {
    match &p.source {
        ParamSource::Components(c) => c
            .iter()
            .enumerate()
            .filter_map(|(k, c)| match c {
                Component::Expr(e) => Some((k, e)),
                _ => None,
            })
            .collect(),
        ParamSource::List(rows) => rows
            .iter()
            .flatten()
            .flat_map(expressions_of)
            .map(|(_, e)| (0, e))
            .collect(),
        ParamSource::Text(_) => Vec::new(),
        ParamSource::Template(pieces) => pieces
            .iter()
            .filter_map(|p| match p {
                Piece::Expr(e) => Some((0, e)),
                _ => None,
            })
            .collect(),
    }
}

/// Checks every `ch()` reference: it must name a parameter, and no chain of
/// references may come back to where it started. Returns the problems, each
/// on the parameter that holds the reference.
pub(crate) fn check_references(net: &Network) -> Vec<LoadError> {
    let mut errors = Vec::new();
    // The graph's vertices are parameter components: (node, parameter,
    // component), so `sizey = ch("sizex")` on one node is no cycle.
    let mut vertices: Vec<(usize, String, usize)> = Vec::new();
    let mut index = std::collections::HashMap::new();
    let mut id = |key: (usize, String, usize), vertices: &mut Vec<(usize, String, usize)>| {
        *index.entry(key.clone()).or_insert_with(|| {
            vertices.push(key);
            vertices.len() - 1
        })
    };
    let mut edges: Vec<(usize, usize)> = Vec::new();
    let env = CookEnv::default();
    for node in 0..net.nodes.len() {
        for (name, p) in net.params_of(node) {
            for (k, e) in expressions_of(p) {
                // An expression reading no other parameter is tried once now, so
                // an unknown function or a type error shows on its own
                // parameter at load rather than on whatever cooks it first.
                if e.expr.references().is_empty() {
                    let cx = EvalCx {
                        net,
                        node,
                        frame: 1.0,
                        env: &env,
                        depth: 0,
                    };
                    if let Err(err) = cx.expression(e) {
                        errors.push(
                            LoadError::param(&net.nodes[node].path, name, err.message)
                                .at(err.position),
                        );
                    }
                }
                for r in e.expr.references() {
                    let Some(t) = net.resolve_reference(node, r) else {
                        errors.push(LoadError::param(
                            &net.nodes[node].path,
                            name,
                            format!(
                                "ch(\"{r}\"): no such parameter (paths are relative to this node: `../other/param`)"
                            ),
                        ));
                        continue;
                    };
                    let a = id((node, name.to_owned(), k), &mut vertices);
                    let width = net
                        .param_named(t.node, &t.param)
                        .map_or(1, |q| q.spec.ty.components().max(1));
                    let targets = match t.component {
                        Some(c) => c..c + 1,
                        None => 0..width,
                    };
                    for c in targets {
                        let b = id((t.node, t.param.clone(), c), &mut vertices);
                        edges.push((a, b));
                    }
                }
            }
        }
    }
    let mut reported = std::collections::HashSet::new();
    for cycle in cycles(vertices.len(), &edges) {
        let names: Vec<String> = cycle
            .iter()
            .chain(cycle.first())
            .map(|&k| format!("{}/{}", net.nodes[vertices[k].0].path, vertices[k].1))
            .collect();
        for &k in &cycle {
            let (node, name, _) = &vertices[k];
            if reported.insert((*node, name.clone())) {
                errors.push(LoadError::param(
                    &net.nodes[*node].path,
                    name,
                    format!(
                        "expression references go round in a cycle: {}",
                        names.join(" → ")
                    ),
                ));
            }
        }
    }
    errors
}

/// The cycles of a directed graph (each once, as found by depth-first search).
fn cycles(n: usize, edges: &[(usize, usize)]) -> Vec<Vec<usize>> {
    let mut out_edges = vec![Vec::new(); n];
    for &(a, b) in edges {
        out_edges[a].push(b);
    }
    // 0 unvisited, 1 on the stack, 2 done; iterative so no graph overflows it.
    let mut state = vec![0u8; n];
    let mut found = Vec::new();
    for start in 0..n {
        if state[start] != 0 {
            continue;
        }
        let mut stack: Vec<(usize, usize)> = vec![(start, 0)];
        state[start] = 1;
        while let Some(&mut (v, ref mut next)) = stack.last_mut() {
            if let Some(&w) = out_edges[v].get(*next) {
                *next += 1;
                match state[w] {
                    0 => {
                        state[w] = 1;
                        stack.push((w, 0));
                    }
                    1 => {
                        let from = stack.iter().position(|(x, _)| *x == w).unwrap_or(0);
                        found.push(stack[from..].iter().map(|(x, _)| *x).collect());
                    }
                    _ => {}
                }
            } else {
                state[v] = 2;
                stack.pop();
            }
        }
    }
    found
}
