//! Frames and sweeps: polyframe writes a rotation-minimizing frame per
//! curve point (T, N, B and `orient`); sweep turns curves into quad tubes
//! with a circle or any section curve, radius by attribute and ramp, caps
//! and UVs.

use geode_curve::frames::{self, Frame, FrameMethod, TangentMode};
use geode_curve::polyline::glam_d::{DQuat, DVec2, DVec3};
use geode_curve::sweep::Tube;
use geode_curve::{curves, sweep, Curve, SweepOptions};
use geode_geo::glam::{Quat, Vec3};
use geode_geo::{
    AttribClass, AttribData, Attribute, Geometry, RampBasis, RampKey, RampKind, TypeInfo,
};
use geode_op::{
    geometry_input, CookContext, CookError, InputSpec, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, PortType, Registry, Value,
};
use rayon::prelude::*;

use crate::util::{geometry, input, input_owned, vec3};

const TANGENT: P = P::new("tangent", "Tangent", T::Menu(&["auto", "central", "previous", "next"]), D::Str("auto"), "auto: the exact tangent in point attribute T when the curve has one (curve nodes write it; frames are then fourth order), else central differences; previous or next: along the edge before or after each point.");
const METHOD: P = P::new("method", "Method", T::Menu(&["double_reflection", "parallel_transport", "up_vector"]), D::Str("double_reflection"), "How the normal follows the curve: rotation-minimizing by double reflection (Wang et al. 2008) or by discrete parallel transport, or the up vector made perpendicular to the tangent.");
const UP: P = P::new("up", "Up", T::Vec3, D::Vec3([0.0, 1.0, 0.0]), "The up vector (up_vector mode), and the first normal of every curve otherwise (made perpendicular to its tangent).");

/// The method menu's choice.
fn method(p: &Params) -> Result<FrameMethod, CookError> {
    Ok(match p.string(&METHOD)? {
        "parallel_transport" => FrameMethod::ParallelTransport,
        "up_vector" => FrameMethod::UpVector(vec3(p, &UP)?.as_dvec3()),
        _ => FrameMethod::DoubleReflection,
    })
}

/// Frames of one curve: tangents by the `tangent` menu's choice, the first
/// normal from `up`.
fn curve_frames(
    g: &Geometry,
    c: &Curve,
    tangent: &str,
    method: FrameMethod,
    up: DVec3,
) -> (Vec<DVec3>, Vec<Frame>) {
    let pos = g.positions();
    let pts: Vec<DVec3> = c
        .points
        .iter()
        .map(|&i| pos[i as usize].as_dvec3())
        .collect();
    let exact = g.attrib(AttribClass::Point, "T").and_then(|a| a.as_vec3());
    let mode = match tangent {
        "previous" => Some(TangentMode::Previous),
        "next" => Some(TangentMode::Next),
        "central" => Some(TangentMode::Central),
        _ => None,
    };
    let tangents = match (mode, exact) {
        (None, Some(t)) => {
            let t: Vec<DVec3> = c
                .points
                .iter()
                .map(|&i| t[i as usize].as_dvec3().normalize_or_zero())
                .collect();
            if t.iter().all(|v| *v != DVec3::ZERO) {
                t
            } else {
                frames::tangents(&pts, c.closed, TangentMode::Central)
            }
        }
        (m, _) => frames::tangents(&pts, c.closed, m.unwrap_or(TangentMode::Central)),
    };
    let f = frames::frames(&pts, &tangents, c.closed, method, Some(up));
    (pts, f)
}

const POLYFRAME_ROLL: P = P::new(
    "roll",
    "Roll",
    T::Float,
    D::Float(0.0),
    "Degrees the frames turn about the tangent.",
);
const POLYFRAME_ROLL_PER_POINT: P = P::new("roll_per_point", "Roll per point", T::Float, D::Float(0.0), "Further degrees per point along each curve (90 alternates copies a quarter turn, as chain links).");

static POLYFRAME: NodeSpec = NodeSpec::new(
    "polyframe",
    "PolyFrame",
    "curve",
    "A frame per curve point: tangent T, normal N, bitangent B (= N x T) and the quaternion `orient` taking X, Y, Z to B, N, T (copies placed with it run along the curve, +Y along N). Closed curves' frames close.",
    &[geometry_input("curves")],
    &[
        TANGENT,
        METHOD,
        UP,
        POLYFRAME_ROLL,
        POLYFRAME_ROLL_PER_POINT,
    ],
);

fn cook_poly_frame(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let cs = curves(&g);
    if cs.is_empty() {
        return Err(ctx.input_error("input 1 has no curves (polylines or polygons)"));
    }
    let n = g.num_points();
    let (mut t, mut nn, mut b) = (vec![Vec3::Z; n], vec![Vec3::Y; n], vec![Vec3::X; n]);
    let mut orient = vec![Quat::IDENTITY; n];
    let (roll, per) = (
        p.float(&POLYFRAME_ROLL)?.to_radians(),
        p.float(&POLYFRAME_ROLL_PER_POINT)?.to_radians(),
    );
    let (tangent, method, up) = (p.string(&TANGENT)?, method(p)?, vec3(p, &UP)?.as_dvec3());
    for c in &cs {
        ctx.check()?;
        let (_, f) = curve_frames(&g, c, tangent, method, up);
        for (k, (&i, fr)) in c.points.iter().zip(&f).enumerate() {
            let fr = fr.rolled(roll + per * k as f64);
            let i = i as usize;
            t[i] = fr.tangent.as_vec3();
            nn[i] = fr.normal.as_vec3();
            b[i] = fr.bitangent.as_vec3();
            orient[i] = fr.orient().as_quat();
        }
    }
    let mut set = |name: &str, data: AttribData, info: TypeInfo| {
        g.set_attrib(AttribClass::Point, name, Attribute::from_data(data, info))
            .map_err(|e| ctx.kernel(e))
    };
    set("T", AttribData::Vec3(t), TypeInfo::Vector)?;
    set("N", AttribData::Vec3(nn), TypeInfo::Normal)?;
    set("B", AttribData::Vec3(b), TypeInfo::Vector)?;
    set("orient", AttribData::Quat(orient), TypeInfo::Quaternion)?;
    geometry(g)
}

const SWEEP_SIDES: P = P::new(
    "sides",
    "Sides",
    T::Int,
    D::Int(12),
    "Circle sides (without a section input).",
)
.range(3.0, 65536.0);
const SWEEP_RADIUS: P = P::new(
    "radius",
    "Radius",
    T::Float,
    D::Float(0.1),
    "Scale of the section.",
)
.at_least(0.0);
const SWEEP_RADIUS_ATTRIBUTE: P = P::new(
    "radius_attribute",
    "Radius attribute",
    T::String,
    D::Str("pscale"),
    "Float (or int) point attribute multiplying the radius (if present).",
);
/// Houdini's Sweep "Apply Scale Along Curve": flat at 1 until edited.
const SWEEP_RAMP_DEFAULT: &[RampKey] = &[
    RampKey::float(0.0, 1.0, RampBasis::Linear),
    RampKey::float(1.0, 1.0, RampBasis::Linear),
];
const SWEEP_RAMP: P = P::ramp(
    "ramp", "Scale along curve", RampKind::Float, SWEEP_RAMP_DEFAULT, "Multiplies the radius along each curve: the ramp at the point's arc-length fraction (0 at the start, 1 at the end); a ramp without keys multiplies by 1. The old text form `u value, u value` still loads, as linear keys.");
const SWEEP_CAPS: P = P::new(
    "caps",
    "End caps",
    T::Toggle,
    D::Toggle(true),
    "Close open curves' ends (closed sections only).",
);

static SWEEP: NodeSpec = NodeSpec::new(
    "sweep",
    "Sweep",
    "curve",
    "A tube of quads along every curve: a circle of `sides` or the section curve of input 2 (drawn in its XY plane: X along the bitangent, Y along the normal), in rotation-minimizing frames (or the curve's own `orient`), scaled by radius x the radius attribute x the ramp along the curve; end caps on open curves; vertex `uv` around (u) and along (v).",
    &[geometry_input("curves"), InputSpec { name: "section", ty: PortType::Geometry, required: false }],
    &[
        SWEEP_SIDES,
        SWEEP_RADIUS,
        SWEEP_RADIUS_ATTRIBUTE,
        SWEEP_RAMP,
        SWEEP_CAPS,
        TANGENT,
        UP,
    ],
)
// 2: `orient` from any float4 column, an int radius attribute.
.version(2);

fn cook_sweep(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let cs = curves(g);
    if cs.is_empty() {
        return Err(ctx.input_error("input 1 has no curves (polylines or polygons)"));
    }
    let ramp = p.ramp(&SWEEP_RAMP)?;
    let caps = p.toggle(&SWEEP_CAPS)?;
    let opts = match inputs
        .get(1)
        .and_then(|v| v.as_ref())
        .and_then(|v| v.as_geometry())
    {
        Some(sec) => {
            let c = curves(sec)
                .into_iter()
                .next()
                .ok_or_else(|| ctx.input_error("input 2 (section) has no curve"))?;
            let pos = sec.positions();
            SweepOptions {
                section: c
                    .points
                    .iter()
                    .map(|&i| DVec2::new(pos[i as usize].x as f64, pos[i as usize].y as f64))
                    .collect(),
                section_closed: c.closed,
                caps,
            }
        }
        None => SweepOptions::circle(p.int(&SWEEP_SIDES)? as usize, caps),
    };
    let radius = p.float(&SWEEP_RADIUS)?;
    let attr = geode_geo::ops::point_scalar(g, p.string(&SWEEP_RADIUS_ATTRIBUTE)?)
        .map_err(|e| ctx.kernel_at(&SWEEP_RADIUS_ATTRIBUTE, e))?;
    // Any float4 `orient` (a wrangle's `p@orient` is a plain vector4).
    let orient = geode_geo::ops::point_float4(g, "orient").map_err(|e| ctx.kernel(e))?;
    let (tangent, up) = (p.string(&TANGENT)?, vec3(p, &UP)?.as_dvec3());
    let rings: f64 = cs.iter().map(|c| c.points.len() as f64).sum();
    let sides = opts.section.len() as f64;
    crate::util::reserve_mesh(
        ctx,
        &SWEEP_SIDES,
        rings * sides,
        4.0 * rings * sides,
        rings * sides,
    )?;
    let tubes: Vec<Result<Tube, CookError>> = cs
        .par_iter()
        .map(|c| {
            let (pts, f) = match orient {
                Some(o) => {
                    let pos = g.positions();
                    let pts: Vec<DVec3> = c
                        .points
                        .iter()
                        .map(|&i| pos[i as usize].as_dvec3())
                        .collect();
                    let f = c
                        .points
                        .iter()
                        .map(|&i| {
                            let q: DQuat = geode_geo::ops::unit_quat(o[i as usize]).as_dquat();
                            Frame {
                                tangent: q * DVec3::Z,
                                normal: q * DVec3::Y,
                                bitangent: q * DVec3::X,
                            }
                        })
                        .collect();
                    (pts, f)
                }
                None => curve_frames(g, c, tangent, FrameMethod::DoubleReflection, up),
            };
            let (along, total) = geode_curve::polyline::arc_lengths(&pts, c.closed);
            let scales: Vec<f64> = c
                .points
                .iter()
                .zip(&along)
                .map(|(&i, s)| {
                    let u = if total > 0.0 { s / total } else { 0.0 };
                    let along = if ramp.is_empty() {
                        1.0
                    } else {
                        ramp.eval_float(u)
                    };
                    radius * attr.map_or(1.0, |a| a.get(i as usize) as f64) * along
                })
                .collect();
            let cancel = || ctx.cancel.is_cancelled();
            sweep(&pts, &f, &scales, c.closed, &opts, &cancel)
                .ok_or_else(|| CookError::cancelled(ctx.path))
        })
        .collect();
    let mut all = Tube::default();
    for t in tubes {
        all.append(t?);
    }
    ctx.check()?;
    let mut out = Geometry::from_polygons(all.positions, all.faces, &all.counts)
        .map_err(|e| ctx.kernel(e))?;
    out.set_attrib(
        AttribClass::Vertex,
        "uv",
        Attribute::from_data(AttribData::Vec2(all.uvs), TypeInfo::TexCoord),
    )
    .map_err(|e| ctx.kernel(e))?;
    geometry(out)
}

pub fn register(r: &mut Registry) {
    r.node(&POLYFRAME, cook_poly_frame);
    r.node(&SWEEP, cook_sweep);
}
