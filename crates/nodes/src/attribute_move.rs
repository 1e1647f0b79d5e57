//! Nodes that move attributes between classes or rename and delete them:
//! attribute_promote, attribute_rename, attribute_delete.

use geode_attrib::promote::{promote, Combine};
use geode_attrib::AttribError;
use geode_geo::pattern::match_names;
use geode_geo::{AttribClass, Geometry};
use geode_op::{
    geometry_input, CookContext, CookError, ListSpec, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{attribute_name, class, geometry, input_owned, CLASSES};

/// A kernel error at parameter `param`, about attribute `name`.
pub(crate) fn attrib_error(ctx: &CookContext, param: &P, name: &str, e: AttribError) -> CookError {
    match e {
        AttribError::Cancelled => CookError::cancelled(ctx.path),
        AttribError::Invalid(why) => ctx.param_error(param, format!("`{name}`: {why}")),
    }
}

const PROMOTE_NAME: P = P::new(
    "name",
    "Original name",
    T::String,
    D::Str(""),
    "The attribute to promote, or a name pattern (`Cd uv*`, `* ^P`): each match is promoted; empty promotes nothing.",
);
const PROMOTE_FROM: P = P::new(
    "from",
    "Original class",
    T::Menu(CLASSES),
    D::Str("point"),
    "The class the attribute is on.",
);
const PROMOTE_TO: P = P::new(
    "to",
    "New class",
    T::Menu(CLASSES),
    D::Str("primitive"),
    "The class to promote it to.",
);
const PROMOTE_METHOD: P = P::new(
    "method",
    "Promotion method",
    T::Menu(&Combine::NAMES),
    D::Str("average"),
    "How the values an element gathers combine: average, min, max, sum, first, last, mode (most common; ties to the first), or area_average (each weighted by the area it stands for). Strings take first, last, mode, min and max.",
);
const PROMOTE_NEW_NAME: P = P::new(
    "new_name",
    "New name",
    T::String,
    D::Str(""),
    "The promoted attribute's name; empty keeps the original's (one attribute only).",
);
const PROMOTE_DELETE: P = P::new(
    "delete_original",
    "Delete original",
    T::Toggle,
    D::Toggle(true),
    "Remove the attribute from its original class.",
);

static PROMOTE: NodeSpec = NodeSpec::new(
    "attribute_promote",
    "Attribute Promote",
    "attribute",
    "Moves attributes between point, vertex, primitive and detail (Houdini's Attribute Promote): each element combines the values of the elements it touches.",
    &[geometry_input("geometry")],
    &[
        PROMOTE_NAME,
        PROMOTE_FROM,
        PROMOTE_TO,
        PROMOTE_METHOD,
        PROMOTE_NEW_NAME,
        PROMOTE_DELETE,
    ],
);

fn cook_promote(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let (from, to) = (class(p, &PROMOTE_FROM)?, class(p, &PROMOTE_TO)?);
    let how = Combine::from_name(p.string(&PROMOTE_METHOD)?).unwrap_or(Combine::Average);
    let pattern = p.string(&PROMOTE_NAME)?;
    if pattern.trim().is_empty() {
        return geometry(g);
    }
    let names = names_matching(ctx, &PROMOTE_NAME, pattern, &g, from)?;
    let new_name = p.string(&PROMOTE_NEW_NAME)?;
    if !new_name.is_empty() {
        attribute_name(ctx, &PROMOTE_NEW_NAME, new_name)?;
        if names.len() > 1 {
            return Err(ctx.param_error(
                &PROMOTE_NEW_NAME,
                format!(
                    "one new name for {} attributes ({}): leave it empty to keep their names",
                    names.len(),
                    names.join(", ")
                ),
            ));
        }
    }
    let cancel = ctx.cancel_fn();
    for name in names {
        let attr = g
            .attrib(from, &name)
            .expect("matched on this geometry")
            .clone();
        let promoted = promote(&g, &attr, from, to, how, &cancel)
            .map_err(|e| attrib_error(ctx, &PROMOTE_METHOD, &name, e))?;
        // P stays on the points whatever is asked: it is their position.
        if p.toggle(&PROMOTE_DELETE)? && !(from == AttribClass::Point && name == geode_geo::P) {
            let _ = g.remove_attrib(from, &name);
        }
        let target = if new_name.is_empty() { &name } else { new_name };
        g.set_attrib(to, target, promoted)
            .map_err(|e| ctx.kernel_at(&PROMOTE_NAME, e))?;
    }
    geometry(g)
}

/// The attributes of class `c` a name pattern selects; none is an error.
pub(crate) fn names_matching(
    ctx: &CookContext,
    spec: &P,
    pattern: &str,
    g: &Geometry,
    c: AttribClass,
) -> Result<Vec<String>, CookError> {
    let names: Vec<String> = match_names(pattern, g.attribs(c).names())
        .into_iter()
        .map(str::to_owned)
        .collect();
    if names.is_empty() {
        crate::util::attribute_of(ctx, spec, g, c, pattern)?;
    }
    Ok(names)
}

const RENAME_FROM: P = P::new(
    "from",
    "From",
    T::String,
    D::Str(""),
    "The attribute's name now.",
)
.not_animatable();

const RENAME_TO: P = P::new("to", "To", T::String, D::Str(""), "Its new name.").not_animatable();

static RENAME_ROWS: ListSpec = ListSpec {
    fields: &[RENAME_FROM, RENAME_TO],
    legacy: None,
};
const RENAME_CLASS: P = P::new(
    "class",
    "Class",
    T::Menu(CLASSES),
    D::Str("point"),
    "The class of the attributes to rename.",
);
const RENAME_PAIRS: P = P::list(
    "renames",
    "Renames",
    &RENAME_ROWS,
    "One row per attribute: its name and its new name, applied in order (an attribute already of the new name is replaced).",
);

static RENAME: NodeSpec = NodeSpec::new(
    "attribute_rename",
    "Attribute Rename",
    "attribute",
    "Renames attributes of one class (Houdini's Attribute Rename).",
    &[geometry_input("geometry")],
    &[RENAME_CLASS, RENAME_PAIRS],
);

fn cook_rename(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let c = class(p, &RENAME_CLASS)?;
    for row in p.list(&RENAME_PAIRS)? {
        let (from, to) = (row.string(&RENAME_FROM)?, row.string(&RENAME_TO)?);
        if from.is_empty() && to.is_empty() {
            continue;
        }
        let attr = crate::util::attribute_of(ctx, &RENAME_PAIRS, &g, c, from)?.clone();
        attribute_name(ctx, &RENAME_PAIRS, to)?;
        if c == AttribClass::Point && (from == geode_geo::P || to == geode_geo::P) {
            return Err(ctx.param_error(
                &RENAME_PAIRS,
                "P is the points' position: it cannot be renamed or replaced",
            ));
        }
        let _ = g.remove_attrib(c, from);
        g.set_attrib(c, to, attr)
            .map_err(|e| ctx.kernel_at(&RENAME_PAIRS, e))?;
    }
    geometry(g)
}

const DELETE_POINT: P = P::new("point", "Point attributes", T::String, D::Str(""), "Point attributes to delete: names with wildcards, `^name` to spare one (`* ^N`). P is never deleted.");
const DELETE_VERTEX: P = P::new(
    "vertex",
    "Vertex attributes",
    T::String,
    D::Str(""),
    "Vertex attributes to delete, as a name pattern.",
);
const DELETE_PRIMITIVE: P = P::new(
    "primitive",
    "Primitive attributes",
    T::String,
    D::Str(""),
    "Primitive attributes to delete, as a name pattern.",
);
const DELETE_DETAIL: P = P::new(
    "detail",
    "Detail attributes",
    T::String,
    D::Str(""),
    "Detail attributes to delete, as a name pattern.",
);
const DELETE_INVERT: P = P::new(
    "invert",
    "Delete non-selected",
    T::Toggle,
    D::Toggle(false),
    "Keep the attributes the patterns select and delete the others.",
);

static DELETE: NodeSpec = NodeSpec::new(
    "attribute_delete",
    "Attribute Delete",
    "attribute",
    "Deletes attributes by name pattern, per class (Houdini's Attribute Delete).",
    &[geometry_input("geometry")],
    &[
        DELETE_POINT,
        DELETE_VERTEX,
        DELETE_PRIMITIVE,
        DELETE_DETAIL,
        DELETE_INVERT,
    ],
);

fn cook_delete(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let invert = p.toggle(&DELETE_INVERT)?;
    for (spec, c) in [
        (&DELETE_POINT, AttribClass::Point),
        (&DELETE_VERTEX, AttribClass::Vertex),
        (&DELETE_PRIMITIVE, AttribClass::Primitive),
        (&DELETE_DETAIL, AttribClass::Detail),
    ] {
        let pattern = p.string(spec)?;
        let all: Vec<String> = g.attribs(c).names().map(str::to_owned).collect();
        let picked = match_names(pattern, all.iter().map(String::as_str));
        let doomed: Vec<String> = all
            .iter()
            .filter(|n| picked.contains(&n.as_str()) != invert)
            .filter(|n| !(c == AttribClass::Point && n.as_str() == geode_geo::P))
            .cloned()
            .collect();
        for name in doomed {
            let _ = g.remove_attrib(c, &name);
        }
    }
    geometry(g)
}

pub fn register(r: &mut Registry) {
    r.node(&PROMOTE, cook_promote);
    r.node(&RENAME, cook_rename);
    r.node(&DELETE, cook_delete);
}
