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
    m.add_function(wrap_pyfunction!(node_type, m)?)?;
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

/// One node type's declaration as the studio reads it: label, category,
/// help, inputs, output, and every parameter's type, default, range, menu
/// items and help.
#[pyfunction]
fn node_type<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
    let spec = geode_graph::node_spec(state::registry(), name).ok_or_else(|| {
        let near = geode_graph::container::closest_types(state::registry(), name);
        let hint = if near.is_empty() {
            String::new()
        } else {
            format!(" (did you mean {}?)", near.join(", "))
        };
        errors::not_found("node type", name, None, format!("no such node type{hint}"))
    })?;
    json::to_py(py, &geode_graph::catalogue::spec_json(spec))
}
