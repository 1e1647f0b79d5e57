//! Reading geometry (SideFX's "Attributes and intrinsics", "Geometry",
//! "Groups" and half-edge categories): attribute values of any element of
//! any input, counts, the vertex, point and primitive numbering
//! functions, group queries and group patterns, and half-edges.

use std::sync::Arc;

use geode_geo::{AttribClass, Geometry, PrimKind, Topology};

use super::{a, form, lane, Category, Function, Ret, I, S};
use crate::program::{Lane, Stop};
use crate::ty::{Elem, Ty};
use crate::value::{read_attrib, Val};

const A: Category = Category::Attributes;
const G: Category = Category::Geometry;
const GR: Category = Category::Groups;
const H: Category = Category::Topology;

const INT: Ret = Ret::Is(Ty::Int);
const INTS: Ret = Ret::Is(Ty::Array(Elem::Int));

#[rustfmt::skip]
pub const FUNCTIONS: &[Function] = &[
    lane("point", A, "A point attribute of input geo; its type is the attribute's (or the declared one).", &[
        form(Ret::Attrib(AttribClass::Point), &[a(I, "geo"), a(S, "attrib"), a(I, "ptnum")], read_point),
    ]),
    lane("prim", A, "A primitive attribute of input geo; its type is the attribute's (or the declared one).", &[
        form(Ret::Attrib(AttribClass::Primitive), &[a(I, "geo"), a(S, "attrib"), a(I, "primnum")], read_prim),
    ]),
    lane("vertex", A, "A vertex attribute by linear vertex number, or by primitive and its vertex index.", &[
        form(Ret::Attrib(AttribClass::Vertex), &[a(I, "geo"), a(S, "attrib"), a(I, "linearvertex")], read_vertex),
        form(Ret::Attrib(AttribClass::Vertex), &[a(I, "geo"), a(S, "attrib"), a(I, "primnum"), a(I, "vertex")], read_vertex),
    ]),
    lane("detail", A, "A detail attribute of input geo.", &[
        form(Ret::Attrib(AttribClass::Detail), &[a(I, "geo"), a(S, "attrib"), a(I, "ignored")], read_detail).opt(1),
    ]),
    lane("haspointattrib", A, "1 if input geo has the point attribute.", &[
        form(INT, &[a(I, "geo"), a(S, "attrib")], has_point),
    ]),
    lane("hasprimattrib", A, "1 if input geo has the primitive attribute.", &[
        form(INT, &[a(I, "geo"), a(S, "attrib")], has_prim),
    ]),
    lane("hasvertexattrib", A, "1 if input geo has the vertex attribute.", &[
        form(INT, &[a(I, "geo"), a(S, "attrib")], has_vertex),
    ]),
    lane("hasdetailattrib", A, "1 if input geo has the detail attribute.", &[
        form(INT, &[a(I, "geo"), a(S, "attrib")], has_detail),
    ]),
    lane("hasattrib", A, "1 if input geo has the attribute of class (\"point\", \"prim\", \"vertex\", \"detail\").", &[
        form(INT, &[a(I, "geo"), a(S, "attribclass"), a(S, "attrib")], has_attrib),
    ]),
    lane("attribsize", A, "The number of components of an attribute (0 if missing).", &[
        form(INT, &[a(I, "geo"), a(S, "attribclass"), a(S, "attrib")], attribsize),
    ]),
    lane("attribtype", A, "An attribute's type: 0 int, 1 float, 2 string, 3 int array, 4 float array, 5 string array; -1 if missing.", &[
        form(INT, &[a(I, "geo"), a(S, "attribclass"), a(S, "attrib")], attribtype),
    ]),
    lane("findattribval", A, "The first element (or the which-th) whose attribute equals value; -1 if none.", &[
        form(INT, &[a(I, "geo"), a(S, "attribclass"), a(S, "attrib"), a(super::T::Any, "value"), a(I, "which")], findattribval).opt(1),
    ]),
    lane("findattribvalcount", A, "How many elements' attribute equals value.", &[
        form(INT, &[a(I, "geo"), a(S, "attribclass"), a(S, "attrib"), a(super::T::Any, "value")], findattribvalcount),
    ]),
    lane("nuniqueval", A, "How many distinct values an int or string attribute holds.", &[
        form(INT, &[a(I, "geo"), a(S, "attribclass"), a(S, "attrib")], nuniqueval),
    ]),
    lane("uniqueval", A, "The which-th distinct value (in first-seen order) of an int or string attribute.", &[
        form(Ret::Context(&[Ty::Int, Ty::Str, Ty::Float]), &[a(I, "geo"), a(S, "attribclass"), a(S, "attrib"), a(I, "which")], uniqueval),
    ]),
    lane("npoints", G, "Number of points of input geo.", &[
        form(INT, &[a(I, "geo")], npoints),
    ]),
    lane("nprimitives", G, "Number of primitives of input geo.", &[
        form(INT, &[a(I, "geo")], nprimitives),
    ]),
    lane("nvertices", G, "Number of vertices of input geo, or of one primitive.", &[
        form(INT, &[a(I, "geo")], nvertices),
        form(INT, &[a(I, "geo"), a(I, "primnum")], primvertexcount),
    ]),
    lane("primvertexcount", G, "Number of vertices of a primitive.", &[
        form(INT, &[a(I, "geo"), a(I, "primnum")], primvertexcount),
    ]),
    lane("primpoints", G, "The points of a primitive, in vertex order.", &[
        form(INTS, &[a(I, "geo"), a(I, "primnum")], primpoints),
    ]),
    lane("primpoint", G, "The point of a primitive's vertex (by its index in the primitive).", &[
        form(INT, &[a(I, "geo"), a(I, "primnum"), a(I, "vertex")], primpoint),
    ]),
    lane("primvertex", G, "The linear vertex number of a primitive's vertex.", &[
        form(INT, &[a(I, "geo"), a(I, "primnum"), a(I, "vertex")], vertexindex),
    ]),
    lane("primvertices", G, "The linear vertex numbers of a primitive.", &[
        form(INTS, &[a(I, "geo"), a(I, "primnum")], primvertices),
    ]),
    lane("vertexindex", G, "The linear vertex number of a primitive's vertex (-1 if none).", &[
        form(INT, &[a(I, "geo"), a(I, "primnum"), a(I, "vertex")], vertexindex),
    ]),
    lane("vertexpoint", G, "The point of a linear vertex.", &[
        form(INT, &[a(I, "geo"), a(I, "linearvertex")], vertexpoint),
    ]),
    lane("vertexprim", G, "The primitive of a linear vertex.", &[
        form(INT, &[a(I, "geo"), a(I, "linearvertex")], vertexprim),
    ]),
    lane("vertexprimindex", G, "The index within its primitive of a linear vertex.", &[
        form(INT, &[a(I, "geo"), a(I, "linearvertex")], vertexprimindex),
    ]),
    lane("pointvertex", G, "The first linear vertex on a point (-1 if none).", &[
        form(INT, &[a(I, "geo"), a(I, "ptnum")], pointvertex),
    ]),
    lane("pointvertices", G, "The linear vertices on a point, in order.", &[
        form(INTS, &[a(I, "geo"), a(I, "ptnum")], pointvertices),
    ]),
    lane("vertexnext", G, "The next linear vertex on the same point (-1 if none).", &[
        form(INT, &[a(I, "geo"), a(I, "linearvertex")], vertexnext),
    ]),
    lane("vertexprev", G, "The previous linear vertex on the same point (-1 if none).", &[
        form(INT, &[a(I, "geo"), a(I, "linearvertex")], vertexprev),
    ]),
    lane("pointprims", G, "The primitives that use a point.", &[
        form(INTS, &[a(I, "geo"), a(I, "ptnum")], pointprims),
    ]),
    lane("neighbours", G, "The points sharing an edge with a point.", &[
        form(INTS, &[a(I, "geo"), a(I, "ptnum")], neighbours),
    ]),
    lane("neighbour", G, "The n-th point sharing an edge with a point (-1 if none).", &[
        form(INT, &[a(I, "geo"), a(I, "ptnum"), a(I, "n")], neighbour),
    ]),
    lane("neighbourcount", G, "Number of points sharing an edge with a point.", &[
        form(INT, &[a(I, "geo"), a(I, "ptnum")], neighbourcount),
    ]),
    lane("inpointgroup", GR, "1 if the point is in the point group.", &[
        form(INT, &[a(I, "geo"), a(S, "group"), a(I, "ptnum")], inpointgroup),
    ]),
    lane("inprimgroup", GR, "1 if the primitive is in the primitive group.", &[
        form(INT, &[a(I, "geo"), a(S, "group"), a(I, "primnum")], inprimgroup),
    ]),
    lane("npointsgroup", GR, "Number of points in a point group.", &[
        form(INT, &[a(I, "geo"), a(S, "group")], npointsgroup),
    ]),
    lane("nprimitivesgroup", GR, "Number of primitives in a primitive group.", &[
        form(INT, &[a(I, "geo"), a(S, "group")], nprimitivesgroup),
    ]),
    lane("expandpointgroup", GR, "The points a group pattern names, in its order: numbers, ranges a-b[:step], * (or an empty pattern) for all, group names and globs, !x for all but x, ^x to remove x.", &[
        form(INTS, &[a(I, "geo"), a(S, "pattern")], expandpointgroup),
    ]),
    lane("expandprimgroup", GR, "The primitives a group pattern names, in its order: numbers, ranges a-b[:step], * (or an empty pattern) for all, group names and globs, !x for all but x, ^x to remove x.", &[
        form(INTS, &[a(I, "geo"), a(S, "pattern")], expandprimgroup),
    ]),
    lane("pointhedge", H, "A half-edge leaving the point (-1 if none).", &[
        form(INT, &[a(I, "geo"), a(I, "ptnum")], |l, a| hedge_call(l, a, Hedge::FromPoint)),
    ]),
    lane("primhedge", H, "The first half-edge of the primitive.", &[
        form(INT, &[a(I, "geo"), a(I, "primnum")], |l, a| hedge_call(l, a, Hedge::FromPrim)),
    ]),
    lane("hedge_next", H, "The next half-edge around its primitive.", &[
        form(INT, &[a(I, "geo"), a(I, "hedge")], |l, a| hedge_call(l, a, Hedge::Next)),
    ]),
    lane("hedge_srcpoint", H, "The point a half-edge starts at.", &[
        form(INT, &[a(I, "geo"), a(I, "hedge")], |l, a| hedge_call(l, a, Hedge::SrcPoint)),
    ]),
    lane("hedge_dstpoint", H, "The point a half-edge ends at.", &[
        form(INT, &[a(I, "geo"), a(I, "hedge")], |l, a| hedge_call(l, a, Hedge::DstPoint)),
    ]),
    lane("hedge_srcvertex", H, "The linear vertex a half-edge starts at.", &[
        form(INT, &[a(I, "geo"), a(I, "hedge")], |l, a| hedge_call(l, a, Hedge::SrcVertex)),
    ]),
    lane("hedge_dstvertex", H, "The linear vertex a half-edge ends at.", &[
        form(INT, &[a(I, "geo"), a(I, "hedge")], |l, a| hedge_call(l, a, Hedge::DstVertex)),
    ]),
    lane("hedge_isvalid", H, "1 if the half-edge exists.", &[
        form(INT, &[a(I, "geo"), a(I, "hedge")], |l, a| hedge_call(l, a, Hedge::IsValid)),
    ]),
    lane("hedge_prim", H, "The primitive of a half-edge.", &[
        form(INT, &[a(I, "geo"), a(I, "hedge")], |l, a| hedge_call(l, a, Hedge::Prim)),
    ]),
];

fn class_of(name: &str) -> Option<AttribClass> {
    Some(match name {
        "point" | "pt" => AttribClass::Point,
        "prim" | "primitive" => AttribClass::Primitive,
        "vertex" | "vtx" => AttribClass::Vertex,
        "detail" | "global" => AttribClass::Detail,
        _ => return None,
    })
}

/// The value read, or the zero of the type the call asked for.
fn read(lane: &Lane, geo: i32, class: AttribClass, name: &str, idx: i32) -> Val {
    lane.host
        .input(geo)
        .and_then(|g| read_attrib(g, class, name, idx))
        .unwrap_or_else(|| super::support::empty_like(lane.out))
}

fn read_point(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(read(l, a[0].i(), AttribClass::Point, a[1].s(), a[2].i()))
}

fn read_prim(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(read(
        l,
        a[0].i(),
        AttribClass::Primitive,
        a[1].s(),
        a[2].i(),
    ))
}

fn read_vertex(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let v = match a.get(3) {
        Some(k) => l
            .host
            .input(a[0].i())
            .and_then(|g| linear_vertex(g, a[2].i(), k.i()))
            .map_or(-1, |v| v as i32),
        None => a[2].i(),
    };
    Ok(read(l, a[0].i(), AttribClass::Vertex, a[1].s(), v))
}

fn read_detail(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(read(l, a[0].i(), AttribClass::Detail, a[1].s(), 0))
}

fn has(l: &Lane, geo: &Val, class: AttribClass, name: &str) -> Val {
    Val::I(i32::from(l.host.input(geo.i()).is_some_and(|g| {
        g.attrib(class, name).is_some() || (class == AttribClass::Point && name == "P")
    })))
}

fn has_point(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(has(l, &a[0], AttribClass::Point, a[1].s()))
}

fn has_prim(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(has(l, &a[0], AttribClass::Primitive, a[1].s()))
}

fn has_vertex(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(has(l, &a[0], AttribClass::Vertex, a[1].s()))
}

fn has_detail(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(has(l, &a[0], AttribClass::Detail, a[1].s()))
}

fn has_attrib(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(match class_of(a[1].s()) {
        Some(c) => has(l, &a[0], c, a[2].s()),
        None => Val::I(0),
    })
}

fn attribsize(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let Some((g, c)) = l.host.input(a[0].i()).zip(class_of(a[1].s())) else {
        return Ok(Val::I(0));
    };
    if c == AttribClass::Point && a[2].s() == "P" {
        return Ok(Val::I(3));
    }
    Ok(Val::I(g.attrib(c, a[2].s()).map_or(0, |at| {
        crate::ty::ty_of(at.data()).map_or(1, |t| match t {
            Ty::Array(e) => e.ty().floats() as i32,
            Ty::Str | Ty::Int => 1,
            t => t.floats() as i32,
        })
    })))
}

fn attribtype(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let Some((g, c)) = l.host.input(a[0].i()).zip(class_of(a[1].s())) else {
        return Ok(Val::I(-1));
    };
    if c == AttribClass::Point && a[2].s() == "P" {
        return Ok(Val::I(1));
    }
    Ok(Val::I(g.attrib(c, a[2].s()).map_or(
        -1,
        |at| match crate::ty::ty_of(at.data()) {
            Some(Ty::Int) => 0,
            Some(Ty::Str) => 2,
            Some(Ty::Array(Elem::Int)) => 3,
            Some(Ty::Array(Elem::Str)) => 5,
            Some(Ty::Array(_)) => 4,
            _ => 1,
        },
    )))
}

/// The elements of `class` whose attribute equals `value`, in order.
fn matching<'g>(
    g: &'g Geometry,
    class: AttribClass,
    name: &'g str,
    value: &'g Val,
) -> impl Iterator<Item = usize> + 'g {
    let n = count(g, class);
    (0..n).filter(move |&i| read_attrib(g, class, name, i as i32).is_some_and(|v| same(&v, value)))
}

fn same(v: &Val, x: &Val) -> bool {
    match (v, x) {
        (Val::S(a), b) => a == b.s(),
        (Val::I(a), b) => *a == b.i(),
        (a, b) => a.floats() == b.floats() || (a.floats().len() == 1 && a.f() == b.f()),
    }
}

fn count(g: &Geometry, class: AttribClass) -> usize {
    match class {
        AttribClass::Point => g.num_points(),
        AttribClass::Primitive => g.num_prims(),
        AttribClass::Vertex => g.num_vertices(),
        AttribClass::Detail => 1,
    }
}

fn findattribval(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let Some((g, c)) = l.host.input(a[0].i()).zip(class_of(a[1].s())) else {
        return Ok(Val::I(-1));
    };
    let which = a.get(4).map_or(0, |w| w.i().max(0) as usize);
    Ok(Val::I(
        matching(g, c, a[2].s(), &a[3])
            .nth(which)
            .map_or(-1, |i| i as i32),
    ))
}

fn findattribvalcount(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let Some((g, c)) = l.host.input(a[0].i()).zip(class_of(a[1].s())) else {
        return Ok(Val::I(0));
    };
    Ok(Val::I(matching(g, c, a[2].s(), &a[3]).count() as i32))
}

/// The distinct values of an attribute, in the order first seen.
fn distinct(g: &Geometry, class: AttribClass, name: &str) -> Vec<Val> {
    let mut seen: Vec<Val> = Vec::new();
    let mut keys = std::collections::HashSet::new();
    for i in 0..count(g, class) {
        if let Some(v) = read_attrib(g, class, name, i as i32) {
            let key = format!("{v:?}");
            if keys.insert(key) {
                seen.push(v);
            }
        }
    }
    seen
}

fn nuniqueval(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let Some((g, c)) = l.host.input(a[0].i()).zip(class_of(a[1].s())) else {
        return Ok(Val::I(0));
    };
    Ok(Val::I(distinct(g, c, a[2].s()).len() as i32))
}

fn uniqueval(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let found = l
        .host
        .input(a[0].i())
        .zip(class_of(a[1].s()))
        .and_then(|(g, c)| {
            usize::try_from(a[3].i())
                .ok()
                .and_then(|k| distinct(g, c, a[2].s()).into_iter().nth(k))
        });
    Ok(found.unwrap_or_else(|| super::support::empty_like(l.out)))
}

fn input_count(l: &Lane, geo: &Val, f: impl Fn(&Geometry) -> usize) -> Val {
    Val::I(l.host.input(geo.i()).map_or(0, |g| f(g) as i32))
}

fn npoints(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(input_count(l, &a[0], Geometry::num_points))
}

fn nprimitives(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(input_count(l, &a[0], Geometry::num_prims))
}

fn nvertices(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(input_count(l, &a[0], Geometry::num_vertices))
}

fn prim_index(g: &Geometry, prim: i32) -> Option<usize> {
    usize::try_from(prim).ok().filter(|&p| p < g.num_prims())
}

fn vertex_index(g: &Geometry, v: i32) -> Option<usize> {
    usize::try_from(v).ok().filter(|&v| v < g.num_vertices())
}

/// The linear vertex of a primitive's `k`-th vertex.
fn linear_vertex(g: &Geometry, prim: i32, k: i32) -> Option<usize> {
    let r = g.prim_vertex_range(prim_index(g, prim)?);
    let k = usize::try_from(k).ok().filter(|&k| k < r.len())?;
    Some(r.start + k)
}

/// The primitive that holds linear vertex `v`.
fn prim_of_vertex(g: &Geometry, v: usize) -> usize {
    g.prim_offsets().partition_point(|&o| o as usize <= v) - 1
}

fn primvertexcount(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(l.host.input(a[0].i()).map_or(0, |g| {
        prim_index(g, a[1].i()).map_or(0, |p| g.prim_vertex_range(p).len() as i32)
    })))
}

fn primpoints(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::AI(l.host.input(a[0].i()).map_or(Vec::new(), |g| {
        prim_index(g, a[1].i()).map_or(Vec::new(), |p| {
            g.prim_points(p).iter().map(|&p| p as i32).collect()
        })
    })))
}

fn primpoint(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(l.host.input(a[0].i()).map_or(-1, |g| {
        linear_vertex(g, a[1].i(), a[2].i()).map_or(-1, |v| g.vertex_points()[v] as i32)
    })))
}

fn vertexindex(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(l.host.input(a[0].i()).map_or(-1, |g| {
        linear_vertex(g, a[1].i(), a[2].i()).map_or(-1, |v| v as i32)
    })))
}

fn primvertices(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::AI(l.host.input(a[0].i()).map_or(Vec::new(), |g| {
        prim_index(g, a[1].i()).map_or(Vec::new(), |p| {
            g.prim_vertex_range(p).map(|v| v as i32).collect()
        })
    })))
}

fn vertexpoint(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(l.host.input(a[0].i()).map_or(-1, |g| {
        vertex_index(g, a[1].i()).map_or(-1, |v| g.vertex_points()[v] as i32)
    })))
}

fn vertexprim(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(l.host.input(a[0].i()).map_or(-1, |g| {
        vertex_index(g, a[1].i()).map_or(-1, |v| prim_of_vertex(g, v) as i32)
    })))
}

fn vertexprimindex(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(l.host.input(a[0].i()).map_or(-1, |g| {
        vertex_index(g, a[1].i()).map_or(-1, |v| {
            (v - g.prim_vertex_range(prim_of_vertex(g, v)).start) as i32
        })
    })))
}

/// The linear vertices on point `pt`, in vertex order.
fn vertices_of_point(l: &Lane, geo: i32, pt: i32) -> Vec<usize> {
    let (Some(g), Some(t)) = (l.host.input(geo), l.host.topology(geo)) else {
        return Vec::new();
    };
    let Some(p) = usize::try_from(pt).ok().filter(|&p| p < g.num_points()) else {
        return Vec::new();
    };
    let mut vs: Vec<usize> = t
        .point_prims(p)
        .iter()
        .flat_map(|&prim| g.prim_vertex_range(prim as usize))
        .filter(|&v| g.vertex_points()[v] as usize == p)
        .collect();
    vs.sort_unstable();
    vs.dedup();
    vs
}

fn pointvertex(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(
        vertices_of_point(l, a[0].i(), a[1].i())
            .first()
            .map_or(-1, |&v| v as i32),
    ))
}

fn pointvertices(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::AI(
        vertices_of_point(l, a[0].i(), a[1].i())
            .into_iter()
            .map(|v| v as i32)
            .collect(),
    ))
}

/// The vertex before (`step` -1) or after (+1) `v` among its point's.
fn vertex_step(l: &Lane, geo: i32, v: i32, step: isize) -> i32 {
    let Some(g) = l.host.input(geo) else {
        return -1;
    };
    let Some(v) = vertex_index(g, v) else {
        return -1;
    };
    let pt = g.vertex_points()[v] as i32;
    let vs = vertices_of_point(l, geo, pt);
    let k = vs.iter().position(|&x| x == v).unwrap_or(0) as isize + step;
    usize::try_from(k)
        .ok()
        .and_then(|k| vs.get(k))
        .map_or(-1, |&x| x as i32)
}

fn vertexnext(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(vertex_step(l, a[0].i(), a[1].i(), 1)))
}

fn vertexprev(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(vertex_step(l, a[0].i(), a[1].i(), -1)))
}

/// A point's primitives or neighbours, by the topology.
fn around(l: &Lane, geo: i32, pt: i32, f: impl Fn(&Topology, usize) -> Vec<i32>) -> Vec<i32> {
    let (Some(g), Some(t)) = (l.host.input(geo), l.host.topology(geo)) else {
        return Vec::new();
    };
    usize::try_from(pt)
        .ok()
        .filter(|&p| p < g.num_points())
        .map_or(Vec::new(), |p| f(&t, p))
}

fn pointprims(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::AI(around(l, a[0].i(), a[1].i(), |t, p| {
        t.point_prims(p).iter().map(|&x| x as i32).collect()
    })))
}

fn neighbours(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::AI(around(l, a[0].i(), a[1].i(), |t, p| {
        t.point_neighbours(p).iter().map(|&x| x as i32).collect()
    })))
}

fn neighbour(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let all = around(l, a[0].i(), a[1].i(), |t, p| {
        t.point_neighbours(p).iter().map(|&x| x as i32).collect()
    });
    Ok(Val::I(
        usize::try_from(a[2].i())
            .ok()
            .and_then(|k| all.get(k).copied())
            .unwrap_or(-1),
    ))
}

fn neighbourcount(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(
        around(l, a[0].i(), a[1].i(), |t, p| {
            vec![0; t.point_neighbours(p).len()]
        })
        .len() as i32,
    ))
}

fn in_group(l: &Lane, a: &[Val], class: AttribClass) -> Val {
    let idx = a[2].i();
    Val::I(i32::from(l.host.input(a[0].i()).is_some_and(|g| {
        let groups = if class == AttribClass::Point {
            g.point_groups()
        } else {
            g.prim_groups()
        };
        groups
            .get(a[1].s())
            .is_some_and(|grp| usize::try_from(idx).is_ok_and(|i| i < grp.len() && grp.contains(i)))
    })))
}

fn inpointgroup(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(in_group(l, a, AttribClass::Point))
}

fn inprimgroup(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(in_group(l, a, AttribClass::Primitive))
}

fn npointsgroup(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(l.host.input(a[0].i()).map_or(0, |g| {
        g.point_groups()
            .get(a[1].s())
            .map_or(0, |grp| grp.count() as i32)
    })))
}

fn nprimitivesgroup(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(l.host.input(a[0].i()).map_or(0, |g| {
        g.prim_groups()
            .get(a[1].s())
            .map_or(0, |grp| grp.count() as i32)
    })))
}

fn expandpointgroup(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::AI(l.host.input(a[0].i()).map_or(Vec::new(), |g| {
        crate::pattern::expand(g, AttribClass::Point, a[1].s())
            .into_iter()
            .map(|i| i as i32)
            .collect()
    })))
}

fn expandprimgroup(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::AI(l.host.input(a[0].i()).map_or(Vec::new(), |g| {
        crate::pattern::expand(g, AttribClass::Primitive, a[1].s())
            .into_iter()
            .map(|i| i as i32)
            .collect()
    })))
}

/// The half-edge functions (a half-edge is the vertex it leaves from).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Hedge {
    FromPoint,
    FromPrim,
    Next,
    SrcPoint,
    DstPoint,
    SrcVertex,
    DstVertex,
    IsValid,
    Prim,
}

fn hedge_call(l: &mut Lane, a: &mut [Val], f: Hedge) -> Result<Val, Stop> {
    let input = a[0].i();
    let topology = || l.host.topology(input).expect("the input exists");
    Ok(Val::I(
        l.host
            .input(input)
            .map_or(-1, |g| hedge(g, topology, f, a[1].i())),
    ))
}

/// Half-edges as Houdini's VEX numbers them: a half-edge is the vertex it
/// leaves from, running to the next vertex of its primitive (a polygon
/// wraps; a polyline's last vertex starts none). -1 where there is none.
fn hedge(g: &Geometry, topology: impl Fn() -> Arc<Topology>, f: Hedge, x: i32) -> i32 {
    let prim_of = |v: usize| prim_of_vertex(g, v);
    // The vertex after `v` in its primitive, if `v` starts a half-edge.
    let next = |v: usize| -> Option<usize> {
        let p = prim_of(v);
        let r = g.prim_vertex_range(p);
        let closed = g.prim_kind(p) == PrimKind::Polygon;
        if v + 1 < r.end {
            Some(v + 1)
        } else if closed && r.len() > 1 {
            Some(r.start)
        } else {
            None
        }
    };
    let valid = |h: i32| vertex_index(g, h).filter(|&v| next(v).is_some());
    let out = match f {
        Hedge::FromPoint => {
            // The point's primitives (from the topology), not every vertex.
            let p = usize::try_from(x).ok().filter(|&p| p < g.num_points());
            let topo = p.map(|_| topology());
            p.and_then(|p| {
                topo.as_ref()?
                    .point_prims(p)
                    .iter()
                    .flat_map(|&prim| g.prim_vertex_range(prim as usize))
                    .filter(|&v| g.vertex_points()[v] as usize == p && next(v).is_some())
                    .min()
            })
        }
        Hedge::FromPrim => prim_index(g, x)
            .map(|p| g.prim_vertex_range(p).start)
            .filter(|&v| next(v).is_some()),
        Hedge::Next => valid(x).and_then(next).filter(|&v| next(v).is_some()),
        Hedge::SrcPoint => valid(x).map(|v| g.vertex_points()[v] as usize),
        Hedge::DstPoint => valid(x)
            .and_then(next)
            .map(|v| g.vertex_points()[v] as usize),
        Hedge::SrcVertex => valid(x),
        Hedge::DstVertex => valid(x).and_then(next),
        Hedge::IsValid => return i32::from(valid(x).is_some()),
        Hedge::Prim => valid(x).map(prim_of),
    };
    out.map_or(-1, |v| v as i32)
}
