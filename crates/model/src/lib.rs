//! geode's modelling kernel: operations on polygon meshes that the
//! modelling nodes call (booleans, and the rest of the modelling family).
//! It knows geometry only: no node, parameter or graph.

pub mod boolean;
pub mod bound;
mod carry;
pub mod clip;
pub mod deform;
mod error;
pub mod extrude;
pub mod fill;
pub mod hull;
pub mod mirror;
mod rebuild;
pub mod remesh;
pub mod revolve;
pub mod smooth;

pub use error::ModelError;
