//! geode's function representation (FRep) kernel: a field `f(x, y, z)`, with
//! `f >= 0` inside (HyperFun's convention), built as a DAG ([`Field`]),
//! compiled to a flat register [`Tape`], and evaluated at single points, in
//! SIMD-friendly batches, over intervals (conservative bounds for pruning,
//! with per-region tape simplification) and with exact gradients; shapes,
//! operations and importers (HyperFun, fidget's VM format) build fields.
//! Meshing them is `geode-mesher`'s work. Knows nothing of nodes, graphs or
//! files.

pub mod capsules;
pub mod codec;
pub mod dataset;
pub mod distance;
pub mod eval;
pub mod field;
pub mod hyperfun;
pub mod interval;
pub mod interval_grad;
pub mod mesh_distance;
pub mod shapes;
pub mod tape;
pub mod vm;
pub mod volume;

pub use capsules::CapsuleSet;
pub use dataset::Dataset;
pub use eval::{BatchEval, BatchGradEval, Grad, GradEval, IntervalEval, PointEval, LANES};
pub use field::{Binary, Field, Node, Unary};
pub use hyperfun::{parse_hf, HfError};
pub use interval::Interval;
pub use interval_grad::{IntervalGrad, IntervalGradEval, Piece};
pub use mesh_distance::{MeshDistance, MeshFieldError};
pub use tape::{Choice, Choices, Instr, Tape};
pub use vm::{parse_vm, VmError};
pub use volume::{SampleError, SampleOptions, SamplePlan, VolumeField};
