//! Mesh nodes: delete, normals, fuse, triangulate.

use geode_geo::{ops, AttribClass, AttribData, Attribute, Group, TypeInfo};
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{class, geometry, input_owned, ELEMENT_CLASSES};

const DELETE_GROUP: P = P::new(
    "group",
    "Group",
    T::String,
    D::Str(""),
    "What to delete: a group pattern (`top`, `0-9:2 ^3`, `@P.y>0`, `!keep*`); empty selects everything.",
);
const DELETE_CLASS: P = P::new(
    "class",
    "Class",
    T::Menu(ELEMENT_CLASSES),
    D::Str("primitive"),
    "Whether the group holds points or primitives.",
);
const DELETE_INVERT: P = P::new(
    "invert",
    "Delete non-selected",
    T::Toggle,
    D::Toggle(false),
    "Keep the group, delete the rest.",
);
const DELETE_KEEP_POINTS: P = P::new(
    "keep_points",
    "Keep unused points",
    T::Toggle,
    D::Toggle(false),
    "When deleting primitives, keep points no longer used.",
);

static DELETE: NodeSpec = NodeSpec::new(
    "delete",
    "Delete",
    "mesh",
    "Deletes the points or primitives a group pattern selects, or all but them (Houdini's Blast). Deleting points deletes the primitives that use them.",
    &[geometry_input("geometry")],
    &DELETE_PARAMS,
);

static DELETE_PARAMS: [P; 4] = [
    DELETE_GROUP,
    DELETE_CLASS,
    DELETE_INVERT,
    DELETE_KEEP_POINTS,
];

/// Houdini's name for the same node.
static BLAST: NodeSpec = NodeSpec::new(
    "blast",
    "Blast",
    "mesh",
    "Deletes the points or primitives a group pattern selects, or all but them: the same node as `delete`, under Houdini's name.",
    &[geometry_input("geometry")],
    &DELETE_PARAMS,
);

fn cook_delete(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let c = class(p, &DELETE_CLASS)?;
    let mut sel = match crate::util::group_param(ctx, p, &DELETE_GROUP, &g, c)? {
        Some(grp) => grp,
        None => Group::from_flags((0..crate::util::count(&g, c)).map(|_| true)),
    };
    if p.toggle(&DELETE_INVERT)? {
        sel = Group::from_flags((0..sel.len()).map(|i| !sel.contains(i)));
    }
    if c == AttribClass::Primitive {
        ops::delete_prims(&mut g, &sel, !p.toggle(&DELETE_KEEP_POINTS)?);
    } else {
        ops::delete_points(&mut g, &sel);
    }
    geometry(g)
}

const NORMALS_CLASS: P = P::new(
    "class",
    "Add to",
    T::Menu(&["point", "vertex", "primitive"]),
    D::Str("vertex"),
    "Where N is stored.",
);
const NORMALS_CUSP_ANGLE: P = P::new(
    "cusp_angle",
    "Cusp angle",
    T::Float,
    D::Float(60.0),
    "Vertex normals: faces meeting at a sharper angle keep separate normals.",
)
.range(0.0, 180.0);

static NORMALS: NodeSpec = NodeSpec::new(
    "normals",
    "Normals",
    "mesh",
    "Computes `N`: angle-weighted point normals, vertex normals split where faces meet at more than the cusp angle, or face normals.",
    &[geometry_input("geometry")],
    &[
        NORMALS_CLASS,
        NORMALS_CUSP_ANGLE,
    ],
);

fn cook_normals(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let c = class(p, &NORMALS_CLASS)?;
    let n = match c {
        AttribClass::Point => ops::point_normals(&g),
        AttribClass::Primitive => ops::prim_normals(&g),
        _ => ops::vertex_normals(&g, p.float(&NORMALS_CUSP_ANGLE)? as f32),
    };
    // One N only: a stale N on another class would win in some writers.
    for other in [
        AttribClass::Point,
        AttribClass::Vertex,
        AttribClass::Primitive,
    ] {
        if other != c {
            let _ = g.remove_attrib(other, "N");
        }
    }
    g.set_attrib(
        c,
        "N",
        Attribute::from_data(AttribData::Vec3(n), TypeInfo::Normal),
    )
    .map_err(|e| ctx.kernel(e))?;
    geometry(g)
}

const FUSE_DISTANCE: P = P::new(
    "distance",
    "Distance",
    T::Float,
    D::Float(0.001),
    "Points closer than this are merged.",
)
.at_least(0.0);

static FUSE: NodeSpec = NodeSpec::new(
    "fuse",
    "Fuse",
    "mesh",
    "Merges points closer than a distance (transitively) into their average; collapses degenerate primitives.",
    &[geometry_input("geometry")],
    &[
        FUSE_DISTANCE,
    ],
);

fn cook_fuse(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    ops::fuse_points(&mut g, p.float(&FUSE_DISTANCE)? as f32);
    geometry(g)
}

static TRIANGULATE: NodeSpec = NodeSpec::new("triangulate", "Triangulate", "mesh", "Splits polygons into triangles: fans for convex ones, ear clipping for concave ones. Attributes carry over.", &[geometry_input("geometry")], &[]);

fn cook_triangulate(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    _: &Params,
) -> Result<Value, CookError> {
    let g = input_owned(ctx, inputs, 0)?;
    geometry(ops::triangulate(&g, None))
}

pub fn register(r: &mut Registry) {
    r.node(&DELETE, cook_delete);
    r.node(&BLAST, cook_delete);
    r.node(&NORMALS, cook_normals);
    r.node(&FUSE, cook_fuse);
    r.node(&TRIANGULATE, cook_triangulate);
}
