//! The boolean node: union, intersection, subtraction and shatter of
//! closed polygon meshes (geode-model's `boolean`).

use geode_model::boolean::{self, BooleanOp};
use geode_model::ModelError;
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{geometry, input};

const OPERATION: P = P::new(
    "operation",
    "Operation",
    T::Menu(BooleanOp::NAMES),
    D::Str("union"),
    "union: inside A or B; intersect: inside both; subtract: A minus B; shatter: A cut by B into its piece outside B (prim `piece` 0) and inside it (`piece` 1), each closed.",
);

static BOOLEAN: NodeSpec = NodeSpec::new(
    "boolean",
    "Boolean",
    "model",
    "Union, intersection, subtraction or shatter of two closed polygon meshes, exact and robust as manifold is (coplanar faces, touching edges and vertices give a closed result). Point and vertex attributes of the new points on the cut are their source face's corners weighted by position; primitive attributes and groups come from the source face. Groups: a_inside_b, a_outside_b, b_inside_a, b_outside_a (primitives) and seam (points where A's and B's faces meet). Unlike Houdini, the result is triangles (Houdini keeps n-gons), the seam is a point group (geode has no edge groups), and an open or inside-out input is an error rather than treated as a surface. As in Houdini, an empty input gives the other side for a union, A for A less nothing, nothing for an intersection.",
    &[geometry_input("a"), geometry_input("b")],
    &[OPERATION],
);

fn cook_boolean(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let a = input(ctx, inputs, 0)?;
    let b = input(ctx, inputs, 1)?;
    let name = p.string(&OPERATION)?;
    let op = BooleanOp::from_name(name).ok_or_else(|| {
        ctx.param_error(
            &OPERATION,
            format!(
                "unknown operation \"{name}\": expected one of {}",
                BooleanOp::NAMES.join(", ")
            ),
        )
    })?;
    // Each polygon of n corners becomes n - 2 triangles.
    let triangles: usize = [a, b]
        .iter()
        .map(|g| g.num_vertices().saturating_sub(2 * g.num_prims()))
        .sum();
    ctx.reserve(
        &OPERATION,
        boolean::estimate_bytes(triangles),
        "the boolean",
    )?;
    match boolean::boolean(a, b, op, &ctx.cancel_fn()) {
        Ok(g) => geometry(g),
        Err(ModelError::Cancelled) => Err(CookError::cancelled(ctx.path)),
        Err(e @ (ModelError::NotClosed { .. } | ModelError::InsideOut { .. })) => {
            Err(ctx.input_error(e.to_string()).with_source(e))
        }
        Err(e) => Err(ctx.kernel(e)),
    }
}

pub fn register(r: &mut Registry) {
    r.node(&BOOLEAN, cook_boolean);
}
