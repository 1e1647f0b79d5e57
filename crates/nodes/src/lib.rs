//! geode's node library: every node type, one file per family, each declaring
//! its parameters once (`NodeSpec`) for the cook, the docs and the CLI.

mod attach;
mod attribute_move;
mod attribute_noise;
mod attribute_spread;
mod attributes;
mod bundles;
mod curve_ops;
mod curves;
mod expr;
mod file;
mod flow;
mod frames;
mod frep;
mod frep_file;
mod frep_mesh;
mod frep_offset;
mod frep_polygonise;
mod frep_volume;
mod groups;
mod growth;
pub mod held;
mod hspline;
mod instancing;
mod measure;
mod mesh;
mod model_bevel;
mod model_boolean;
mod model_cut;
mod model_extrude;
mod model_reduce;
mod model_remesh;
mod model_surface;
mod model_wire;
mod network_file;
mod noise_params;
mod nurbs;
mod param_expr;
mod patches;
mod pieces;
mod primitives;
mod scatter;
mod skin;
mod sort;
mod subd;
mod thickness;
mod transform;
mod util;
mod uv;
mod wrangle;
mod wrangle_check;

pub use expr::{Expr, ExprError};
/// The wrangle language's function table, for the studio's snippet
/// completion (the node library is the one crate that uses geode-vex).
pub use geode_vex::{signatures as vex_signatures, Signature as VexSignature};
pub use patches::for_file;

use geode_op::Registry;

/// Every node type of the library.
pub fn registry() -> Registry {
    let mut r = Registry::new();
    file::register(&mut r);
    held::register(&mut r);
    primitives::register(&mut r);
    thickness::register(&mut r);
    transform::register(&mut r);
    flow::register(&mut r);
    frep::register(&mut r);
    frep_file::register(&mut r);
    frep_mesh::register(&mut r);
    frep_volume::register(&mut r);
    frep_offset::register(&mut r);
    frep_polygonise::register(&mut r);
    attributes::register(&mut r);
    attribute_move::register(&mut r);
    attribute_noise::register(&mut r);
    attribute_spread::register(&mut r);
    groups::register(&mut r);
    mesh::register(&mut r);
    pieces::register(&mut r);
    measure::register(&mut r);
    sort::register(&mut r);
    uv::register(&mut r);
    model_bevel::register(&mut r);
    model_boolean::register(&mut r);
    model_extrude::register(&mut r);
    model_reduce::register(&mut r);
    model_surface::register(&mut r);
    model_cut::register(&mut r);
    model_wire::register(&mut r);
    model_remesh::register(&mut r);
    bundles::register(&mut r);
    curves::register(&mut r);
    curve_ops::register(&mut r);
    frames::register(&mut r);
    instancing::register(&mut r);
    scatter::register(&mut r);
    growth::register(&mut r);
    subd::register(&mut r);
    nurbs::register(&mut r);
    patches::register(&mut r);
    hspline::register(&mut r);
    attach::register(&mut r);
    skin::register(&mut r);
    wrangle::register(&mut r);
    r.set_expressions(std::sync::Arc::new(param_expr::VexExpressions));
    r
}
