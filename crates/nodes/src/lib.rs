//! geode's node library: every node type, one file per family, each declaring
//! its parameters once (`NodeSpec`) for the cook, the docs and the CLI.

mod attributes;
mod bundles;
mod expr;
mod file;
mod flow;
mod frep;
mod frep_mesh;
mod groups;
mod mesh;
mod primitives;
mod transform;
mod util;

pub use expr::{Expr, ExprError};

use geode_op::Registry;

/// Every node type of the library.
pub fn registry() -> Registry {
    let mut r = Registry::new();
    file::register(&mut r);
    primitives::register(&mut r);
    transform::register(&mut r);
    flow::register(&mut r);
    frep::register(&mut r);
    frep_mesh::register(&mut r);
    attributes::register(&mut r);
    groups::register(&mut r);
    mesh::register(&mut r);
    bundles::register(&mut r);
    r
}
