//! geode's spline kernel. Today: Catmull-Clark subdivision of any polygon
//! mesh with OpenSubdiv's Catmark rules (semi-sharp and Chaikin creases,
//! corners, boundary modes, holes), attributes interpolated, and limit
//! positions and normals. Depends on `geode-geo` only.

pub mod subd;

pub use subd::{subdivide, BoundaryMode, CreaseMethod, SubdError, SubdOptions};
