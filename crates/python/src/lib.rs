//! The native half of Python's `geode` package: networks built, edited and cooked through geode's graph crate, geometry handed to numpy without copying.
//!
//! The package's Python half (`python/geode/`) wraps these in the
//! documented classes (`Network`, `Node`, `Parm`, `Geometry`).

mod cancel;
mod errors;
mod geometry;
mod json;
mod network;
mod picture;
mod state;

use pyo3::prelude::*;

#[pymodule]
fn _geode(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<network::PyNetwork>()?;
    m.add_class::<geometry::PyGeometry>()?;
    errors::register(m)?;
    m.add_function(wrap_pyfunction!(node_types, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

/// Every node type: name, category and help, as `geode nodes` lists them.
#[pyfunction]
fn node_types() -> Vec<(String, String, String)> {
    geode_graph::node_specs(state::registry())
        .into_iter()
        .map(|s| (s.name.to_owned(), s.category.to_owned(), s.help.to_owned()))
        .collect()
}
