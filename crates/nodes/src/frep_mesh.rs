//! Mesh primitives as FRep inputs: the box, sphere, torus and tube nodes
//! (with `analytic` on) feed FRep networks as the exact solids they stand
//! for, moved by any `transform` on the way (the seed's use of Houdini's own
//! primitives as guide geometry).

use geode_frep::shapes;
use geode_geo::analytic;
use geode_op::{CookContext, CookError, InputSpec, NodeSpec, Params, PortType, Registry, Value};

static FROM_PRIMITIVES: NodeSpec = NodeSpec::new(
    "frep_from_primitives",
    "FRep From Primitives",
    "frep",
    "The exact solids behind mesh primitives (box, sphere, torus, tube made with `analytic` on, then transformed, merged or partly deleted): their union as a field. Any other polygon is an error naming it.",
    &[InputSpec {
        name: "primitives",
        ty: PortType::Geometry,
        required: true,
    }],
    &[],
)
.output(PortType::Field);

fn cook_from_primitives(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    _: &Params,
) -> Result<Value, CookError> {
    let g = crate::util::input(ctx, inputs, 0)?;
    let found = analytic::shapes(g).map_err(|e| ctx.input_error(format!("input 1: {e}")))?;
    let mut solids = Vec::with_capacity(found.len());
    for (shape, frame) in found {
        let solid = shapes::analytic(&shape)
            .transformed(&frame.as_dmat4())
            .ok_or_else(|| ctx.input_error(format!("a {shape:?} is scaled to nothing")))?;
        solids.push(solid);
    }
    shapes::union_all(solids)
        .map(Value::Field)
        .ok_or_else(|| ctx.input_error("input 1 has no primitives"))
}

pub fn register(r: &mut Registry) {
    r.node(&FROM_PRIMITIVES, cook_from_primitives);
}
