//! geode's modelling kernel: operations on polygon meshes that the
//! modelling nodes call (booleans, and the rest of the modelling family).
//! It knows geometry only: no node, parameter or graph.

pub mod bevel;
pub mod boolean;
pub mod bound;
mod carry;
pub mod clip;
pub mod deform;
pub mod divide;
pub mod edge_divide;
mod error;
pub mod extrude;
pub mod fill;
pub mod hull;
pub mod mirror;
pub mod polywire;
mod rebuild;
pub mod reduce;
pub mod remesh;
pub mod revolve;
pub mod smooth;

pub use error::ModelError;
