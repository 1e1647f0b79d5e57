//! geode's attribute and query kernels: moving values between element
//! classes and between meshes, smoothing them over a surface, measuring
//! elements and pieces, sorting. It knows geometry only: no node, parameter
//! or graph.
mod error;
pub mod kdtree;
pub mod promote;
pub mod relation;

pub use error::AttribError;
pub mod blur;
pub mod measure;
pub mod transfer;
