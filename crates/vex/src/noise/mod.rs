//! Seeded noise kernels, the same on every machine: Perlin's improved
//! gradient noise (`noise`, `snoise`, `curlnoise`), his original 1985
//! noise (`onoise`), simplex noise (`xnoise`) and Worley's cellular noise
//! (`wnoise`). Not Houdini's exact numbers: the same kinds of field.

mod perlin;
mod simplex;
mod worley;

pub use perlin::{curl, curl2d, original, perlin};
pub use simplex::simplex;
pub use worley::{worley, Cell};
