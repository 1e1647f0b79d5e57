//! Space colonization as a node: a tree grown from birth points toward
//! attractor points, as branch polylines with generation, branch order and
//! a pipe-model radius (`pscale`, ready for sweep or frep_sweep).

use geode_geo::{AttribClass, AttribData, Attribute, Geometry, PrimKind, TypeInfo};
use geode_growth::{colonize, ColonizeOptions};
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{geometry, input};

const COLONIZE_INFLUENCE: P = P::new(
    "influence",
    "Influence radius",
    T::Float,
    D::Float(0.1),
    "How far an attractor reaches.",
)
.at_least(1e-9);
const COLONIZE_KILL: P = P::new(
    "kill",
    "Kill distance",
    T::Float,
    D::Float(0.02),
    "An attractor this close to a node is reached.",
)
.at_least(1e-9);
const COLONIZE_STEP: P = P::new(
    "step",
    "Step",
    T::Float,
    D::Float(0.01),
    "Length of each new segment.",
)
.at_least(1e-9);
const COLONIZE_ITERATIONS: P = P::new(
    "iterations",
    "Iterations",
    T::Int,
    D::Int(1000),
    "Most growth steps.",
)
.range(0.0, 10_000_000.0);
const COLONIZE_JITTER: P = P::new(
    "jitter",
    "Jitter",
    T::Float,
    D::Float(0.0),
    "Random turn of each step (fraction of its direction), seeded.",
)
.range(0.0, 10.0);
const COLONIZE_SEED: P = P::new("seed", "Seed", T::Int, D::Int(0), "Jitter seed.");
const COLONIZE_TIP_RADIUS: P = P::new(
    "tip_radius",
    "Tip radius",
    T::Float,
    D::Float(0.002),
    "Radius at the branch tips.",
)
.at_least(0.0);
const COLONIZE_EXPONENT: P = P::new(
    "exponent",
    "Pipe exponent",
    T::Float,
    D::Float(2.5),
    "n in r^n = sum of children's r^n (2: area kept, 3: Murray's law).",
)
.range(2.0, 3.0);

static COLONIZE: NodeSpec = NodeSpec::new(
    "space_colonize",
    "Space Colonization",
    "growth",
    "Grows branches from the points of input 2 toward the attractor points of input 1 (Runions et al. 2007): each step every attractor pulls its nearest node within the influence radius, each pulled node grows a step along the mean pull, attractors within the kill distance die. Output: branch polylines with point attributes generation (the step that made the point), branch_order (0 on the stem, +1 per side branch) and pscale (pipe model: tip radius at the tips, a parent's radius^exponent the sum of its children's). Key `iterations` to the frame to watch it grow.",
    &[geometry_input("attractors"), geometry_input("births")],
    &[
        COLONIZE_INFLUENCE,
        COLONIZE_KILL,
        COLONIZE_STEP,
        COLONIZE_ITERATIONS,
        COLONIZE_JITTER,
        COLONIZE_SEED,
        COLONIZE_TIP_RADIUS,
        COLONIZE_EXPONENT,
    ],
);

fn cook_colonize(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let (attractors, births) = (input(ctx, inputs, 0)?, input(ctx, inputs, 1)?);
    if births.num_points() == 0 {
        return Err(ctx.input_error("input 2 has no birth points"));
    }
    let opts = ColonizeOptions {
        influence: p.float(&COLONIZE_INFLUENCE)? as f32,
        kill: p.float(&COLONIZE_KILL)? as f32,
        step: p.float(&COLONIZE_STEP)? as f32,
        max_iterations: p.int(&COLONIZE_ITERATIONS)? as usize,
        jitter: p.float(&COLONIZE_JITTER)? as f32,
        seed: p.int(&COLONIZE_SEED)? as u64,
    };
    let cancel = || ctx.cancel.is_cancelled();
    let tree = colonize(attractors.positions(), births.positions(), &opts, &cancel)
        .map_err(|e| ctx.kernel(e))?;
    let branches = tree.branches();
    let radii = tree.pipe_radii(
        p.float(&COLONIZE_TIP_RADIUS)? as f32,
        p.float(&COLONIZE_EXPONENT)? as f32,
    );
    let order = tree.branch_order();
    let counts: Vec<u32> = branches.iter().map(|b| b.len() as u32).collect();
    let kinds = vec![PrimKind::Polyline; branches.len()];
    let flat: Vec<u32> = branches.into_iter().flatten().collect();
    let mut g =
        Geometry::from_prims(tree.positions, flat, &counts, kinds).map_err(|e| ctx.kernel(e))?;
    let gen: Vec<i32> = tree.generation.iter().map(|&x| x as i32).collect();
    let order: Vec<i32> = order.into_iter().map(|x| x as i32).collect();
    for (name, data) in [
        ("generation", AttribData::Int(gen)),
        ("branch_order", AttribData::Int(order)),
        ("pscale", AttribData::Float(radii)),
    ] {
        g.set_attrib(
            AttribClass::Point,
            name,
            Attribute::from_data(data, TypeInfo::None),
        )
        .map_err(|e| ctx.kernel(e))?;
    }
    geometry(g)
}

pub fn register(r: &mut Registry) {
    r.node(&COLONIZE, cook_colonize);
}
