//! Catmull-Clark subdivision as a node, reading OpenSubdiv's tags as the
//! OBJ reader stores them (creases, corners, holes, boundary and crease
//! method), each overridable here.

use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};
use geode_spline::subd::{
    subdivide, BoundaryMode, CreaseMethod, FVarLinear, SubdError, SubdOptions,
};

use crate::util::{count_text, geometry, input};
use geode_geo::Geometry;

const SUBDIVIDE_LEVELS: P = P::new(
    "levels",
    "Levels",
    T::Int,
    D::Int(2),
    "Refinement levels (each quadruples the faces).",
)
.range(0.0, 8.0);
const SUBDIVIDE_BOUNDARY: P = P::new(
    "boundary",
    "Boundary",
    T::Menu(&["from_geometry", "none", "edge_only", "edge_and_corner"]),
    D::Str("from_geometry"),
    "How boundaries interpolate: from the subd_boundary tag (edge only when absent), or forced.",
);
const SUBDIVIDE_CREASE_METHOD: P = P::new("crease_method", "Crease method", T::Menu(&["from_geometry", "uniform", "chaikin"]), D::Str("from_geometry"), "How semi-sharp creases decay: from the subd_creasemethod tag (uniform when absent), or forced.");
const SUBDIVIDE_UV_INTERPOLATION: P = P::new("uv_interpolation", "UV interpolation", T::Menu(&["from_geometry", "none", "corners_only", "corners_plus1", "corners_plus2", "boundaries", "all"]), D::Str("from_geometry"), "OpenSubdiv's face-varying rules for vertex attributes (uv): smooth everywhere (none), pinning island corners, also junctions of three or more islands (plus1), also darts and concave corners (plus2), pinning island boundaries (boundaries: outlines keep, insides smooth), or bilinear (all). From the subd_fvar_boundary tag, boundaries when absent.");
const SUBDIVIDE_LIMIT: P = P::new(
    "limit",
    "Push to limit",
    T::Toggle,
    D::Toggle(false),
    "Move points to the limit surface and write limit normals N.",
);

static SUBDIVIDE: NodeSpec = NodeSpec::new(
    "subdivide",
    "Subdivide",
    "mesh",
    "Catmull-Clark subdivision with OpenSubdiv's rules: semi-sharp creases (vertex attribute creaseweight, per edge), corners (point attribute cornerweight), holes (primitive attribute subd_hole), boundary interpolation and uniform or Chaikin crease decay. Point attributes are refined like P, vertex attributes (uv) by OpenSubdiv's face-varying rules (seams kept), primitive attributes inherited. With `limit`, points move to the limit surface and get exact limit normals N, and vertex attributes (uv) move to their limit too.",
    &[geometry_input("mesh")],
    &[
        SUBDIVIDE_LEVELS,
        SUBDIVIDE_BOUNDARY,
        SUBDIVIDE_CREASE_METHOD,
        SUBDIVIDE_UV_INTERPOLATION,
        SUBDIVIDE_LIMIT,
    ],
);

fn cook_subdivide(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    reserve_refinement(ctx, g, p.int(&SUBDIVIDE_LEVELS)?)?;
    let opts = SubdOptions {
        levels: p.int(&SUBDIVIDE_LEVELS)? as u32,
        boundary: match p.string(&SUBDIVIDE_BOUNDARY)? {
            "none" => Some(BoundaryMode::None),
            "edge_only" => Some(BoundaryMode::EdgeOnly),
            "edge_and_corner" => Some(BoundaryMode::EdgeAndCorner),
            _ => None,
        },
        crease: match p.string(&SUBDIVIDE_CREASE_METHOD)? {
            "uniform" => Some(CreaseMethod::Uniform),
            "chaikin" => Some(CreaseMethod::Chaikin),
            _ => None,
        },
        fvar: match p.string(&SUBDIVIDE_UV_INTERPOLATION)? {
            "none" => Some(FVarLinear::None),
            "corners_only" => Some(FVarLinear::CornersOnly),
            "corners_plus1" => Some(FVarLinear::CornersPlus1),
            "corners_plus2" => Some(FVarLinear::CornersPlus2),
            "boundaries" => Some(FVarLinear::Boundaries),
            "all" => Some(FVarLinear::All),
            _ => None,
        },
        limit: p.toggle(&SUBDIVIDE_LIMIT)?,
    };
    let cancel = || ctx.cancel.is_cancelled();
    let out = subdivide(g, &opts, &cancel).map_err(|e| match e {
        SubdError::NotPolygon(prim) => ctx.input_error(format!(
            "input 1: primitive {prim} is not a polygon; subdivide needs a polygon mesh"
        )),
        other => ctx.kernel(other),
    })?;
    geometry(out)
}

/// Peak bytes per quad of the finest level while refining (the topology of
/// the last two levels, positions and attributes, the output geometry),
/// measured on catmark_car at levels 3-5: about 375, rounded up.
const BYTES_PER_REFINED_QUAD: f64 = 400.0;

/// Refuses a refinement the memory budget cannot hold: an n-gon becomes n
/// quads at level 1, and every quad four at each further level.
fn reserve_refinement(ctx: &CookContext, g: &Geometry, levels: i64) -> Result<(), CookError> {
    if levels <= 0 {
        return Ok(());
    }
    let quads = g.num_vertices() as f64 * 4f64.powi(levels as i32 - 1);
    ctx.reserve(
        &SUBDIVIDE_LEVELS,
        quads * BYTES_PER_REFINED_QUAD,
        &format!("{} quads at level {levels}", count_text(quads)),
    )
}

pub fn register(r: &mut Registry) {
    r.node(&SUBDIVIDE, cook_subdivide);
}
