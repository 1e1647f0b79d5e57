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

use crate::compiled_param::CompiledParam;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlockKind {
    Loop,
    Solver,
    ForEach,
    /// Not a network: its input cooked at another frame.
    TimeShift,
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

const FOR_EACH_METHOD: P = P::new(
    "method",
    "Iterate over",
    T::Menu(&["pieces", "attribute", "count"]),
    D::Str("pieces"),
    "Connected pieces (primitives sharing points: Houdini's For-Each Connected Piece), the values of a primitive attribute (For-Each Named Primitive), or a count of passes each on the previous pass's result (a loop with feedback).",
);
const FOR_EACH_ATTRIBUTE: P = P::new(
    "attribute",
    "Piece attribute",
    T::String,
    D::Str("name"),
    "Iterating over an attribute: the primitive attribute (string or integer, e.g. `name` or `class`) whose values make the pieces, in order of first appearance.",
);
const FOR_EACH_ITERATIONS: P = P::new(
    "iterations",
    "Iterations",
    T::Int,
    D::Int(1),
    "Iterating by count: the passes, each on the previous pass's result.",
)
.at_least(0.0);

pub(crate) static FOR_EACH_PARAMS: [P; 4] = [
    FOR_EACH_METHOD,
    FOR_EACH_ATTRIBUTE,
    FOR_EACH_ITERATIONS,
    STOP,
];

const SHIFT_METHOD: P = P::new(
    "method",
    "Method",
    T::Menu(&["offset", "frame"]),
    D::Str("offset"),
    "Shift the frame by an offset, or cook at the frame given (an expression of $F like any number: `{\"expr\": \"$F * 2\"}` or `{\"expr\": \"floor($F / 4) * 4\"}` in a network file).",
);
const SHIFT_OFFSET: P = P::new(
    "offset",
    "Offset",
    T::Float,
    D::Float(0.0),
    "Frames added to the current one (-1: the previous frame).",
);
const SHIFT_FRAME: P = P::new(
    "frame",
    "Frame",
    T::Float,
    D::Float(1.0),
    "The frame to cook the input at.",
);
const SHIFT_CLAMP: P = P::new(
    "clamp",
    "Clamp",
    T::Toggle,
    D::Toggle(false),
    "Keep the frame within the range.",
);
const SHIFT_RANGE: P = P::new(
    "range",
    "Range",
    T::Vec2,
    D::Vec2([1.0, 240.0]),
    "The first and last frame the input is cooked at, when clamped (in either order).",
);

pub(crate) static TIME_SHIFT_PARAMS: [P; 5] = [
    SHIFT_METHOD,
    SHIFT_OFFSET,
    SHIFT_FRAME,
    SHIFT_CLAMP,
    SHIFT_RANGE,
];

/// The frame a time shift cooks its input at, from the current `frame`.
pub fn shifted_frame(p: &Params, frame: f64) -> Result<f64, CookError> {
    let mut f = match p.string(&SHIFT_METHOD)? {
        "frame" => p.float(&SHIFT_FRAME)?,
        _ => frame + p.float(&SHIFT_OFFSET)?,
    };
    if p.toggle(&SHIFT_CLAMP)? {
        let r = p.vector::<2>(&SHIFT_RANGE)?;
        f = f.clamp(r[0].min(r[1]), r[0].max(r[1]));
    }
    Ok(f)
}

/// What a for-each iterates over.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ForEach {
    /// Connected pieces.
    Pieces,
    /// The values of a primitive attribute.
    Attribute(String),
    /// Passes with feedback, and the stop attribute.
    Count(usize, String),
}

/// The for-each's settings.
pub fn for_each_settings(p: &Params) -> Result<ForEach, CookError> {
    Ok(match p.string(&FOR_EACH_METHOD)? {
        "attribute" => ForEach::Attribute(p.string(&FOR_EACH_ATTRIBUTE)?.to_owned()),
        "count" => ForEach::Count(
            p.int(&FOR_EACH_ITERATIONS)?.max(0) as usize,
            p.string(&STOP)?.to_owned(),
        ),
        _ => ForEach::Pieces,
    })
}

/// The geometry's pieces for a for-each (in order: by first primitive, or
/// by first appearance of the attribute's value), each with its value for
/// `@meta` (the piece number, or the attribute's value).
/// `Ok(None)` when `cancel` says stop.
pub fn pieces_of(
    g: &Geometry,
    how: &ForEach,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Option<Vec<(Geometry, MetaValue)>>, String> {
    use geode_geo::ops;
    match how {
        ForEach::Attribute(name) => {
            let Some(a) = g.attrib(AttribClass::Primitive, name) else {
                let known: Vec<&str> = g.attribs(AttribClass::Primitive).names().collect();
                return Err(format!(
                    "parameter `attribute`: no primitive attribute `{name}` (there are: {})",
                    if known.is_empty() {
                        "none".to_owned()
                    } else {
                        known.join(", ")
                    }
                ));
            };
            let (of_prim, firsts) = ops::value_classes(a.data());
            let mut lists: Vec<Vec<u32>> = vec![Vec::new(); firsts.len()];
            for (prim, &k) in of_prim.iter().enumerate() {
                lists[k as usize].push(prim as u32);
            }
            use rayon::prelude::*;
            if cancel() {
                return Ok(None);
            }
            Ok(Some(
                lists
                    .par_iter()
                    .zip(firsts.par_iter())
                    .map(|(prims, &first)| {
                        let value = match a.data().get(first as usize) {
                            AttribValue::String(s) => MetaValue::Text(s),
                            AttribValue::Int(i) => MetaValue::Int(i),
                            other => MetaValue::Text(format!("{other:?}")),
                        };
                        (ops::extract(g, prims, &[]), value)
                    })
                    .collect(),
            ))
        }
        _ => {
            let Some(pieces) =
                ops::connectivity_cancellable(g, ops::Connect::SharedPoint, None, cancel)
            else {
                return Ok(None);
            };
            let Some(parts) = ops::split_pieces_cancellable(g, &pieces, cancel) else {
                return Ok(None);
            };
            Ok(Some(
                parts
                    .into_iter()
                    .enumerate()
                    .map(|(k, piece)| (piece, MetaValue::Int(k as i32)))
                    .collect(),
            ))
        }
    }
}

/// A piece's value in `@meta`.
#[derive(Clone, Debug, PartialEq)]
pub enum MetaValue {
    Int(i32),
    Text(String),
}

impl BlockKind {
    pub fn from_type(ty: &str) -> Option<BlockKind> {
        BlockKind::ALL.into_iter().find(|k| k.name() == ty)
    }

    pub const ALL: [BlockKind; 4] = [
        BlockKind::Loop,
        BlockKind::Solver,
        BlockKind::ForEach,
        BlockKind::TimeShift,
    ];

    /// The block's declaration ([`crate::container`]).
    pub fn spec(self) -> &'static geode_op::NodeSpec {
        match self {
            BlockKind::Loop => &crate::container::LOOP,
            BlockKind::Solver => &crate::container::SOLVER,
            BlockKind::ForEach => &crate::container::FOR_EACH,
            BlockKind::TimeShift => &crate::container::TIME_SHIFT,
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

/// The `@meta` geometry of a for-each pass: iteration, numiterations and
/// the piece's value (`value`, an integer or a string).
pub fn piece_meta(iteration: usize, count: usize, value: &MetaValue) -> Value {
    let mut g = meta_geometry(&[
        ("iteration", iteration as i32),
        ("numiterations", count as i32),
    ]);
    {
        let a = match value {
            MetaValue::Int(i) => Attribute::from_data(AttribData::Int(vec![*i]), TypeInfo::None),
            MetaValue::Text(t) => Attribute::from_data(
                AttribData::String(geode_geo::StringColumn {
                    table: vec![t.clone()],
                    indices: vec![0],
                }),
                TypeInfo::None,
            ),
        };
        g.set_attrib(AttribClass::Detail, "value", a)
            .expect("one detail element");
    }
    Value::geometry(g)
}

/// The `@meta` geometry of a pass: detail attributes by name.
pub fn meta(values: &[(&str, i32)]) -> Value {
    Value::geometry(meta_geometry(values))
}

fn meta_geometry(values: &[(&str, i32)]) -> Geometry {
    let mut g = Geometry::new();
    for (name, v) in values {
        let a = Attribute::from_data(AttribData::Int(vec![*v]), TypeInfo::None);
        g.set_attrib(AttribClass::Detail, name, a)
            .expect("one detail element");
    }
    g
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
