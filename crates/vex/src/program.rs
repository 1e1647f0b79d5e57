//! A compiled snippet (instructions, call sites, bindings) and the contract
//! between a call site and the lane function it runs: what the function
//! sees of the run (`Host`), how it stops, and what it asks the budget for.

use std::sync::Arc;

use geode_geo::{AttribClass, Geometry, Topology};

use crate::compile::Pos;
use crate::effect::EffectKind;
use crate::ir;
use crate::ty::Ty;
use crate::value::Val;

/// Register counts per file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    pub f: u32,
    pub i: u32,
    pub s: u32,
    pub af: u32,
    pub ai: u32,
    pub as_: u32,
}

/// The program's numeric constants, each file's from its first register
/// on: a frame sets them once (see `compile::lower::pool`).
#[derive(Clone, Debug, Default)]
pub struct Constants {
    pub floats: (ir::Reg, Vec<f32>),
    pub ints: (ir::Reg, Vec<i32>),
}

/// A compiled snippet, ready to run on the geometry it was compiled for.
pub struct Program {
    pub(crate) ops: Vec<ir::Op>,
    /// Each instruction's statement, for errors at run time.
    pub(crate) op_pos: Vec<Pos>,
    pub(crate) calls: Vec<CallSite>,
    pub(crate) strings: Vec<String>,
    pub(crate) counts: Counts,
    pub(crate) bindings: Vec<Binding>,
    pub(crate) written: Vec<bool>,
    pub(crate) run_over: AttribClass,
    /// The ramp parameters `chramp` reads, by index.
    pub(crate) ramps: Vec<geode_geo::Ramp>,
    pub(crate) constants: Constants,
    /// One lane (a detail run): control flow is jumps and an instruction
    /// may write a register it reads (see `compile::lower::flow`).
    pub(crate) uniform: bool,
}

impl Program {
    /// Instructions, for tests and the curious.
    pub fn len(&self) -> usize {
        self.ops.len()
    }

    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// The instructions, one a line with its index, for tests and for
    /// reading what the compiler made of a snippet.
    pub fn listing(&self) -> String {
        self.ops
            .iter()
            .enumerate()
            .map(|(k, op)| format!("{k:4} {op:?}\n"))
            .collect()
    }

    /// The attributes the snippet writes (created if missing).
    pub fn written(&self) -> Vec<&str> {
        self.bindings
            .iter()
            .zip(&self.written)
            .filter(|(_, w)| **w)
            .map(|(b, _)| b.name.as_str())
            .collect()
    }
}

/// Where a binding's value comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    /// An attribute of input `input` (0 is written back), of `class`.
    Attr {
        input: usize,
        class: AttribClass,
        attrib: String,
    },
    /// A detail attribute of input 0, the same for every element.
    Detail(String),
    /// The element's own number (`@ptnum` over points, `@elemnum`).
    Elem,
    /// The primitive of the vertex (`@primnum` over vertices).
    PrimOfVertex,
    /// The point of the vertex (`@ptnum` over vertices).
    PointOfVertex,
    /// Membership of the element in a group of input 0 (`@group_name`):
    /// 1 or 0, and written back as the group.
    Group(String),
    /// The vertex count of the element's primitive (`@numvtx` over
    /// primitives and vertices).
    PrimVertexCount,
    /// A constant of the run (`@numpt`, `@Frame`, `-1` for numbers that do
    /// not apply).
    Const(f64),
    /// `@P` over primitives that have no `P` of their own: the average of
    /// the primitive's points, as Houdini reads it (read-only).
    Centroid,
    /// Over vertices, a numeric attribute the vertices lack but their
    /// points (or else primitives) have, read through each vertex's
    /// point or primitive, as Houdini does (read-only).
    Through { class: AttribClass, attrib: String },
}

#[derive(Clone, Debug)]
pub struct Binding {
    pub name: String,
    pub ty: Ty,
    pub loc: ir::Loc,
    pub source: Source,
}

impl Binding {
    /// Why a binding cannot be written, for the error that says so (""
    /// where "read-only" says it all).
    pub fn read_only_because(&self) -> &'static str {
        match self.source {
            Source::Centroid => " here: over primitives it is the average of each primitive's points (move points with setpointattrib)",
            Source::Through { .. } => " here: the vertices read it from their points or primitives (write it with setpointattrib or setprimattrib)",
            _ => "",
        }
    }

    pub fn writable(&self) -> bool {
        matches!(
            self.source,
            Source::Attr { input: 0, .. } | Source::Group(_)
        )
    }
}

impl std::fmt::Debug for Program {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (i, op) in self.ops.iter().enumerate() {
            writeln!(f, "{i:4} {op:?}")?;
        }
        Ok(())
    }
}

/// What a call asks the budget for, in the words a refusal uses; made
/// on every call that grows something, so words are only formatted when
/// the request is refused.
#[derive(Clone, Copy, Debug)]
pub enum Request {
    Resize(u64),
    IndexSet(i32),
    Array(u64),
    Concat(u64),
    Split(u64),
    Format(u64),
    NearPoints(u64),
}

impl std::fmt::Display for Request {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Request::Resize(n) => write!(f, "resize to {n} elements"),
            Request::IndexSet(i) => write!(f, "setting element {i}"),
            Request::Array(n) => write!(f, "an array of {n} elements"),
            Request::Concat(n) => write!(f, "a string of {n} bytes"),
            Request::Split(n) => write!(f, "splitting a string of {n} bytes"),
            Request::Format(n) => write!(f, "formatting a string of {n} bytes"),
            Request::NearPoints(n) => write!(f, "nearpoints finding up to {n} points"),
        }
    }
}

/// Why a lane function stopped: a message for the element, or cancelled.
#[derive(Debug)]
pub enum Stop {
    Msg(String),
    Cancelled,
    OverBudget(String),
}

impl From<String> for Stop {
    fn from(msg: String) -> Stop {
        Stop::Msg(msg)
    }
}

/// Stop with an over-budget refusal: the message names the request.
impl Stop {
    pub fn over_budget(msg: String) -> Stop {
        Stop::OverBudget(msg)
    }
}

/// What a lane function sees of the run: the inputs and the indexes built
/// on them once per run, the effects it may queue, cancellation.
pub trait Host {
    /// Input `i`, if connected.
    fn input(&self, i: i32) -> Option<&Geometry>;
    /// Input `i`'s topology, built on first use.
    fn topology(&self, i: i32) -> Option<Arc<Topology>>;
    /// Up to `count` points of input `i` (of point group `group` unless it
    /// is empty) within `radius` of `q`, nearest first.
    fn nearest(&self, i: i32, group: &str, q: [f32; 3], radius: f32, count: usize) -> Vec<u32>;
    /// Queues a geometry change of this lane's element; `Err` is the
    /// budget's refusal (or the change's own error where it is made at
    /// once).
    fn queue(&mut self, kind: EffectKind) -> Result<(), Stop>;
    /// Makes a point for this lane's element (a copy of point `from` with
    /// its attributes, or at `at`); its provisional number. `Err` is the
    /// budget's refusal or a missing source point.
    fn add_point(&mut self, from: Option<i32>, at: [f32; 3]) -> Result<i32, Stop>;
    /// Makes a polygon (or a polyline) through `points`; its provisional
    /// number.
    fn add_prim(&mut self, polyline: bool, points: &[i32]) -> Result<i32, Stop>;
    fn cancelled(&self) -> bool;
    /// The element this lane runs (for messages).
    fn elem(&self) -> u32;
    /// An index over input `i` built once per run by `build` and kept
    /// under `key` and `variant` (the surface `xyzdist` searches, for one,
    /// with the primitive group pattern it covers as the variant).
    fn cached(
        &self,
        i: i32,
        key: &'static str,
        variant: &str,
        build: &dyn Fn(&Geometry) -> Arc<dyn std::any::Any + Send + Sync>,
    ) -> Option<Arc<dyn std::any::Any + Send + Sync>>;
    /// The ramp parameter `chramp` compiled as index `k`.
    fn ramp(&self, k: usize) -> Option<&geode_geo::Ramp>;
    /// Keeps a point cloud query for this lane; its handle.
    fn open_query(&mut self, q: PointQuery) -> i32;
    /// The query of a handle `open_query` gave this lane.
    fn query(&mut self, handle: i32) -> Option<&mut PointQuery>;
}

/// One lane's call: the host, and the type the call site asked for (the
/// functions whose result VEX picks from the context read it).
pub struct Lane<'h> {
    pub host: &'h mut dyn Host,
    pub out: Ty,
}

/// A library function over one lane: reads its arguments, may change the
/// ones declared as outputs (VEX's by-reference arguments), and returns
/// its result. It leaves the other arguments as they are: a literal is
/// read once for every lane of a call.
pub type LaneFn = fn(&mut Lane<'_>, &mut [Val]) -> Result<Val, Stop>;

/// A pure function of numbers, for calls whose arguments and result are
/// all numbers: the floats of its arguments in order (ints as floats) to
/// the floats of its result (as many as the call's result type holds). A
/// call site runs it over its lanes without building a value per lane; the
/// form's lane function computes through it too, so both give the same
/// bits.
pub type NumFn = fn(&[f32], &mut [f32]);

/// The most argument floats a call of numbers gathers per lane.
pub const NUM_ARGS: usize = 64;

/// The most ints and the most floats a call of edits gathers per lane
/// (more take the general path).
pub const EDIT_ARGS: usize = 16;

/// One lane's arguments to a function of edits (`EditFn`): the ints and
/// the floats of its arguments, each in order (an int array spread into
/// the ints), and the string argument (empty if none).
pub struct Numbers<'a> {
    pub ints: &'a [i32],
    pub floats: &'a [f32],
    pub text: &'a str,
}

/// A function that changes geometry through the host from numbers
/// (`addpoint`, `addprim`, `addvertex`) and returns an int. A call site
/// whose arguments are numbers and string literals runs it without
/// building a value per lane (a detail loop makes millions of these
/// calls); the form's lane function goes through it too.
pub type EditFn = fn(&mut dyn Host, &Numbers) -> Result<i32, Stop>;

/// What a call's result will hold on the heap before it is made, where
/// that can exceed what its arguments hold, with the request a refusal
/// names.
pub type BytesFn = fn(&[Val], &dyn Host) -> Option<(Request, u64)>;

/// How a call reads an argument for a lane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArgMode {
    /// A literal, read once for every lane.
    Const,
    /// Copied out of its register (numbers, or a register another argument
    /// also reads).
    Copy,
    /// Moved out of its register and back after the call: a string or an
    /// array used once, or an output.
    Move,
}

/// A call of a library function at one place of the snippet.
#[derive(Clone, Debug)]
pub struct CallSite {
    pub name: &'static str,
    pub lane: LaneFn,
    pub bytes: Option<BytesFn>,
    pub args: Vec<ir::Loc>,
    /// The arguments that are literals, read once instead of per lane.
    pub consts: Vec<Option<Val>>,
    /// How each argument is read for a lane (outputs are moved out of
    /// their registers before the call and back after it).
    pub modes: Vec<ArgMode>,
    pub out: ir::Loc,
    /// Lanes the call applies to (side effects): `None` for all.
    pub mask: Option<ir::Reg>,
    /// Whether the call touches strings or arrays (only those are charged
    /// to the memory budget).
    pub counted: bool,
    /// The form's function of numbers, where every argument and the result
    /// are numbers (see `NumFn`).
    pub num: Option<NumFn>,
    /// The form's function of edits, where every argument is a number or a
    /// string literal (see `EditFn`).
    pub edit: Option<EditFn>,
    /// Where in the snippet, for runtime errors.
    pub pos: Pos,
}

/// The points a `pcopen` found, nearest first, and where `pciterate` is.
#[derive(Clone, Debug, Default)]
pub struct PointQuery {
    pub input: i32,
    pub points: Vec<u32>,
    pub distances: Vec<f32>,
    /// The next point `pciterate` moves to (1-based: 0 before the first).
    pub cursor: usize,
}

impl ArgMode {
    /// How a call reads each argument: literals once, outputs and strings
    /// or arrays no other argument reads moved, the rest copied.
    pub fn of(args: &[ir::Loc], consts: &[Option<Val>], outs: &[bool]) -> Vec<ArgMode> {
        let heap = |t: Ty| matches!(t, Ty::Str | Ty::Array(_));
        args.iter()
            .enumerate()
            .map(|(k, a)| {
                if consts[k].is_some() {
                    return ArgMode::Const;
                }
                let shared = args
                    .iter()
                    .enumerate()
                    .any(|(j, b)| j != k && b.reg == a.reg && b.ty == a.ty);
                if outs[k] || (heap(a.ty) && !shared) {
                    ArgMode::Move
                } else {
                    ArgMode::Copy
                }
            })
            .collect()
    }
}
