//! geode's function representation (FRep) kernel: a field `f(x, y, z)`, with
//! `f >= 0` inside (HyperFun's convention), built as a DAG ([`Field`]),
//! compiled to a flat register [`Tape`], and evaluated at single points, in
//! SIMD-friendly batches, over intervals (conservative bounds for pruning,
//! with per-region tape simplification) and with exact gradients. Knows
//! nothing of geometry containers, nodes or files.

pub mod eval;
pub mod field;
pub mod interval;
pub mod shapes;
pub mod tape;
pub mod vm;

pub use eval::{BatchEval, Grad, GradEval, IntervalEval, PointEval, LANES};
pub use field::{Binary, Field, Node, Unary};
pub use interval::Interval;
pub use tape::{Choice, Instr, Tape};
pub use vm::{parse_vm, VmError};
