//! Query nodes: measure (area, perimeter, volume per primitive, piece or in
//! total; mean and Gaussian curvature per point) and ray (points projected
//! onto a second geometry).

use geode_attrib::measure::{self, per_piece};
use geode_geo::ops::{self, Connect};
use geode_geo::{AttribClass, AttribData, Attribute, Geometry, TypeInfo};
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{attribute_name, geometry, input_owned};

const MEASURE_WHAT: P = P::new(
    "measure",
    "Measure",
    T::Menu(&["area", "perimeter", "volume", "mean_curvature", "gaussian_curvature"]),
    D::Str("area"),
    "Area, perimeter (a polyline's length) or enclosed volume of primitives; or the mean or Gaussian curvature at each point (Meyer et al.'s discrete operators; 1/r and 1/r² on a sphere of radius r).",
);
const MEASURE_SCOPE: P = P::new(
    "accumulate",
    "Accumulate",
    T::Menu(&["primitive", "piece", "total"]),
    D::Str("primitive"),
    "Area, perimeter and volume: each primitive's own, its piece's sum (on every primitive of the piece), or the sum over everything (a detail attribute). A volume is a closed piece's; a primitive's is its share (the cone from the origin).",
);
const MEASURE_PIECE: P = P::new(
    "piece_attribute",
    "Piece attribute",
    T::String,
    D::Str(""),
    "Pieces by this primitive attribute's values (e.g. `name`, `class`); empty: by connectivity (primitives sharing points, as connectivity and for_each have them).",
);
const MEASURE_NAME: P = P::new(
    "name",
    "Attribute",
    T::String,
    D::Str(""),
    "The output attribute; empty names it after the measure (`area`, `perimeter`, `volume`, `curvature`).",
);

static MEASURE: NodeSpec = NodeSpec::new(
    "measure",
    "Measure",
    "attribute",
    "Measures primitives, pieces or the whole (area, perimeter, volume) or the surface's curvature at each point (Houdini's Measure).",
    &[geometry_input("geometry")],
    &[MEASURE_WHAT, MEASURE_SCOPE, MEASURE_PIECE, MEASURE_NAME],
);

fn cook_measure(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input_owned(ctx, inputs, 0)?;
    let what = p.string(&MEASURE_WHAT)?;
    let name = match p.string(&MEASURE_NAME)? {
        "" if what.ends_with("curvature") => "curvature",
        "" => what,
        n => n,
    };
    attribute_name(ctx, &MEASURE_NAME, name)?;
    if what.ends_with("curvature") {
        let c = measure::curvature(&g, &ctx.cancel_fn())
            .map_err(|e| crate::attribute_move::attrib_error(ctx, &MEASURE_WHAT, name, e))?;
        let values = if what == "mean_curvature" {
            c.mean
        } else {
            c.gaussian
        };
        return store(ctx, g, AttribClass::Point, name, values);
    }
    let per_prim: Vec<f64> = match what {
        "perimeter" => measure::prim_perimeters(&g)
            .into_iter()
            .map(f64::from)
            .collect(),
        "volume" => {
            warn_open(ctx, &g);
            measure::prim_volumes(&g)
        }
        _ => measure::prim_areas(&g).into_iter().map(f64::from).collect(),
    };
    ctx.check()?;
    match p.string(&MEASURE_SCOPE)? {
        "total" => {
            let total = vec![per_prim.iter().sum::<f64>() as f32];
            store(ctx, g, AttribClass::Detail, name, total)
        }
        "piece" => {
            let pieces = pieces(ctx, p, &g)?;
            let values = per_piece(&per_prim, &pieces)
                .into_iter()
                .map(|v| v as f32)
                .collect();
            store(ctx, g, AttribClass::Primitive, name, values)
        }
        _ => {
            let values = per_prim.into_iter().map(|v| v as f32).collect();
            store(ctx, g, AttribClass::Primitive, name, values)
        }
    }
}

/// Each primitive's piece: by connectivity, or by an attribute's values
/// (numbered in order of first appearance).
fn pieces(ctx: &CookContext, p: &Params, g: &Geometry) -> Result<Vec<u32>, CookError> {
    let by = p.string(&MEASURE_PIECE)?;
    if by.is_empty() {
        return Ok(ops::connectivity(g, Connect::SharedPoint, None).of_prim);
    }
    let attr = crate::util::attribute_of(ctx, &MEASURE_PIECE, g, AttribClass::Primitive, by)?;
    Ok(ops::value_classes(attr.data()).0)
}

/// Warns when polygons have open edges: the volume of an open piece is its
/// polygons' cones from the origin, not an enclosed volume.
fn warn_open(ctx: &CookContext, g: &Geometry) {
    let open = g.topology().boundary_edges().len();
    if open > 0 {
        ctx.warn(format!(
            "{open} open edges: the geometry is not closed, so its volume is not an enclosed one (close it, e.g. with polyfill)"
        ));
    }
    let packed = (0..g.num_prims())
        .filter(|&i| Geometry::is_packed(g.prim_kind(i)))
        .count();
    if packed > 0 {
        ctx.warn(format!(
            "{packed} packed primitives measure 0: unpack them first"
        ));
    }
}

fn store(
    ctx: &CookContext,
    mut g: Geometry,
    c: AttribClass,
    name: &str,
    values: Vec<f32>,
) -> Result<Value, CookError> {
    g.set_attrib(
        c,
        name,
        Attribute::from_data(AttribData::Float(values), TypeInfo::None),
    )
    .map_err(|e| ctx.kernel_at(&MEASURE_NAME, e))?;
    geometry(g)
}

pub fn register(r: &mut Registry) {
    r.node(&MEASURE, cook_measure);
    r.node(&RAY, cook_ray);
}

const RAY_GROUP: P = P::new(
    "group",
    "Group",
    T::String,
    D::Str(""),
    "The points to project (a group pattern); empty for all.",
);
const RAY_COLLISION_GROUP: P = P::new(
    "collision_group",
    "Collision group",
    T::String,
    D::Str(""),
    "The second input's primitives to hit (a group pattern); empty for all.",
);
const RAY_METHOD: P = P::new(
    "method",
    "Method",
    T::Menu(&["project", "minimum"]),
    D::Str("project"),
    "Cast a ray from each point, or go to the nearest point of the surface (minimum distance).",
);
const RAY_DIRECTION: P = P::new(
    "direction_from",
    "Direction from",
    T::Menu(&["normal", "vector"]),
    D::Str("normal"),
    "Rays along each point's normal (point N, else the surface's), or along one vector.",
);
const RAY_VECTOR: P = P::new(
    "direction",
    "Direction",
    T::Vec3,
    D::Vec3([0.0, -1.0, 0.0]),
    "The rays' direction when it is one vector.",
);
const RAY_HIT: P = P::new(
    "hit",
    "Hit",
    T::Menu(&["first", "farthest"]),
    D::Str("first"),
    "The nearest hit along the ray, or the last one within the maximum distance.",
);
const RAY_REVERSE: P = P::new(
    "reverse",
    "Reverse rays",
    T::Toggle,
    D::Toggle(false),
    "Cast against the direction.",
);
const RAY_LIMIT: P = P::new(
    "limit",
    "Limit distance",
    T::Toggle,
    D::Toggle(false),
    "Ignore hits farther than the maximum distance. With minimum distance, it also bounds the search: a point far from a dense surface (inside a closed shape, where every triangle is nearly as close as the nearest) costs up to a millisecond unlimited, microseconds limited.",
);
const RAY_MAX: P = P::new(
    "max_distance",
    "Max distance",
    T::Float,
    D::Float(1.0),
    "The farthest a hit may be, when limited.",
)
.at_least(0.0);
const RAY_MOVE: P = P::new(
    "transform",
    "Transform points",
    T::Toggle,
    D::Toggle(true),
    "Move each point that hits to its hit (scaled); off: only write the hit attributes.",
);
const RAY_SCALE: P = P::new(
    "scale",
    "Scale",
    T::Float,
    D::Float(1.0),
    "How far toward its hit a point moves (1: onto it).",
);
const RAY_ATTRIBUTES: P = P::new(
    "hit_attributes",
    "Hit attributes",
    T::Toggle,
    D::Toggle(true),
    "Write point `hitprim` (the primitive hit, -1 for none), `hitprimuv` (its parametric uv, as the wrangle's xyzdist and primuv read it) and `dist` (the distance, -1 for none).",
);

static RAY: NodeSpec = NodeSpec::new(
    "ray",
    "Ray",
    "attribute",
    "Projects points onto a second geometry (Houdini's Ray): along their normals or a vector (first or farthest hit), or to the nearest surface point; writes the hit primitive, its parametric uv and the distance.",
    &[
        geometry_input("geometry"),
        geode_op::InputSpec { name: "collision", ty: geode_op::PortType::Geometry, required: true },
    ],
    &[
        RAY_GROUP,
        RAY_COLLISION_GROUP,
        RAY_METHOD,
        RAY_DIRECTION,
        RAY_VECTOR,
        RAY_HIT,
        RAY_REVERSE,
        RAY_LIMIT,
        RAY_MAX,
        RAY_MOVE,
        RAY_SCALE,
        RAY_ATTRIBUTES,
    ],
);

/// A point's hit: primitive, parametric uv, point, distance.
type Found = Option<(u32, f32, f32, geode_geo::glam::Vec3, f32)>;

fn cook_ray(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    use geode_geo::glam::Vec3;
    use geode_geo::ops::prim_surface::PrimSurface;
    use rayon::prelude::*;
    let mut g = input_owned(ctx, inputs, 0)?;
    let collision = crate::util::input(ctx, inputs, 1)?;
    let selected = crate::util::group_param(ctx, p, &RAY_GROUP, &g, AttribClass::Point)?;
    let prims: Vec<usize> = match crate::util::group_param(
        ctx,
        p,
        &RAY_COLLISION_GROUP,
        collision,
        AttribClass::Primitive,
    )? {
        Some(grp) => grp.members().collect(),
        None => (0..collision.num_prims()).collect(),
    };
    let surface = PrimSurface::new(collision, &prims);
    ctx.check()?;
    let max = if p.toggle(&RAY_LIMIT)? {
        p.float(&RAY_MAX)? as f32
    } else {
        f32::INFINITY
    };
    let minimum = p.string(&RAY_METHOD)? == "minimum";
    let farthest = p.string(&RAY_HIT)? == "farthest";
    let sign = if p.toggle(&RAY_REVERSE)? { -1.0 } else { 1.0 };
    let directions: Vec<Vec3> = if p.string(&RAY_DIRECTION)? == "vector" {
        let d = crate::util::vec3(p, &RAY_VECTOR)?.normalize_or_zero();
        if d == Vec3::ZERO && !minimum {
            return Err(ctx.param_error(
                &RAY_VECTOR,
                "the direction is zero (or not finite): rays need a direction",
            ));
        }
        vec![d * sign; g.num_points()]
    } else {
        let n = match g.attrib(AttribClass::Point, "N").map(|a| a.data()) {
            Some(AttribData::Vec3(n)) => n.clone(),
            _ => geode_geo::ops::point_normals(&g),
        };
        n.into_iter()
            .map(|d| d.normalize_or_zero() * sign)
            .collect()
    };
    if farthest && !max.is_finite() && !minimum {
        return Err(ctx.param_error(
            &RAY_HIT,
            "the farthest hit needs a limited distance: turn on Limit distance",
        ));
    }
    let positions = g.positions().to_vec();
    let found: Vec<Found> = positions
        .par_iter()
        .enumerate()
        .map(|(i, &q)| {
            // A minimum-distance query far from a dense surface can take
            // a millisecond: poll before each (one atomic load; the
            // result is dropped once cancelled).
            if ctx.cancel.is_cancelled() {
                return None;
            }
            if selected.as_ref().is_some_and(|s| !s.contains(i)) {
                return None;
            }
            if minimum {
                let c = surface.bvh.closest(q, max)?;
                let (prim, u, v) = surface.locate(collision, c.triangle, c.point, c.u, c.v);
                return Some((prim, u, v, c.point, c.dist2.sqrt()));
            }
            let d = directions[i];
            if d == Vec3::ZERO {
                return None;
            }
            let (hit, point) = surface.hit(q, d, 0.0, max, farthest)?;
            let (prim, u, v) = surface.locate(collision, hit.triangle, point, hit.u, hit.v);
            Some((prim, u, v, point, hit.t))
        })
        .collect();
    ctx.check()?;
    if p.toggle(&RAY_MOVE)? {
        let scale = p.float(&RAY_SCALE)? as f32;
        let moved: Vec<Vec3> = positions
            .iter()
            .zip(&found)
            .map(|(&q, f)| f.map_or(q, |(_, _, _, hit, _)| q + (hit - q) * scale))
            .collect();
        g.set_positions(moved);
    }
    if p.toggle(&RAY_ATTRIBUTES)? {
        let prim: Vec<i32> = found.iter().map(|f| f.map_or(-1, |h| h.0 as i32)).collect();
        let uv: Vec<Vec3> = found
            .iter()
            .map(|f| f.map_or(Vec3::ZERO, |h| Vec3::new(h.1, h.2, 0.0)))
            .collect();
        let dist: Vec<f32> = found.iter().map(|f| f.map_or(-1.0, |h| h.4)).collect();
        for (name, data) in [
            ("hitprim", AttribData::Int(prim)),
            ("hitprimuv", AttribData::Vec3(uv)),
            ("dist", AttribData::Float(dist)),
        ] {
            g.set_attrib(
                AttribClass::Point,
                name,
                Attribute::from_data(data, TypeInfo::None),
            )
            .map_err(|e| ctx.kernel_at(&RAY_ATTRIBUTES, e))?;
        }
    }
    geometry(g)
}
