//! Loops and solvers: subnets the engine cooks repeatedly. A loop cooks its
//! network N times (or until a detail attribute of the result says stop),
//! each pass on the previous pass's result; a solver cooks frame F's network
//! on frame F-1's result, its first frame on the input. Inside, `@0` is that
//! feedback, `@1`.. the block's other inputs and `@meta` a geometry whose
//! detail attributes give the pass (`iteration`, `numiterations`; for a
//! solver `frame` and `start_frame`). Every pass's nodes are keyed by
//! content, so the key of a result covers the chain that led to it and a
//! second cook (or scrubbing forward) is a walk of cache hits.

use geode_geo::{AttribClass, AttribData, AttribValue, Attribute, Geometry, TypeInfo};
use geode_op::{
    CookError, ErrorKind, ParamDefault as D, ParamSpec as P, ParamType as T, Params, Value,
};

use crate::compile::CompiledParam;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlockKind {
    Loop,
    Solver,
}

const ITERATIONS: P = P::new(
    "iterations",
    "Iterations",
    T::Int,
    D::Int(1),
    "Passes of the network, each on the previous pass's result.",
)
.at_least(0.0);
const STOP: P = P::new(
    "stop",
    "Stop attribute",
    T::String,
    D::Str(""),
    "A detail attribute of a pass's result that ends the loop when non-zero; empty for none.",
);
const START_FRAME: P = P::new("start_frame", "Start frame", T::Float, D::Float(1.0), "The frame the solver starts from: its network runs on the input there, and on the previous frame's result after.");

pub(crate) static LOOP_PARAMS: [P; 2] = [ITERATIONS, STOP];
pub(crate) static SOLVER_PARAMS: [P; 1] = [START_FRAME];

impl BlockKind {
    pub fn from_type(ty: &str) -> Option<BlockKind> {
        BlockKind::ALL.into_iter().find(|k| k.name() == ty)
    }

    pub const ALL: [BlockKind; 2] = [BlockKind::Loop, BlockKind::Solver];

    /// The block's declaration ([`crate::container`]).
    pub fn spec(self) -> &'static geode_op::NodeSpec {
        match self {
            BlockKind::Loop => &crate::container::LOOP,
            BlockKind::Solver => &crate::container::SOLVER,
        }
    }

    pub fn name(self) -> &'static str {
        self.spec().name
    }

    pub fn params(self) -> &'static [P] {
        self.spec().params
    }
}

/// A loop's or solver's own parameters.
#[derive(Clone)]
pub struct Block {
    pub kind: BlockKind,
    pub(crate) params: Vec<CompiledParam>,
}

impl std::fmt::Debug for Block {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Block({})", self.kind.name())
    }
}

impl Block {
    pub fn new(kind: BlockKind) -> Block {
        Block {
            kind,
            params: Vec::new(),
        }
    }
}

/// What a feed gives inside a block.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FeedSlot {
    /// `@0`: the feedback; `@N`: the block's input N.
    Input(usize),
    /// `@meta`: the pass's numbers as detail attributes.
    Meta,
}

/// The `@meta` geometry of a pass: detail attributes by name.
pub fn meta(values: &[(&str, i32)]) -> Value {
    let mut g = Geometry::new();
    for (name, v) in values {
        let a = Attribute::new(AttribValue::Int(0), TypeInfo::None, 1);
        g.set_attrib(AttribClass::Detail, name, a)
            .expect("one detail element");
        if let Some(x) = g.attribs_mut(AttribClass::Detail).get_mut(name) {
            let _ = x.values_mut().set(0, &AttribValue::Int(*v));
        }
    }
    Value::geometry(g)
}

/// Whether a pass's result asks the loop to stop.
pub fn stops(value: &Value, attr: &str) -> bool {
    if attr.is_empty() {
        return false;
    }
    let Some(g) = value.as_geometry() else {
        return false;
    };
    match g.attrib(AttribClass::Detail, attr).map(|a| a.data()) {
        Some(AttribData::Int(v)) => v.first().is_some_and(|x| *x != 0),
        Some(AttribData::Float(v)) => v.first().is_some_and(|x| *x != 0.0),
        _ => false,
    }
}

/// The loop's pass count and stop attribute.
pub fn loop_settings(p: &Params) -> Result<(usize, String), CookError> {
    Ok((
        p.int(&ITERATIONS)?.max(0) as usize,
        p.string(&STOP)?.to_owned(),
    ))
}

pub fn start_frame(p: &Params) -> Result<f64, CookError> {
    p.float(&START_FRAME)
}

/// An error inside pass `pass` of block `path`, saying so.
pub fn in_pass(mut e: CookError, path: &str, what: &str) -> CookError {
    if e.kind != ErrorKind::Cancelled {
        e.message = format!("{} ({what} of {path})", e.message);
    }
    e
}
