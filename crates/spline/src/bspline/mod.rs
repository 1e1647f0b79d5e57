//! B-spline and NURBS curves and tensor-product surfaces: evaluation with
//! derivatives, exact knot insertion and refinement, tessellation.

pub mod basis;
pub mod curve;
pub mod patch;
pub mod surface;

pub use basis::{KnotError, Knots};
pub use curve::NurbsCurve;
pub use surface::{NurbsSurface, Tessellation};
