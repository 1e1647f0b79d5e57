//! geode's growth kernel: seeded scattering in solids (any inside test; a
//! mesh's winding number provided) and on surfaces, uniform or blue noise,
//! and space-colonization growth of branching structures. Depends on
//! `geode-geo` only.

pub mod colonize;
pub mod eliminate;
pub mod inside;
pub mod scatter;

pub use colonize::{colonize, ColonizeError, ColonizeOptions, Tree};
pub use inside::InsideTest;
pub use scatter::ScatterError;
