//! Curve generators: line, circle or arc, helix, torus knot, and a curve
//! through the input's points (polyline, Catmull-Rom, B-spline). Each
//! writes the exact unit tangent as point attribute `T`, which polyframe
//! uses for fourth-order frames.

use geode_curve::polyline::glam_d::DVec3;
use geode_curve::shapes::{self, Sampled};
use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, AttribData, Attribute, Geometry, PrimKind, TypeInfo};
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamName, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{geometry, input, vec3};

/// Curves as geometry: points with `T`, one polyline (open) or polygon
/// (closed) per curve.
pub(crate) fn curves_geometry(
    curves: &[Sampled],
    offset: Vec3,
) -> Result<Geometry, geode_geo::GeoError> {
    let mut positions = Vec::new();
    let mut tangents = Vec::new();
    let (mut counts, mut kinds) = (Vec::new(), Vec::new());
    for c in curves
        .iter()
        .filter(|c| c.points.len() >= if c.closed { 3 } else { 2 })
    {
        positions.extend(c.points.iter().map(|p| p.as_vec3() + offset));
        tangents.extend(c.tangents.iter().map(|t| t.as_vec3()));
        counts.push(c.points.len() as u32);
        kinds.push(if c.closed {
            PrimKind::Polygon
        } else {
            PrimKind::Polyline
        });
    }
    let n = positions.len() as u32;
    let mut g = Geometry::from_prims(positions, (0..n).collect(), &counts, kinds)?;
    g.set_attrib(
        AttribClass::Point,
        "T",
        Attribute::from_data(AttribData::Vec3(tangents), TypeInfo::Vector),
    )?;
    Ok(g)
}

fn finish(ctx: &CookContext, c: Sampled, p: &Params) -> Result<Value, CookError> {
    let g = curves_geometry(&[c], vec3(p, &CENTER)?).map_err(|e| ctx.kernel(e))?;
    geometry(g)
}

fn count(p: &Params, name: &(impl ParamName + ?Sized)) -> Result<usize, CookError> {
    Ok(p.int(name)?.clamp(2, 1 << 24) as usize)
}

const CENTER: P = P::new(
    "center",
    "Center",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "Offset of the whole curve.",
);

const LINE_START: P = P::new("start", "Start", T::Vec3, D::Vec3([0.0; 3]), "First point.");
const LINE_END: P = P::new(
    "end",
    "End",
    T::Vec3,
    D::Vec3([0.0, 1.0, 0.0]),
    "Last point.",
);
const LINE_POINTS: P =
    P::new("points", "Points", T::Int, D::Int(10), "Point count.").range(2.0, 16_777_216.0);

static LINE: NodeSpec = NodeSpec::new(
    "curve_line",
    "Line",
    "curve",
    "A straight polyline from start to end.",
    &[],
    &[LINE_START, LINE_END, LINE_POINTS, CENTER],
);

fn cook_line(ctx: &CookContext, _: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let (a, b) = (
        vec3(p, &LINE_START)?.as_dvec3(),
        vec3(p, &LINE_END)?.as_dvec3(),
    );
    finish(ctx, shapes::line(a, b, count(p, &LINE_POINTS)?), p)
}

const RADIUS: P = P::new("radius", "Radius", T::Float, D::Float(1.0), "Radius.").at_least(0.0);
const CIRCLE_START_ANGLE: P = P::new(
    "start_angle",
    "Start angle",
    T::Float,
    D::Float(0.0),
    "Degrees from +X.",
);
const CIRCLE_END_ANGLE: P = P::new(
    "end_angle",
    "End angle",
    T::Float,
    D::Float(360.0),
    "Degrees from +X.",
);
const CIRCLE_POINTS: P =
    P::new("points", "Points", T::Int, D::Int(32), "Point count.").range(2.0, 16_777_216.0);

static CIRCLE: NodeSpec = NodeSpec::new(
    "curve_circle",
    "Circle",
    "curve",
    "A circle or arc in the XZ plane, counter-clockwise seen from +Y; a full turn is a closed curve.",
    &[],
    &[
        RADIUS,
        CIRCLE_START_ANGLE,
        CIRCLE_END_ANGLE,
        CIRCLE_POINTS,
        CENTER,
    ],
);

fn cook_circle(ctx: &CookContext, _: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let (a, b) = (
        p.float(&CIRCLE_START_ANGLE)?.to_radians(),
        p.float(&CIRCLE_END_ANGLE)?.to_radians(),
    );
    if a == b {
        return Err(ctx.param_error(
            &CIRCLE_END_ANGLE,
            "the arc has no extent (start and end angles are equal)",
        ));
    }
    finish(
        ctx,
        shapes::arc(p.float(&RADIUS)?, a, b, count(p, &CIRCLE_POINTS)?),
        p,
    )
}

const HELIX_PITCH: P = P::new("pitch", "Pitch", T::Float, D::Float(0.5), "Rise per turn.");
const HELIX_TURNS: P = P::new(
    "turns",
    "Turns",
    T::Float,
    D::Float(3.0),
    "Number of turns.",
)
.at_least(0.001);
const HELIX_POINTS: P =
    P::new("points", "Points", T::Int, D::Int(200), "Point count.").range(2.0, 16_777_216.0);

static HELIX: NodeSpec = NodeSpec::new(
    "curve_helix",
    "Helix",
    "curve",
    "A helix rising along +Y.",
    &[],
    &[RADIUS, HELIX_PITCH, HELIX_TURNS, HELIX_POINTS, CENTER],
);

fn cook_helix(ctx: &CookContext, _: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let c = shapes::helix(
        p.float(&RADIUS)?,
        p.float(&HELIX_PITCH)?,
        p.float(&HELIX_TURNS)?,
        count(p, &HELIX_POINTS)?,
    );
    finish(ctx, c, p)
}

const KNOT_P: P = P::new("p", "P", T::Int, D::Int(2), "Turns around the axis.").range(1.0, 1000.0);
const KNOT_Q: P = P::new("q", "Q", T::Int, D::Int(3), "Turns through the hole.").range(0.0, 1000.0);
const KNOT_MAJOR_RADIUS: P = P::new(
    "major_radius",
    "Major radius",
    T::Float,
    D::Float(1.0),
    "Radius of the torus.",
)
.at_least(0.0);
const KNOT_MINOR_RADIUS: P = P::new(
    "minor_radius",
    "Minor radius",
    T::Float,
    D::Float(0.4),
    "Radius of its tube.",
)
.at_least(0.0);
const KNOT_POINTS: P =
    P::new("points", "Points", T::Int, D::Int(300), "Point count.").range(3.0, 16_777_216.0);

static KNOT: NodeSpec = NodeSpec::new(
    "curve_knot",
    "Torus Knot",
    "curve",
    "A closed (p, q) torus knot around +Y: p turns around the axis, q through the hole; (2, 3) is the trefoil.",
    &[],
    &[
        KNOT_P,
        KNOT_Q,
        KNOT_MAJOR_RADIUS,
        KNOT_MINOR_RADIUS,
        KNOT_POINTS,
        CENTER,
    ],
);

fn cook_knot(ctx: &CookContext, _: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let c = shapes::torus_knot(
        p.int(&KNOT_P)? as u32,
        p.int(&KNOT_Q)? as u32,
        p.float(&KNOT_MAJOR_RADIUS)?,
        p.float(&KNOT_MINOR_RADIUS)?,
        count(p, &KNOT_POINTS)?,
    );
    finish(ctx, c, p)
}

const INTERPOLATE_METHOD: P = P::new("method", "Method", T::Menu(&["polyline", "catmull_rom", "bspline"]), D::Str("catmull_rom"), "polyline: the points as they are; catmull_rom: a centripetal spline through them; bspline: a cubic B-spline with them as control points (clamped to the ends when open).");
const INTERPOLATE_CLOSED: P = P::new(
    "closed",
    "Closed",
    T::Toggle,
    D::Toggle(false),
    "Close a curve made from loose points (curves keep their own).",
);
const INTERPOLATE_SAMPLES: P = P::new(
    "samples",
    "Samples per segment",
    T::Int,
    D::Int(8),
    "Points per span of the spline.",
)
.range(1.0, 10_000.0);
const INTERPOLATE_ALPHA: P = P::new(
    "alpha",
    "Catmull-Rom alpha",
    T::Float,
    D::Float(0.5),
    "0 uniform, 0.5 centripetal (no cusps or loops), 1 chordal.",
)
.range(0.0, 1.0);

static INTERPOLATE: NodeSpec = NodeSpec::new(
    "curve_interpolate",
    "Curve Through Points",
    "curve",
    "A curve through (or, as a B-spline, guided by) points: each curve of the input, or all its points in order when it has none.",
    &[geometry_input("points")],
    &[
        INTERPOLATE_METHOD,
        INTERPOLATE_CLOSED,
        INTERPOLATE_SAMPLES,
        INTERPOLATE_ALPHA,
    ],
);

fn cook_interpolate(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let pos = g.positions();
    let mut sources: Vec<(Vec<DVec3>, bool)> = geode_curve::curves(g)
        .into_iter()
        .map(|c| {
            (
                c.points
                    .iter()
                    .map(|&i| pos[i as usize].as_dvec3())
                    .collect(),
                c.closed,
            )
        })
        .collect();
    if sources.is_empty() {
        sources.push((
            pos.iter().map(|p| p.as_dvec3()).collect(),
            p.toggle(&INTERPOLATE_CLOSED)?,
        ));
    }
    let per = p.int(&INTERPOLATE_SAMPLES)? as usize;
    let alpha = p.float(&INTERPOLATE_ALPHA)?;
    let method = p.string(&INTERPOLATE_METHOD)?;
    let mut out = Vec::new();
    for (pts, closed) in sources {
        if pts.len() < 2 {
            continue;
        }
        out.push(match method {
            "polyline" => {
                let t = geode_curve::tangents(&pts, closed, geode_curve::TangentMode::Central);
                Sampled {
                    points: pts,
                    tangents: t,
                    closed,
                }
            }
            "bspline" => shapes::bspline(&pts, closed, per),
            _ => shapes::catmull_rom(&pts, closed, per, alpha),
        });
    }
    if out.is_empty() {
        return Err(ctx.input_error("input 1 has fewer than 2 points to pass a curve through"));
    }
    geometry(curves_geometry(&out, Vec3::ZERO).map_err(|e| ctx.kernel(e))?)
}

pub fn register(r: &mut Registry) {
    r.node(&LINE, cook_line);
    r.node(&CIRCLE, cook_circle);
    r.node(&HELIX, cook_helix);
    r.node(&KNOT, cook_knot);
    r.node(&INTERPOLATE, cook_interpolate);
}
