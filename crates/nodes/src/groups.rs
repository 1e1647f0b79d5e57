//! Group nodes: by bounding box, or by an expression on position.

use geode_geo::{AttribClass, Geometry, Group};
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};
use rayon::prelude::*;

use crate::expr::Expr;
use crate::util::{class, element_positions, geometry, input_owned, vec3, ELEMENT_CLASSES};

fn store(
    ctx: &CookContext,
    param: &P,
    g: &mut Geometry,
    c: AttribClass,
    name: &str,
    flags: Vec<bool>,
) -> Result<(), CookError> {
    if name.is_empty() {
        return Err(ctx.param_error(param, "a group needs a name"));
    }
    let grp = Group::from_flags(flags);
    let r = if c == AttribClass::Primitive {
        g.set_prim_group(name, grp)
    } else {
        g.set_point_group(name, grp)
    };
    r.map_err(|e| ctx.kernel_at(param, e))
}

const BOUNDING_GROUP: P = P::new("group", "Group", T::String, D::Str("inside"), "Group name.");
const ELEMENT_CLASS: P = P::new(
    "class",
    "Class",
    T::Menu(ELEMENT_CLASSES),
    D::Str("point"),
    "Group points or primitives.",
);
const BOUNDING_MIN: P = P::new("min", "Min", T::Vec3, D::Vec3([-0.5; 3]), "Box corner.");
const BOUNDING_MAX: P = P::new("max", "Max", T::Vec3, D::Vec3([0.5; 3]), "Opposite corner.");

static BOUNDING: NodeSpec = NodeSpec::new(
    "group_bbox",
    "Group by Bounding Box",
    "group",
    "Puts the points (or primitives, by centroid) inside an axis-aligned box into a group.",
    &[geometry_input("geometry")],
    &[BOUNDING_GROUP, ELEMENT_CLASS, BOUNDING_MIN, BOUNDING_MAX],
);

fn cook_bounding(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let c = class(p, &ELEMENT_CLASS)?;
    let (lo, hi) = (vec3(p, &BOUNDING_MIN)?, vec3(p, &BOUNDING_MAX)?);
    let flags = element_positions(&g, c)
        .par_iter()
        .map(|q| q.cmpge(lo).all() && q.cmple(hi).all())
        .collect();
    store(
        ctx,
        &BOUNDING_GROUP,
        &mut g,
        c,
        p.string(&BOUNDING_GROUP)?,
        flags,
    )?;
    geometry(g)
}

const EXPRESSION_GROUP: P = P::new(
    "group",
    "Group",
    T::String,
    D::Str("selected"),
    "Group name.",
);
const EXPRESSION_EXPRESSION: P = P::new(
    "expression",
    "Expression",
    T::String,
    D::Str("y > 0"),
    "The test, e.g. `x > 0 && y < 0.5`.",
);

static EXPRESSION: NodeSpec = NodeSpec::new(
    "group_expression",
    "Group by Expression",
    "group",
    "Puts the elements for which an expression is non-zero into a group. Variables: x, y, z (position; a primitive's centroid), id (element index), frame. Operators: + - * / % ^ < <= > >= == != && || !; functions sin cos tan abs sqrt floor ceil min max pow atan2; pi.",
    &[geometry_input("geometry")],
    &[
        EXPRESSION_GROUP,
        ELEMENT_CLASS,
        EXPRESSION_EXPRESSION,
    ],
);

fn cook_expression(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let c = class(p, &ELEMENT_CLASS)?;
    let expr = Expr::parse(
        p.string(&EXPRESSION_EXPRESSION)?,
        &["x", "y", "z", "id", "frame"],
    )
    .map_err(|e| {
        ctx.param_error(&EXPRESSION_EXPRESSION, e.to_string())
            .at_position(1, e.column as u32)
    })?;
    let frame = ctx.frame;
    let flags = element_positions(&g, c)
        .par_iter()
        .enumerate()
        .map(|(i, q)| expr.eval(&[q.x as f64, q.y as f64, q.z as f64, i as f64, frame]) != 0.0)
        .collect();
    store(
        ctx,
        &EXPRESSION_GROUP,
        &mut g,
        c,
        p.string(&EXPRESSION_GROUP)?,
        flags,
    )?;
    geometry(g)
}

pub fn register(r: &mut Registry) {
    r.node(&BOUNDING, cook_bounding);
    r.node(&EXPRESSION, cook_expression);
}
