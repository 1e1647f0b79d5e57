//! Spline patches in networks: the convert node (patches to polygons at a
//! level of detail per knot span) and the conversion `geode cook` applies
//! before writing a format that holds only meshes.

use std::borrow::Cow;
use std::path::Path;

use geode_geo::{GeoError, Geometry, KnotVector, PrimKind};
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};
use geode_spline::bspline::patch::convert_patches;

use crate::util::{geometry, input};

/// Knot spans in a direction's domain.
fn spans(k: &KnotVector) -> usize {
    let o = k.order as usize;
    k.knots[o - 1..=k.knots.len() - o]
        .windows(2)
        .filter(|w| w[1] > w[0])
        .count()
}

/// Every patch as polygons, `lod` quads per knot span each way (the finest
/// span count among the patches sets the samples, so patches match).
pub fn patches_to_polygons(g: &Geometry, lod: usize) -> Result<Geometry, GeoError> {
    let (mut su, mut sv) = (1, 1);
    for prim in g.prims_where(|k| matches!(k, PrimKind::Patch(_))) {
        let b = g.patch_basis(prim).expect("a patch");
        su = su.max(spans(&b.u));
        sv = sv.max(spans(&b.v));
    }
    convert_patches(g, [su * lod + 1, sv * lod + 1])
}

/// What `geode cook` writes to `path`: `g`, with patches as polygons unless
/// the format keeps them (USD).
pub fn for_file<'a>(g: &'a Geometry, path: &Path) -> Result<Cow<'a, Geometry>, GeoError> {
    let keeps = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("usda"));
    if keeps || !g.has_patches() {
        Ok(Cow::Borrowed(g))
    } else {
        patches_to_polygons(g, 8).map(Cow::Owned)
    }
}

const CONVERT_LEVEL_OF_DETAIL: P = P::new(
    "level_of_detail",
    "Level of detail",
    T::Int,
    D::Int(8),
    "Quads per knot span in each direction.",
)
.range(1.0, 256.0);

static CONVERT: NodeSpec = NodeSpec::new(
    "convert",
    "Convert",
    "spline",
    "Turns spline patches into polygons: quads with exact normals N and uv, `level_of_detail` quads per knot span each way, each carrying its patch's primitive attributes. Other primitives pass through.",
    &[geometry_input("geometry")],
    &[
        CONVERT_LEVEL_OF_DETAIL,
    ],
);

fn cook_convert(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let lod = p.int(&CONVERT_LEVEL_OF_DETAIL)?.max(1) as usize;
    // A patch of n control points has fewer than n knot spans: n x lod^2 quads at most.
    let controls: f64 = (0..g.num_prims())
        .filter(|&i| matches!(g.prim_kind(i), geode_geo::PrimKind::Patch(_)))
        .map(|i| g.prim_vertex_range(i).len() as f64)
        .sum();
    let quads = controls * (lod * lod) as f64;
    crate::util::reserve_mesh(ctx, &CONVERT_LEVEL_OF_DETAIL, quads, 4.0 * quads, quads)?;
    geometry(patches_to_polygons(g, lod).map_err(|e| ctx.kernel(e))?)
}

pub fn register(r: &mut Registry) {
    r.node(&CONVERT, cook_convert);
}
