//! geode's spline kernel: B-spline and NURBS curves and surfaces (any
//! degree and knot vector, rational weights, derivatives, exact knot
//! insertion and refinement, tessellation), and Catmull-Clark subdivision
//! of any polygon mesh with OpenSubdiv's Catmark rules (semi-sharp and
//! Chaikin creases, corners, boundary modes, holes), attributes
//! interpolated, limit positions and normals. Depends on `geode-geo` only.

pub mod bspline;
pub mod hspline;
pub mod skin;
pub mod subd;

pub use subd::{subdivide, BoundaryMode, CreaseMethod, SubdError, SubdOptions};
