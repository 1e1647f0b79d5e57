//! Wiring nodes: merge, switch, null.

use geode_geo::{ops, Geometry};
use geode_op::{
    CookContext, CookError, InputSpec, NodeSpec, ParamDefault as D, ParamSpec as P, ParamType as T,
    Params, PortType, Registry, Value,
};

use crate::util::geometry;

const ANY_GEOMETRY: &[InputSpec] = &[InputSpec {
    name: "geometry",
    ty: PortType::Geometry,
    required: false,
}];

static MERGE: NodeSpec = NodeSpec::new(
    "merge",
    "Merge",
    "flow",
    "Combines all inputs in order. Attributes missing on some inputs take their defaults; groups are kept.",
    ANY_GEOMETRY,
    &[],
)
.variadic();

fn cook_merge(ctx: &CookContext, inputs: &[Option<Value>], _: &Params) -> Result<Value, CookError> {
    let gs: Vec<&Geometry> = inputs
        .iter()
        .flatten()
        .filter_map(|v| v.as_geometry().map(|g| &**g))
        .collect();
    geometry(ops::merge(&gs).map_err(|e| ctx.kernel(e))?)
}

const SWITCH_INDEX: P = P::new(
    "index",
    "Index",
    T::Int,
    D::Int(0),
    "Which input (0 is the first).",
)
.at_least(0.0);

static SWITCH: NodeSpec = NodeSpec::new(
    "switch",
    "Switch",
    "flow",
    "Passes one of its inputs through, chosen by index (clamped to the inputs present).",
    ANY_GEOMETRY,
    &[SWITCH_INDEX],
)
.variadic();

fn cook_switch(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    if inputs.is_empty() {
        return Err(ctx.input_error("switch has no inputs"));
    }
    let i = (p.int(&SWITCH_INDEX)?.max(0) as usize).min(inputs.len() - 1);
    inputs[i]
        .clone()
        .ok_or_else(|| ctx.param_error("index", format!("input {} is not connected", i + 1)))
}

static NULL: NodeSpec = NodeSpec::new(
    "null",
    "Null",
    "flow",
    "Passes its input through unchanged: a named place in a network.",
    &[InputSpec {
        name: "geometry",
        ty: PortType::Geometry,
        required: true,
    }],
    &[],
);

fn cook_null(ctx: &CookContext, inputs: &[Option<Value>], _: &Params) -> Result<Value, CookError> {
    inputs
        .first()
        .cloned()
        .flatten()
        .ok_or_else(|| ctx.input_error("input 1 is not connected"))
}

pub fn register(r: &mut Registry) {
    r.node(&MERGE, cook_merge);
    r.node(&SWITCH, cook_switch);
    r.node(&NULL, cook_null);
}
