//! geode's FRep polygoniser: a `geode-frep` field meshed into `geode-geo`
//! geometry by an octree over bricks of cells pruned by interval arithmetic
//! and feature-preserving dual contouring (QEF placement on sharp edges and
//! corners, walls and ridges thinner than a cell meshed on both sides
//! through the edges they cross twice, pinches split, adaptive
//! simplification within a tolerance); also sampling fields at points and measuring a mesh
//! against its field. Knows nothing of nodes, graphs or files.

pub mod adaptive;
mod boundary;
mod brick;
mod cell;
mod cluster;
mod coarse;
mod components;
mod crease;
mod double;
mod features;
mod flip;
mod inner_leaves;
mod lattice;
mod node_memo;
mod parts;
mod pinch;
pub mod polygonise;
mod qef;
mod recovery;
mod refine;
mod surface;
mod thin;

pub use polygonise::{polygonise, sample, MeshError, MeshEstimate, MeshOptions, MeshStats};
pub use surface::surface_distances;
