//! The wall_thickness analysis node: each point's wall thickness, the
//! thinnest wall as a detail attribute and the points thinner than a
//! printable minimum as a group, so a designer sees what will not print.

use geode_geo::ops::{wall_thickness, NO_OPPOSITE_WALL};
use geode_geo::{AttribClass, AttribData, Attribute, Group, TypeInfo};
use geode_op::{
    CookContext, CookError, InputSpec, NodeSpec, ParamDefault as D, ParamSpec as P, ParamType as T,
    Params, PortType, Registry, Value,
};

use crate::util::input_owned;

const MINIMUM: P = P::new(
    "minimum",
    "Minimum Thickness",
    T::Float,
    D::Float(0.08),
    "The thinnest wall the printer makes, in model units: thinner points join the group.",
)
.at_least(0.0);
const ATTRIBUTE: P = P::new(
    "attribute",
    "Attribute",
    T::String,
    D::Str("thickness"),
    "Point attribute for each point's thickness (-1 where the inward ray leaves the mesh: an open surface).",
);
const GROUP: P = P::new(
    "group",
    "Group",
    T::String,
    D::Str("thin"),
    "Point group of the points thinner than the minimum.",
);

static WALL_THICKNESS: NodeSpec = NodeSpec::new(
    "wall_thickness",
    "Wall Thickness",
    "analysis",
    "Measures a closed mesh's wall thickness at every point: the distance to the opposite wall along the inverted normal (the 3D-print checkers' ray test). Writes a point attribute, the detail attribute min_thickness (the thinnest wall, -1 if none was found) and a group of the points thinner than the minimum.",
    &[InputSpec {
        name: "mesh",
        ty: PortType::Geometry,
        required: true,
    }],
    &[MINIMUM, ATTRIBUTE, GROUP],
);

fn cook(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let (attribute, group) = (p.string(&ATTRIBUTE)?, p.string(&GROUP)?);
    if attribute.is_empty() {
        return Err(ctx.param_error(&ATTRIBUTE, "the thickness attribute needs a name"));
    }
    if group.is_empty() {
        return Err(ctx.param_error(&GROUP, "the group of thin points needs a name"));
    }
    let minimum = p.float(&MINIMUM)? as f32;
    let thickness =
        wall_thickness(&g, &ctx.cancel_fn()).map_err(|_| CookError::cancelled(ctx.path))?;
    let measured = || thickness.iter().copied().filter(|&t| t != NO_OPPOSITE_WALL);
    let thinnest = measured().fold(None, |m: Option<f32>, t| Some(m.map_or(t, |m| m.min(t))));
    let thin = Group::from_flags(
        thickness
            .iter()
            .map(|&t| t != NO_OPPOSITE_WALL && t < minimum),
    );
    g.set_point_group(group, thin)
        .map_err(|e| ctx.kernel_at(&GROUP, e))?;
    g.set_attrib(
        AttribClass::Point,
        attribute,
        Attribute::from_data(AttribData::Float(thickness), TypeInfo::None),
    )
    .map_err(|e| ctx.kernel_at(&ATTRIBUTE, e))?;
    g.set_attrib(
        AttribClass::Detail,
        "min_thickness",
        Attribute::from_data(
            AttribData::Float(vec![thinnest.unwrap_or(NO_OPPOSITE_WALL)]),
            TypeInfo::None,
        ),
    )
    .map_err(|e| ctx.kernel(e))?;
    Ok(Value::geometry(g))
}

pub fn register(r: &mut Registry) {
    r.node(&WALL_THICKNESS, cook);
}
