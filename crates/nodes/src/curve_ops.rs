//! Curve edits: resample by length or count, smooth, carve a range,
//! reverse, join, polypath (segments joined into one curve per branch).
//! Resampling and carving blend every point attribute
//! between the points a new point falls between.

use geode_curve::polyline::glam_d::DVec3;
use geode_curve::resample::{self, Sample};
use geode_curve::{curves, polypath, rebuild, Curve, CurveOut, PolyPathError, PolyPathOptions};
use geode_geo::{ops, Geometry};
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{geometry, input, input_owned};

fn positions(g: &Geometry, c: &Curve) -> Vec<DVec3> {
    let p = g.positions();
    c.points.iter().map(|&i| p[i as usize].as_dvec3()).collect()
}

/// Rebuilds every curve of `g` from the samples `f` picks on it; other
/// primitives are dropped (an error if there are no curves at all).
fn rebuild_curves(
    ctx: &CookContext,
    g: &Geometry,
    f: impl Fn(&Curve, &[DVec3]) -> (Vec<Sample>, bool),
) -> Result<Value, CookError> {
    let cs = curves(g);
    if cs.is_empty() {
        return Err(ctx.input_error("input 1 has no curves (polylines or polygons)"));
    }
    let outs: Vec<CurveOut> = cs
        .iter()
        .map(|c| {
            let pts = positions(g, c);
            let (samples, closed) = f(c, &pts);
            let n = c.points.len();
            let points = samples
                .iter()
                .map(|s| {
                    let (a, b) = s.ends(n);
                    (c.points[a], c.points[b], s.t as f32)
                })
                .collect();
            CurveOut {
                prim: c.prim,
                closed,
                points,
            }
        })
        .collect();
    geometry(rebuild(g, &outs).map_err(|e| ctx.kernel(e))?)
}

const RESAMPLE_MODE: P = P::new("mode", "Mode", T::Menu(&["length", "count"]), D::Str("length"), "length: segments of about `length` (evened out so the ends land exactly); count: `count` points per curve.");
const RESAMPLE_LENGTH: P = P::new(
    "length",
    "Length",
    T::Float,
    D::Float(0.1),
    "Segment length.",
)
.at_least(1e-9);
const RESAMPLE_COUNT: P =
    P::new("count", "Count", T::Int, D::Int(20), "Points per curve.").range(2.0, 16_777_216.0);

static RESAMPLE: NodeSpec = NodeSpec::new(
    "resample",
    "Resample",
    "curve",
    "Evenly spaced points along every curve, by segment length or by count; point attributes are interpolated.",
    &[geometry_input("curves")],
    &[
        RESAMPLE_MODE,
        RESAMPLE_LENGTH,
        RESAMPLE_COUNT,
    ],
);

fn cook_resample(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let by_count = p.string(&RESAMPLE_MODE)? == "count";
    let (length, count) = (p.float(&RESAMPLE_LENGTH)?, p.int(&RESAMPLE_COUNT)? as usize);
    let points = if by_count {
        g.num_prims() as f64 * count as f64
    } else {
        // Every edge of every curve, however the curves share points.
        let pos = g.positions();
        let total: f64 = (0..g.num_prims())
            .map(|i| {
                let pts = g.prim_points(i);
                pts.windows(2)
                    .map(|w| pos[w[0] as usize].distance(pos[w[1] as usize]) as f64)
                    .sum::<f64>()
            })
            .sum();
        total / length + 2.0 * g.num_prims() as f64
    };
    let param = if by_count {
        &RESAMPLE_COUNT
    } else {
        &RESAMPLE_LENGTH
    };
    crate::util::reserve_mesh(ctx, param, points, points, g.num_prims() as f64)?;
    rebuild_curves(ctx, g, |c, pts| {
        let s = if by_count {
            resample::resample_by_count(pts, c.closed, count)
        } else {
            resample::resample_by_length(pts, c.closed, length)
        };
        (s, c.closed)
    })
}

const CARVE_FROM: P = P::new(
    "from",
    "From",
    T::Float,
    D::Float(0.0),
    "Start, as a fraction of the length.",
)
.range(0.0, 1.0);
const CARVE_TO: P = P::new(
    "to",
    "To",
    T::Float,
    D::Float(1.0),
    "End, as a fraction of the length.",
)
.range(0.0, 1.0);

static CARVE: NodeSpec = NodeSpec::new(
    "carve",
    "Carve",
    "curve",
    "Keeps the part of every curve between two fractions of its length (a closed curve is cut open at its first point).",
    &[geometry_input("curves")],
    &[
        CARVE_FROM,
        CARVE_TO,
    ],
);

fn cook_carve(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let (from, to) = (p.float(&CARVE_FROM)?, p.float(&CARVE_TO)?);
    rebuild_curves(ctx, g, |c, pts| {
        // A loop opens at its first point: that point again at the end
        // (its last segment is the closing one, which `ends` wraps to 0).
        let opened = c.closed.then(|| [pts, &pts[..1]].concat());
        (
            resample::carve(opened.as_deref().unwrap_or(pts), from, to),
            false,
        )
    })
}

const SMOOTH_STRENGTH: P = P::new(
    "strength",
    "Strength",
    T::Float,
    D::Float(0.5),
    "How far toward the mean per pass.",
)
.range(0.0, 1.0);
const SMOOTH_ITERATIONS: P =
    P::new("iterations", "Iterations", T::Int, D::Int(10), "Passes.").range(0.0, 100_000.0);

static SMOOTH: NodeSpec = NodeSpec::new(
    "curve_smooth",
    "Smooth Curve",
    "curve",
    "Moves each point toward the mean of its neighbours (Laplacian smoothing); open curves keep their ends.",
    &[geometry_input("curves")],
    &[
        SMOOTH_STRENGTH,
        SMOOTH_ITERATIONS,
    ],
);

fn cook_smooth(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let (strength, iterations) = (
        p.float(&SMOOTH_STRENGTH)?,
        p.int(&SMOOTH_ITERATIONS)? as usize,
    );
    for c in curves(&g) {
        ctx.check()?;
        let smoothed = resample::smooth(&positions(&g, &c), c.closed, strength, iterations);
        let pos = g.positions_mut();
        for (&i, q) in c.points.iter().zip(smoothed) {
            pos[i as usize] = q.as_vec3();
        }
    }
    geometry(g)
}

static REVERSE: NodeSpec = NodeSpec::new(
    "reverse",
    "Reverse",
    "curve",
    "Reverses the vertex order of every primitive: curves run the other way, polygons face the other side.",
    &[geometry_input("geometry")],
    &[],
);

fn cook_reverse(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    _: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    ops::reverse_prims(&mut g, None);
    geometry(g)
}

const JOIN_CLOSE: P = P::new(
    "close",
    "Close",
    T::Toggle,
    D::Toggle(false),
    "Close the joined curve.",
);

static JOIN: NodeSpec = NodeSpec::new(
    "join",
    "Join Curves",
    "curve",
    "Joins all open curves into one, in primitive order, each continuing from the end of the previous (a shared end point is used once).",
    &[geometry_input("curves")],
    &[
        JOIN_CLOSE,
    ],
);

fn cook_join(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let open: Vec<Curve> = curves(g).into_iter().filter(|c| !c.closed).collect();
    let Some(first) = open.first() else {
        return Err(ctx.input_error("input 1 has no open curves to join"));
    };
    let pos = g.positions();
    let mut points: Vec<(u32, u32, f32)> = Vec::new();
    for c in &open {
        for &i in &c.points {
            let repeat = points
                .last()
                .is_some_and(|&(j, _, _)| pos[j as usize] == pos[i as usize]);
            if !repeat {
                points.push((i, i, 0.0));
            }
        }
    }
    let closed = p.toggle(&JOIN_CLOSE)?;
    let out = CurveOut {
        prim: first.prim,
        closed,
        points,
    };
    if out.points.len() < if closed { 3 } else { 2 } {
        return Err(ctx.input_error("the joined curve has too few distinct points"));
    }
    geometry(rebuild(g, &[out]).map_err(|e| ctx.kernel(e))?)
}

const POLYPATH_CLOSE_LOOPS: P = P::new(
    "close_loops",
    "Make isolated loops closed",
    T::Toggle,
    D::Toggle(true),
    "A loop of edges that touches no other edge becomes a closed polygon (off: an open polyline ending at its first point).",
);

static POLYPATH: NodeSpec = NodeSpec::new(
    "polypath",
    "PolyPath",
    "curve",
    "Houdini's PolyPath: the edges of all polylines and polygons rewired into polylines that run until a point with one edge or three or more (an end or a branch), so segments grown one at a time become one curve per branch. Duplicate edges count once, edges from a point to itself go; points and their attributes stay. Each path runs the way most of its edges ran; it takes the primitive attributes of its first source edge's primitive. Points are joined by number, not position (fuse first to join coincident ends). Other primitives are dropped.",
    &[geometry_input("curves")],
    &[
        POLYPATH_CLOSE_LOOPS,
    ],
);

fn cook_polypath(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    if curves(g).is_empty() {
        return Err(ctx.input_error("input 1 has no curves (polylines or polygons)"));
    }
    let opts = PolyPathOptions {
        close_loops: p.toggle(&POLYPATH_CLOSE_LOOPS)?,
    };
    let dropped = g
        .prim_kinds()
        .iter()
        .filter(|k| {
            !matches!(
                k,
                geode_geo::PrimKind::Polyline | geode_geo::PrimKind::Polygon
            )
        })
        .count();
    if dropped > 0 {
        ctx.warn(format!(
            "{dropped} primitives that are not polylines or polygons were dropped"
        ));
    }
    let cancel = || ctx.cancel.is_cancelled();
    match polypath(g, &opts, &cancel) {
        Ok(out) => geometry(out),
        Err(PolyPathError::Cancelled) => Err(CookError::cancelled(ctx.path)),
        Err(e) => Err(ctx.kernel(e)),
    }
}

pub fn register(r: &mut Registry) {
    r.node(&RESAMPLE, cook_resample);
    r.node(&CARVE, cook_carve);
    r.node(&SMOOTH, cook_smooth);
    r.node(&REVERSE, cook_reverse);
    r.node(&JOIN, cook_join);
    r.node(&POLYPATH, cook_polypath);
}
