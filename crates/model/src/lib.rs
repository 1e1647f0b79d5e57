//! geode's modelling kernel: operations on polygon meshes that the
//! modelling nodes call (booleans, and the rest of the modelling family).
//! It knows geometry only: no node, parameter or graph.

pub mod boolean;
mod carry;
pub mod clip;
mod error;
pub mod fill;
pub mod hull;
pub mod mirror;
pub mod revolve;

pub use error::ModelError;
