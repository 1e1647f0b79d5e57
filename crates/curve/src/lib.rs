//! geode's curve kernel: curve shapes (line, arc, helix, torus knot) and
//! interpolation through points (Catmull-Rom, B-spline), resampling by
//! length or count, smoothing and carving, rotation-minimizing frames
//! (double reflection, parallel transport, up vector; closed curves close),
//! sweeps into quad tubes, polylines joined into maximal paths (PolyPath),
//! and copy to points (packed or not). Works on
//! `geode-geo` geometry; knows nothing of nodes, graphs or files.

pub mod copy;
pub mod frames;
pub mod polyline;
pub mod polypath;
pub mod rebuild;
pub mod resample;
pub mod shapes;
pub mod sweep;

pub use copy::{copy_to_points, CopyError, CopyOptions};
pub use frames::{frames, tangents, Frame, FrameMethod, TangentMode};
pub use polyline::{curves, Curve};
pub use polypath::{polypath, PolyPathError, PolyPathOptions};
pub use rebuild::{rebuild, CurveOut};
pub use resample::{carve, resample_by_count, resample_by_length, smooth, Sample};
pub use sweep::{sweep, SweepOptions};
