//! Piece nodes: connectivity (a piece number per point or primitive) and
//! split (the primitives a group pattern selects, or the rest).

use geode_geo::ops::{self, Connect};
use geode_geo::{AttribClass, AttribData, Attribute, Group, TypeInfo};
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{class, geometry, group_param, input, input_owned, ELEMENT_CLASSES};

const CONNECTIVITY_CLASS: P = P::new(
    "class",
    "Connectivity type",
    T::Menu(ELEMENT_CLASSES),
    D::Str("primitive"),
    "Whether the piece number goes on points or on primitives.",
);
const CONNECTIVITY_ATTRIBUTE: P = P::new(
    "attribute",
    "Attribute",
    T::String,
    D::Str("class"),
    "The integer attribute that receives each element's piece number (0 is the piece of primitive 0; points no primitive uses are pieces of their own, numbered last).",
);
const CONNECTIVITY_CONNECT: P = P::new(
    "connect",
    "Connect by",
    T::Menu(&["point", "edge"]),
    D::Str("point"),
    "Primitives are one piece when they share a point, or only when they share an edge.",
);
const CONNECTIVITY_AGREE: P = P::new(
    "by_attribute",
    "Only where attribute agrees",
    T::String,
    D::Str(""),
    "A primitive or vertex attribute (e.g. `uv` for uv islands, `name`) that must hold the same value on both sides for primitives to join; empty for topology alone.",
);

static CONNECTIVITY: NodeSpec = NodeSpec::new(
    "connectivity",
    "Connectivity",
    "pieces",
    "Numbers the connected pieces of the geometry (Houdini's Connectivity): an integer attribute per point or primitive, pieces numbered by their first primitive.",
    &[geometry_input("geometry")],
    &[
        CONNECTIVITY_CLASS,
        CONNECTIVITY_ATTRIBUTE,
        CONNECTIVITY_CONNECT,
        CONNECTIVITY_AGREE,
    ],
);

fn cook_connectivity(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let name = p.string(&CONNECTIVITY_ATTRIBUTE)?;
    if name.is_empty() {
        return Err(ctx.param_error(&CONNECTIVITY_ATTRIBUTE, "the attribute needs a name"));
    }
    let connect = match p.string(&CONNECTIVITY_CONNECT)? {
        "edge" => Connect::SharedEdge,
        _ => Connect::SharedPoint,
    };
    let agree_name = p.string(&CONNECTIVITY_AGREE)?;
    let agree = if agree_name.is_empty() {
        None
    } else {
        let found = [AttribClass::Primitive, AttribClass::Vertex]
            .into_iter()
            .find_map(|c| g.attrib(c, agree_name).map(|a| (c, a.data().clone())));
        Some(found.ok_or_else(|| {
            let why = if g.attrib(AttribClass::Point, agree_name).is_some() {
                format!("`{agree_name}` is a point attribute: pieces meet at shared points, where it has one value, so it cannot part them; split by a primitive or vertex attribute (uv_flatten and uv_project write vertex `uv`)")
            } else {
                format!("there is no primitive or vertex attribute `{agree_name}`")
            };
            ctx.param_error(&CONNECTIVITY_AGREE, why)
        })?)
    };
    let pieces = ops::connectivity(&g, connect, agree.as_ref().map(|(c, d)| (*c, d)));
    let c = class(p, &CONNECTIVITY_CLASS)?;
    let numbers = if c == AttribClass::Point {
        pieces.of_point
    } else {
        pieces.of_prim
    };
    let column = AttribData::Int(numbers.into_iter().map(|k| k as i32).collect());
    g.set_attrib(c, name, Attribute::from_data(column, TypeInfo::None))
        .map_err(|e| ctx.kernel_at(&CONNECTIVITY_ATTRIBUTE, e))?;
    geometry(g)
}

const SPLIT_GROUP: P = P::new(
    "group",
    "Group",
    T::String,
    D::Str(""),
    "The primitives to split off: a group pattern (`top`, `0-9:2`, `@name=piece*`, `!bottom`).",
);
const SPLIT_CLASS: P = P::new(
    "class",
    "Group type",
    T::Menu(ELEMENT_CLASSES),
    D::Str("primitive"),
    "Whether the pattern selects primitives, or points (a primitive is selected when every point of it is).",
);
const SPLIT_SIDE: P = P::new(
    "side",
    "Output",
    T::Menu(&["selected", "rest"]),
    D::Str("selected"),
    "Which side this node passes on: the selected primitives, or the rest (Houdini's Split has both as outputs; use two split nodes for both).",
);

static SPLIT: NodeSpec = NodeSpec::new(
    "split",
    "Split",
    "pieces",
    "The primitives a group pattern selects, or the rest, with the points they use and every attribute and group.",
    &[geometry_input("geometry")],
    &[SPLIT_GROUP, SPLIT_CLASS, SPLIT_SIDE],
);

fn cook_split(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let c = class(p, &SPLIT_CLASS)?;
    let selected = selected_prims(ctx, p, &SPLIT_GROUP, g, c)?;
    let (inside, outside) = ops::split_by_group(g, &selected);
    geometry(if p.string(&SPLIT_SIDE)? == "rest" {
        outside
    } else {
        inside
    })
}

/// The primitives a pattern selects: directly, or through their points
/// (every point selected).
pub(crate) fn selected_prims(
    ctx: &CookContext,
    p: &Params,
    spec: &P,
    g: &geode_geo::Geometry,
    c: AttribClass,
) -> Result<Group, CookError> {
    let Some(grp) = group_param(ctx, p, spec, g, c)? else {
        return Ok(Group::from_flags((0..g.num_prims()).map(|_| true)));
    };
    if c == AttribClass::Primitive {
        return Ok(grp);
    }
    Ok(Group::from_flags((0..g.num_prims()).map(|prim| {
        let pts = g.prim_points(prim);
        !pts.is_empty() && pts.iter().all(|&q| grp.contains(q as usize))
    })))
}

pub fn register(r: &mut Registry) {
    r.node(&CONNECTIVITY, cook_connectivity);
    r.node(&SPLIT, cook_split);
}
