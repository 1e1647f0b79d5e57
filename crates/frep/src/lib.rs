//! geode's function representation (FRep) kernel: a field `f(x, y, z)`, with
//! `f >= 0` inside (HyperFun's convention), built as a DAG ([`Field`]),
//! compiled to a flat register [`Tape`], and evaluated at single points, in
//! SIMD-friendly batches, over intervals (conservative bounds for pruning,
//! with per-region tape simplification) and with exact gradients; meshed by
//! a feature-preserving dual-contouring polygoniser into `geode-geo`
//! geometry. Knows nothing of nodes, graphs or files.

pub mod adaptive;
mod brick;
pub mod capsules;
mod cell;
mod cluster;
pub mod codec;
pub mod distance;
pub mod eval;
mod features;
pub mod field;
mod flip;
pub mod hyperfun;
pub mod interval;
mod lattice;
mod parts;
mod pinch;
pub mod polygonise;
mod qef;
mod recovery;
mod refine;
pub mod shapes;
mod surface;
pub mod tape;
mod thin;
pub mod vm;

pub use capsules::CapsuleSet;
pub use eval::{BatchEval, BatchGradEval, Grad, GradEval, IntervalEval, PointEval, LANES};
pub use field::{Binary, Field, Node, Unary};
pub use hyperfun::{parse_hf, HfError};
pub use interval::Interval;
pub use polygonise::{polygonise, sample, MeshError, MeshEstimate, MeshOptions, MeshStats};
pub use surface::surface_distances;
pub use tape::{Choice, Choices, Instr, Tape};
pub use vm::{parse_vm, VmError};
