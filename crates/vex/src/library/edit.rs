//! Writing geometry (SideFX's "Geometry" writing functions): attribute
//! writes to any element, new points, primitives and vertices, removals
//! and group membership. Each queues an effect that applies after every
//! element ran, in element order.

use geode_geo::{AttribClass, PrimKind};

use super::support::through_edits;
use super::{a, form, lane, Category, Function, Ret, I, IA, S, T, V};
use crate::effect::{EffectKind, Mode, SetAttr};
use crate::program::{Host, Lane, Numbers, Stop};
use crate::ty::Ty;
use crate::value::Val;

const C: Category = Category::Editing;
const INT: Ret = Ret::Is(Ty::Int);

#[rustfmt::skip]
pub const FUNCTIONS: &[Function] = &[
    lane("setpointattrib", C, "Writes a point attribute of any type (mode: set, add, min, max, mult, append).", &[
        form(INT, &[a(I, "geo"), a(S, "attrib"), a(I, "ptnum"), a(T::Any, "value"), a(S, "mode")], |l, a| set(l, a, AttribClass::Point)).opt(1),
    ]),
    lane("setprimattrib", C, "Writes a primitive attribute of any type (mode: set, add, min, max, mult, append).", &[
        form(INT, &[a(I, "geo"), a(S, "attrib"), a(I, "primnum"), a(T::Any, "value"), a(S, "mode")], |l, a| set(l, a, AttribClass::Primitive)).opt(1),
    ]),
    lane("setvertexattrib", C, "Writes a vertex attribute: by primitive and vertex index, or by linear vertex with primnum -1.", &[
        form(INT, &[a(I, "geo"), a(S, "attrib"), a(I, "primnum"), a(I, "vertex"), a(T::Any, "value"), a(S, "mode")], |l, a| set(l, a, AttribClass::Vertex)).opt(1),
    ]),
    lane("setdetailattrib", C, "Writes a detail attribute of any type (mode: set, add, min, max, mult, append).", &[
        form(INT, &[a(I, "geo"), a(S, "attrib"), a(T::Any, "value"), a(S, "mode")], |l, a| set(l, a, AttribClass::Detail)).opt(1),
    ]),
    lane("setattrib", C, "Writes an attribute of a class (\"point\", \"prim\", \"vertex\", \"detail\"): element, vertex index (-1 for a linear element), value, mode.", &[
        form(INT, &[a(I, "geo"), a(S, "attribclass"), a(S, "attrib"), a(I, "elemnum"), a(I, "vertex"), a(T::Any, "value"), a(S, "mode")], set_any).opt(1),
    ]),
    lane("addpoint", C, "Adds a point at a position, or a copy of a point with its attributes; the number is valid for calls in this element.", &[
        form(INT, &[a(I, "geo"), a(V, "pos")], |l, a| through_edits(l, a, addpoint_at)).edit(addpoint_at),
        form(INT, &[a(I, "geo"), a(I, "ptnum")], |l, a| through_edits(l, a, addpoint_from)).edit(addpoint_from),
    ]),
    lane("addprim", C, "Adds a \"poly\" or \"polyline\" through the given points.", &[
        form(INT, &[a(I, "geo"), a(S, "type"), a(I, "pt")], |l, a| through_edits(l, a, addprim)).opt(1).many().edit(addprim),
        form(INT, &[a(I, "geo"), a(S, "type"), a(IA, "points")], |l, a| through_edits(l, a, addprim)),
    ]),
    lane("addvertex", C, "Appends a vertex on a point to a primitive: a new one, or a polygon or polyline of the input (after the new primitives are added; its new vertex's attributes start at their defaults).", &[
        form(INT, &[a(I, "geo"), a(I, "primnum"), a(I, "ptnum")], |l, a| through_edits(l, a, addvertex)).edit(addvertex),
    ]),
    lane("removepoint", C, "Removes a point and its vertices; primitives left degenerate are removed (unless and_prims is 0).", &[
        form(INT, &[a(I, "geo"), a(I, "ptnum"), a(I, "and_prims")], removepoint).opt(1),
    ]),
    lane("removeprim", C, "Removes a primitive; its points too when andpoints is 1 and nothing else uses them.", &[
        form(INT, &[a(I, "geo"), a(I, "primnum"), a(I, "andpoints")], removeprim).opt(1),
    ]),
    lane("setpointgroup", C, "Puts a point in (1) or out of (0) a point group.", &[
        form(INT, &[a(I, "geo"), a(S, "group"), a(I, "ptnum"), a(I, "value"), a(S, "mode")], |l, a| set_group(l, a, AttribClass::Point)).opt(1),
    ]),
    lane("setprimgroup", C, "Puts a primitive in (1) or out of (0) a primitive group.", &[
        form(INT, &[a(I, "geo"), a(S, "group"), a(I, "primnum"), a(I, "value"), a(S, "mode")], |l, a| set_group(l, a, AttribClass::Primitive)).opt(1),
    ]),
];

fn mode_of(m: Option<&Val>) -> Result<Mode, Stop> {
    Ok(match m.map(Val::s) {
        None | Some("set") => Mode::Set,
        Some("add") => Mode::Add,
        Some("min") => Mode::Min,
        Some("max") => Mode::Max,
        Some("mult") | Some("multiply") => Mode::Mult,
        Some("append") => Mode::Append,
        Some(other) => {
            return Err(Stop::Msg(format!(
                "unknown mode \"{other}\": expected set, add, min, max, mult or append"
            )))
        }
    })
}

fn queue(l: &mut Lane, kind: EffectKind) -> Result<(), Stop> {
    l.host.queue(kind)
}

fn write(
    l: &mut Lane,
    class: AttribClass,
    name: &str,
    target: i32,
    vtx: i32,
    value: Val,
    mode: Mode,
) -> Result<Val, Stop> {
    queue(
        l,
        EffectKind::SetAttr(Box::new(SetAttr {
            class,
            name: name.to_string(),
            target,
            vtx,
            value,
            mode,
        })),
    )?;
    Ok(Val::I(0))
}

/// `(geo, name, [elem, [vtx,]] value, [mode])`.
fn set(l: &mut Lane, a: &mut [Val], class: AttribClass) -> Result<Val, Stop> {
    let (target, vtx, value) = match class {
        AttribClass::Detail => (0, -1, 2),
        AttribClass::Vertex => (a[2].i(), a[3].i(), 4),
        _ => (a[2].i(), -1, 3),
    };
    let mode = mode_of(a.get(value + 1))?;
    let v = a[value].clone();
    write(l, class, a[1].s(), target, vtx, v, mode)
}

fn set_any(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let class = match a[1].s() {
        "point" => AttribClass::Point,
        "prim" | "primitive" => AttribClass::Primitive,
        "vertex" => AttribClass::Vertex,
        "detail" | "global" => AttribClass::Detail,
        other => {
            return Err(Stop::Msg(format!(
                "setattrib: unknown class \"{other}\": expected point, prim, vertex or detail"
            )))
        }
    };
    let mode = mode_of(a.get(6))?;
    let (target, vtx) = match class {
        AttribClass::Vertex => (a[3].i(), a[4].i()),
        AttribClass::Detail => (0, -1),
        _ => (a[3].i(), -1),
    };
    let v = a[5].clone();
    let name = a[2].s().to_string();
    write(l, class, &name, target, vtx, v, mode)
}

/// `addpoint(geo, pos)`.
fn addpoint_at(h: &mut dyn Host, n: &Numbers) -> Result<i32, Stop> {
    let pos = [n.floats[0], n.floats[1], n.floats[2]];
    h.add_point(None, pos)
}

/// `addpoint(geo, ptnum)`: a copy of the point with its attributes.
fn addpoint_from(h: &mut dyn Host, n: &Numbers) -> Result<i32, Stop> {
    let from = n.ints[1];
    h.add_point(Some(from), [from as f32; 3])
}

/// `addprim(geo, type, pt...)` and `addprim(geo, type, points[])`.
fn addprim(h: &mut dyn Host, n: &Numbers) -> Result<i32, Stop> {
    let polyline = match n.text {
        "poly" => false,
        "polyline" => true,
        other => {
            return Err(Stop::Msg(format!(
                "addprim: unknown type \"{other}\": expected \"poly\" or \"polyline\""
            )))
        }
    };
    h.add_prim(polyline, &n.ints[1..])
}

/// `addvertex(geo, prim, point)`: a primitive made by the wrangle, or one
/// of the input's polygons and polylines (which take the vertex after
/// the new primitives are added).
fn addvertex(h: &mut dyn Host, n: &Numbers) -> Result<i32, Stop> {
    let (prim, point) = (n.ints[1], n.ints[2]);
    let kind = usize::try_from(prim)
        .ok()
        .and_then(|p| h.input(0)?.prim_kinds().get(p).copied());
    if let Some(kind) = kind.filter(|k| !matches!(k, PrimKind::Polygon | PrimKind::Polyline)) {
        return Err(Stop::Msg(format!(
            "addvertex: primitive {prim} is a {} primitive: only polygons and polylines take vertices",
            kind.name()
        )));
    }
    h.queue(EffectKind::AddVertex { prim, point })?;
    Ok(0)
}

fn removepoint(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    queue(
        l,
        EffectKind::RemovePoint {
            point: a[1].i(),
            and_prims: a.get(2).is_none_or(|v| v.i() != 0),
        },
    )?;
    Ok(Val::I(1))
}

fn removeprim(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    queue(
        l,
        EffectKind::RemovePrim {
            prim: a[1].i(),
            and_points: a.get(2).is_some_and(|v| v.i() != 0),
        },
    )?;
    Ok(Val::I(1))
}

fn set_group(l: &mut Lane, a: &mut [Val], class: AttribClass) -> Result<Val, Stop> {
    // "Use "set" to set the membership according to the value. Use
    // "toggle" to toggle the membership, regardless of the value."
    let on = a.get(3).is_none_or(|v| v.i() != 0);
    let on = match a.get(4).map(Val::s) {
        None | Some("set") => Some(on),
        Some("add") | Some("or") => Some(on),
        Some("subtract") | Some("remove") => Some(!on),
        Some("toggle") => None,
        Some(other) => {
            return Err(Stop::Msg(format!(
                "unknown group mode \"{other}\": expected set or toggle"
            )))
        }
    };
    queue(
        l,
        EffectKind::SetGroup {
            class,
            name: a[1].s().to_string(),
            target: a[2].i(),
            on,
        },
    )?;
    Ok(Val::I(0))
}
