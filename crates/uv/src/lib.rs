//! geode's UV kernel: texture coordinates for polygon meshes (projections,
//! and flattening by least-squares conformal maps with packed islands).
//! It knows geometry only: no node, parameter or graph.
//!
//! * [`project`]: planar, cylindrical, spherical and box projections
//!   through a frame, with seam-continuous polygons (Houdini's UV
//!   Project / UV Texture).
//! * [`flatten`]: islands cut along seams, each flattened by LSCM
//!   ([`lscm`], with [`choose_pins`]), rescaled to its 3D area and packed
//!   into the unit square ([`pack_islands`]) (Houdini's UV Flatten and
//!   UV Layout in one).
//! * [`write_uv`], [`write_islands`]: the results as the vertex attribute
//!   `uv` (three floats, z = 0) and an island number per primitive.
//!
//! Every result is per vertex (`Vec<Vec3>` in vertex order, z = 0): a
//! point on a seam has one uv per side. Nothing here panics on real
//! input, and every parallel computation is deterministic (the same
//! input gives bit-identical output on any number of threads).
//!
//! ```
//! use geode_geo::glam::{Vec2, Vec3};
//! use geode_geo::primitives;
//! use geode_uv::*;
//!
//! // A cylindrical projection about Y, the frame 2 units tall.
//! let mut tube = primitives::tube(1.0, 2.0, 32, 4, false);
//! let options = ProjectOptions {
//!     projection: Projection::Cylindrical { axis: Axis::Y },
//!     frame: frame_from_trs(Vec3::new(0.0, 1.0, 0.0), Vec3::ZERO, Vec3::splat(2.0)),
//!     transform: UvTransform { scale: Vec2::new(2.0, 1.0), ..UvTransform::default() },
//! };
//! let uv = project(&tube, &options)?;
//! write_uv(&mut tube, UV, uv)?;
//!
//! // Flattened instead, cut open along the column of points 0, 32, 64...
//! let seams: Vec<[u32; 2]> = (0..4).map(|j| [j * 32, (j + 1) * 32]).collect();
//! let flat = flatten(&tube, &seams, &FlattenOptions::default(), &|| false)?;
//! assert_eq!(flat.island_count, 1);
//! write_uv(&mut tube, UV, flat.uv)?;
//! write_islands(&mut tube, "island", flat.prim_island)?;
//! # Ok::<(), UvError>(())
//! ```

mod attrib;
mod error;
pub mod flatten;
pub mod lscm;
pub mod pack;
pub mod project;
mod solver;

pub use attrib::{write_islands, write_uv, UV};
pub use error::UvError;
pub use flatten::{flatten, FlattenOptions, Flattened};
pub use lscm::{
    choose_pins, lscm, spectral, ConformalMethod, LinearSolver, LscmSolution, Pin, SolverOptions,
};
pub use pack::{pack_islands, PackOptions, Packed, Placement};
pub use project::{frame_from_trs, project, Axis, ProjectOptions, Projection, UvTransform};
