//! The polyreduce node: quadric error decimation to a share of the
//! triangles, a count or an error bound (geode-model's `reduce`).

use geode_model::reduce::{reduce, Reduce, Target};
use geode_model::ModelError;
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{geometry, input};

const TARGETS: &[&str] = &["percent", "count", "error"];

const TARGET: P = P::new(
    "target",
    "Target",
    T::Menu(TARGETS),
    D::Str("percent"),
    "percent: keep a share of the triangles; count: keep a number of triangles; error: collapse everything whose error stays within Max Error.",
);
const PERCENT: P = P::new(
    "percent",
    "Percent to Keep",
    T::Float,
    D::Float(10.0),
    "The share of the (triangulated) input's triangles to keep, in percent (target percent).",
)
.range(0.0, 100.0);
const COUNT: P = P::new(
    "count",
    "Number to Keep",
    T::Int,
    D::Int(1000),
    "The number of triangles to keep (target count).",
)
.at_least(0.0);
const MAX_ERROR: P = P::new(
    "max_error",
    "Max Error",
    T::Float,
    D::Float(0.0),
    "No collapse whose error is larger, in model units (the root mean squared distance of the new point to the planes of the triangles it replaces). For targets percent and count 0 means no bound; for target error it is the bound.",
)
.at_least(0.0);
const LOCK_BORDERS: P = P::new(
    "lock_borders",
    "Lock Borders",
    T::Toggle,
    D::Toggle(false),
    "Border points never move (off: they move along their border only, which keeps its shape).",
);
const LOCK_SEAMS: P = P::new(
    "lock_seams",
    "Lock Seams",
    T::Toggle,
    D::Toggle(false),
    "Points on a seam (a vertex attribute such as uv that differs across an edge) never move (off: they move along their seam only).",
);

static POLYREDUCE: NodeSpec = NodeSpec::new(
    "polyreduce",
    "PolyReduce",
    "model",
    "Reduces a polygon mesh by quadric error edge collapses (Garland and Heckbert, each new point where the error is least). Polygons are triangulated first and the output is triangles, as Houdini's PolyReduce and Blender's Decimate (collapse) give. Borders and seams of any vertex attribute keep their place; a closed manifold stays closed; no triangle flips. Float point attributes are blended where the points merge, float vertex attributes per seam side; other attributes and point groups come from the surviving point, primitive attributes and groups from the source polygon. Unlike Houdini, no quads are kept, there are no attribute weights or length equalisation; Blender's Decimate ratio is Percent to Keep / 100.",
    &[geometry_input("geometry")],
    &[TARGET, PERCENT, COUNT, MAX_ERROR, LOCK_BORDERS, LOCK_SEAMS],
);

fn cook_polyreduce(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let percent = p.float(&PERCENT)?;
    if !(0.0..=100.0).contains(&percent) {
        return Err(ctx.param_error(&PERCENT, format!("{percent} is not between 0 and 100")));
    }
    let bound = p.float(&MAX_ERROR)?;
    if bound.is_nan() || bound < 0.0 {
        return Err(ctx.param_error(&MAX_ERROR, format!("{bound} is below 0")));
    }
    let target = match p.string(&TARGET)? {
        "count" => Target::Count(p.int(&COUNT)?.max(0) as usize),
        "error" => Target::Error,
        _ => Target::Percent(percent),
    };
    let how = Reduce {
        target,
        max_error: if bound > 0.0 || target == Target::Error {
            bound
        } else {
            f64::INFINITY
        },
        lock_borders: p.toggle(&LOCK_BORDERS)?,
        lock_seams: p.toggle(&LOCK_SEAMS)?,
    };
    // The working mesh: a position, quadric and lists per point, links
    // and wedges per corner, heap entries per edge; then the output.
    let bytes = g.num_points() as f64 * 160.0 + g.num_vertices() as f64 * 64.0;
    ctx.reserve(&TARGET, bytes, "the reduction")?;
    match reduce(g, &how, &ctx.cancel_fn()) {
        Ok(r) => geometry(r.geometry),
        Err(ModelError::Cancelled) => Err(CookError::cancelled(ctx.path)),
        Err(e) => Err(ctx.kernel(e)),
    }
}

pub fn register(r: &mut Registry) {
    r.node(&POLYREDUCE, cook_polyreduce);
}
