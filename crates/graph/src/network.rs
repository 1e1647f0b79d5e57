//! The loaded network as the engine runs it: nodes flattened by path with
//! their inputs and compiled parameters, and what the studio and CLI ask of
//! it (types, parameter values at a frame, tags, problems, `check`).

use std::collections::HashMap;
use std::sync::Arc;

use geode_op::{CookEnv, Operator, ParamValue, Params};

use crate::compiled_param::CompiledParam;
use crate::expr::EvalCx;
use crate::load::LoadError;

/// What a node is: an operator, a subnetwork (a loop or solver's body
/// included), a block's feed, or a type the registry does not know.
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

/// A node of the flattened network.
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
    pub(crate) by_path: HashMap<String, usize>,
    pub(crate) output: Option<usize>,
    pub(crate) promotions: Vec<Promotion>,
    pub(crate) notes: Vec<LoadError>,
    /// Every problem found, sorted by path (each node's also on the node).
    pub(crate) problems: Vec<LoadError>,
    /// The document's frame rate (`fps`), if it sets one.
    pub(crate) fps: Option<f64>,
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
}
