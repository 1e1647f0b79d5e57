//! Measuring (SideFX's "Measuring" and intrinsics functions): bounding
//! boxes, primitive intrinsics (`measuredarea`, `closed`...), the closest
//! point on a surface (`xyzdist`), ray hits (`intersect`), and attribute
//! values at a primitive's parametric coordinates (`primuv`).
//!
//! Parametric coordinates follow Houdini's "Primitive parametric spaces":
//! a triangle is `P0 (1-u-v) + P1 u + P2 v`; a quad the bilinear patch
//! `P0 (1-u)(1-v) + P1 (1-u) v + P2 u v + P3 u (1-v)`; an n-gon a fan
//! around its vertices' average where each edge spans `1/n` of u and v
//! runs from the centre (0) to the boundary (1); a polyline has u uniform
//! per segment. The surface searched is triangles in a hierarchy built
//! once per input and primitive group pattern (quads split on 0-2,
//! polylines as segments); a
//! non-planar quad answers on those triangles, its (u, v) fitted on the
//! patch.

use std::any::Any;
use std::sync::Arc;

use geode_geo::glam::Vec3;
use geode_geo::ops::prim_surface::{corners, weights, PrimSurface};
use geode_geo::{AttribClass, Geometry, PrimKind};

use super::{a, form, lane, out, Category, Function, Ret, F, I, S, T, V};
use crate::program::{Lane, Stop};
use crate::ty::{Elem, Ty};
use crate::value::read_attrib;
use crate::value::Val;

const C: Category = Category::Measuring;
const VEC: Ret = Ret::Is(Ty::Vec3);

#[rustfmt::skip]
pub const FUNCTIONS: &[Function] = &[
    lane("getbbox", C, "The bounding box of input geo's points (of a primitive group's points when one is named) into min and max.", &[
        form(Ret::Is(Ty::Void), &[a(I, "geo"), out(V, "min"), out(V, "max")], getbbox),
        form(Ret::Is(Ty::Void), &[a(I, "geo"), a(S, "primgroup"), out(V, "min"), out(V, "max")], getbbox),
    ]),
    lane("getbbox_min", C, "The smallest corner of input geo's bounding box.", &[
        form(VEC, &[a(I, "geo"), a(S, "primgroup")], |l, a| corner(l, a, Corner::Min)).opt(1),
    ]),
    lane("getbbox_max", C, "The largest corner of input geo's bounding box.", &[
        form(VEC, &[a(I, "geo"), a(S, "primgroup")], |l, a| corner(l, a, Corner::Max)).opt(1),
    ]),
    lane("getbbox_size", C, "The size of input geo's bounding box.", &[
        form(VEC, &[a(I, "geo"), a(S, "primgroup")], |l, a| corner(l, a, Corner::Size)).opt(1),
    ]),
    lane("getbbox_center", C, "The centre of input geo's bounding box.", &[
        form(VEC, &[a(I, "geo"), a(S, "primgroup")], |l, a| corner(l, a, Corner::Center)).opt(1),
    ]),
    lane("relbbox", C, "A position relative to input geo's bounding box: 0 at the smallest corner, 1 at the largest (0.5 on a flat axis).", &[
        form(VEC, &[a(I, "geo"), a(V, "pos")], relbbox),
    ]),
    lane("relpointbbox", C, "A position relative to the bounding box of input geo's points.", &[
        form(VEC, &[a(I, "geo"), a(V, "pos")], relbbox),
    ]),
    lane("primintrinsic", C, "A primitive intrinsic: measuredarea, measuredperimeter, closed, typename, typeid, pointcount, vertexcount, bounds.", &[
        form(Ret::Intrinsic, &[a(I, "geo"), a(S, "intrinsic"), a(I, "primnum")], primintrinsic),
    ]),
    lane("detailintrinsic", C, "A detail intrinsic: pointcount, primitivecount, vertexcount, bounds.", &[
        form(Ret::Intrinsic, &[a(I, "geo"), a(S, "intrinsic")], detailintrinsic),
    ]),
    lane("xyzdist", C, "The distance from pos to the closest point of input geo's surface (of the primitives a group pattern names, when given; within maxdist); its primitive and parametric uv into prim and uv (-1 if none).", &[
        form(Ret::Is(Ty::Float), &[a(I, "geo"), a(V, "pos"), out(I, "prim"), out(V, "uv"), a(F, "maxdist")], xyzdist).opt(3),
        form(Ret::Is(Ty::Float), &[a(I, "geo"), a(S, "primgroup"), a(V, "pos"), out(I, "prim"), out(V, "uv"), a(F, "maxdist")], xyzdist).opt(3),
    ]),
    lane("primuv", C, "An attribute's value at a primitive's parametric uv, interpolated from its vertices or points.", &[
        form(Ret::Attrib(AttribClass::Point), &[a(I, "geo"), a(S, "attrib"), a(I, "primnum"), a(V, "uv")], primuv),
    ]),
    lane("prim_normal", C, "The normal of a polygon (its area-weighted Newell normal).", &[
        form(VEC, &[a(I, "geo"), a(I, "primnum"), a(V, "uv")], prim_normal).opt(1),
    ]),
    lane("intersect", C, "The first primitive (of a group pattern's, when given) the ray from orig along dir (its length the reach) hits; the hit position and parametric uv into pos and uvw, or u and v (-1 if none). Options: \"farthest\", 1 takes the last hit.", &[
        form(Ret::Is(Ty::Int), &[a(I, "geo"), a(V, "orig"), a(V, "dir"), out(V, "pos"), out(V, "uvw")], intersect),
        form(Ret::Is(Ty::Int), &[a(I, "geo"), a(S, "group"), a(V, "orig"), a(V, "dir"), out(V, "pos"), out(V, "uvw")], intersect),
        form(Ret::Is(Ty::Int), &[a(I, "geo"), a(V, "orig"), a(V, "dir"), out(V, "pos"), out(F, "u"), out(F, "v"), a(T::Any, "option")], intersect_uv).opt(1).many(),
    ]),
];

/// The type of an intrinsic by name, for calls whose name is a literal.
pub fn intrinsic_type(name: &str) -> Option<Ty> {
    Some(match name {
        "measuredarea" | "measuredperimeter" | "measuredvolume" => Ty::Float,
        "closed" | "pointcount" | "vertexcount" | "primitivecount" | "typeid" => Ty::Int,
        "typename" => Ty::Str,
        "bounds" => Ty::Array(Elem::Float),
        _ => return None,
    })
}

/// Input `geo`'s points, or the points of the primitives a group pattern
/// names.
fn bounds(g: &Geometry, group: Option<&str>) -> Option<(Vec3, Vec3)> {
    let mut lo = Vec3::INFINITY;
    let mut hi = Vec3::NEG_INFINITY;
    let mut add = |p: Vec3| {
        lo = lo.min(p);
        hi = hi.max(p);
    };
    match group.filter(|s| !s.is_empty()) {
        Some(pattern) => {
            for prim in crate::pattern::expand(g, AttribClass::Primitive, pattern) {
                for &p in g.prim_points(prim) {
                    add(g.positions()[p as usize]);
                }
            }
        }
        None => g.positions().iter().for_each(|&p| add(p)),
    }
    (lo.x <= hi.x).then_some((lo, hi))
}

fn getbbox(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let group = (a.len() == 4).then(|| a[1].s().to_string());
    let (lo, hi) = l
        .host
        .input(a[0].i())
        .and_then(|g| bounds(g, group.as_deref()))
        .unwrap_or((Vec3::ZERO, Vec3::ZERO));
    let n = a.len();
    a[n - 2] = Val::vec(&lo.to_array());
    a[n - 1] = Val::vec(&hi.to_array());
    Ok(Val::I(0))
}

#[derive(Clone, Copy)]
enum Corner {
    Min,
    Max,
    Size,
    Center,
}

fn corner(l: &mut Lane, a: &mut [Val], which: Corner) -> Result<Val, Stop> {
    let (lo, hi) = l
        .host
        .input(a[0].i())
        .and_then(|g| bounds(g, a.get(1).map(Val::s)))
        .unwrap_or((Vec3::ZERO, Vec3::ZERO));
    let v = match which {
        Corner::Min => lo,
        Corner::Max => hi,
        Corner::Size => hi - lo,
        Corner::Center => (lo + hi) * 0.5,
    };
    Ok(Val::vec(&v.to_array()))
}

fn relbbox(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let p = Vec3::from_array(a[1].v3());
    let Some((lo, hi)) = l.host.input(a[0].i()).and_then(|g| bounds(g, None)) else {
        return Ok(Val::vec(&[0.0; 3]));
    };
    let size = hi - lo;
    let r = Vec3::select(size.cmpgt(Vec3::ZERO), (p - lo) / size, Vec3::splat(0.5));
    Ok(Val::vec(&r.to_array()))
}

/// Twice the area vector of a closed polygon (Newell).
fn newell(c: &[Vec3]) -> Vec3 {
    let mut n = Vec3::ZERO;
    for (i, p) in c.iter().enumerate() {
        let q = c[(i + 1) % c.len()];
        n += p.cross(q);
    }
    n
}

fn is_closed(g: &Geometry, prim: usize) -> bool {
    g.prim_kind(prim) == PrimKind::Polygon
}

fn primintrinsic(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let Some(g) = l.host.input(a[0].i()) else {
        return Ok(super::support::empty_like(l.out));
    };
    let Some(prim) = usize::try_from(a[2].i())
        .ok()
        .filter(|&p| p < g.num_prims())
    else {
        return Ok(super::support::empty_like(l.out));
    };
    let c = corners(g, prim);
    let closed = is_closed(g, prim);
    Ok(match a[1].s() {
        "measuredarea" => Val::float(if closed && c.len() >= 3 {
            newell(&c).length() * 0.5
        } else {
            0.0
        }),
        "measuredperimeter" => {
            let open: f32 = c.windows(2).map(|w| w[0].distance(w[1])).sum();
            let wrap = if closed && c.len() > 2 {
                c[c.len() - 1].distance(c[0])
            } else {
                0.0
            };
            Val::float(open + wrap)
        }
        "measuredvolume" => Val::float(0.0),
        "closed" => Val::I(i32::from(closed)),
        "typename" => Val::S(
            match g.prim_kind(prim) {
                PrimKind::Polygon | PrimKind::Polyline => "Poly",
                _ => "PackedGeometry",
            }
            .into(),
        ),
        "typeid" => Val::I(match g.prim_kind(prim) {
            PrimKind::Polygon | PrimKind::Polyline => 1,
            _ => 0,
        }),
        "pointcount" | "vertexcount" => Val::I(c.len() as i32),
        "bounds" => {
            let (lo, hi) = c.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
                (lo.min(p), hi.max(p))
            });
            Val::AF(vec![lo.x, hi.x, lo.y, hi.y, lo.z, hi.z], 1)
        }
        other => {
            return Err(Stop::Msg(format!(
                "primintrinsic: unknown intrinsic \"{other}\": expected measuredarea, measuredperimeter, closed, typename, typeid, pointcount, vertexcount or bounds"
            )))
        }
    })
}

fn detailintrinsic(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let Some(g) = l.host.input(a[0].i()) else {
        return Ok(super::support::empty_like(l.out));
    };
    Ok(match a[1].s() {
        "pointcount" => Val::I(g.num_points() as i32),
        "primitivecount" => Val::I(g.num_prims() as i32),
        "vertexcount" => Val::I(g.num_vertices() as i32),
        "bounds" => {
            let (lo, hi) = bounds(g, None).unwrap_or((Vec3::ZERO, Vec3::ZERO));
            Val::AF(vec![lo.x, hi.x, lo.y, hi.y, lo.z, hi.z], 1)
        }
        other => {
            return Err(Stop::Msg(format!(
                "detailintrinsic: unknown intrinsic \"{other}\": expected pointcount, primitivecount, vertexcount or bounds"
            )))
        }
    })
}

/// The surface of the primitives a group pattern names (every primitive
/// for an empty one, as SOP groups read it), in primitive order so ties
/// go to the lower primitive as over the whole input.
fn surface_of(g: &Geometry, group: &str) -> Arc<dyn Any + Send + Sync> {
    let prims: Vec<usize> = if group.trim().is_empty() {
        (0..g.num_prims()).collect()
    } else {
        let mut members = crate::pattern::expand(g, AttribClass::Primitive, group);
        members.sort_unstable();
        members
    };
    Arc::new(PrimSurface::new(g, &prims))
}

/// Input `geo`'s surface over the primitives of `group` (all for ""),
/// built once per run and group.
fn surface(l: &Lane, geo: i32, group: &str) -> Option<Arc<PrimSurface>> {
    l.host
        .cached(geo, "surface", group, &|g| surface_of(g, group))
        .and_then(|s| s.downcast::<PrimSurface>().ok())
}

/// The primitive group pattern of a call's group form (its second
/// argument a string) and where the arguments after it start.
fn group_arg(a: &[Val]) -> (String, usize) {
    match a.get(1) {
        Some(Val::S(group)) => (group.clone(), 2),
        _ => (String::new(), 1),
    }
}

fn xyzdist(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    // (geo, [group,] pos, &prim, &uv, maxdist)
    let (group, at) = group_arg(a);
    let max = a.get(at + 3).map_or(f32::INFINITY, |m| {
        if m.f() < 0.0 {
            f32::INFINITY
        } else {
            m.f()
        }
    });
    let q = Vec3::from_array(a[at].v3());
    let (Some(g), Some(s)) = (l.host.input(a[0].i()), surface(l, a[0].i(), &group)) else {
        set_out(a, at + 1, Val::I(-1));
        return Ok(Val::float(-1.0));
    };
    let Some(hit) = s.bvh.closest(q, max) else {
        set_out(a, at + 1, Val::I(-1));
        return Ok(Val::float(-1.0));
    };
    let (prim, u, v) = s.locate(g, hit.triangle, hit.point, hit.u, hit.v);
    set_out(a, at + 1, Val::I(prim as i32));
    set_out(a, at + 2, Val::vec(&[u, v, 0.0]));
    Ok(Val::float(hit.dist2.sqrt()))
}

/// Writes an output argument the call was given.
fn set_out(a: &mut [Val], k: usize, v: Val) {
    if let Some(slot) = a.get_mut(k) {
        *slot = v;
    }
}

fn primuv(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let zero = || super::support::empty_like(l.out);
    let Some(g) = l.host.input(a[0].i()) else {
        return Ok(zero());
    };
    let Some(prim) = usize::try_from(a[2].i())
        .ok()
        .filter(|&p| p < g.num_prims())
    else {
        return Ok(zero());
    };
    let name = a[1].s();
    let uv = a[3].v3();
    let range = g.prim_vertex_range(prim);
    // Point or vertex values at each vertex; a primitive or detail value
    // is the same everywhere.
    let values: Vec<Val> = if name == "P" || g.attrib(AttribClass::Point, name).is_some() {
        g.prim_points(prim)
            .iter()
            .filter_map(|&p| read_attrib(g, AttribClass::Point, name, p as i32))
            .collect()
    } else if g.attrib(AttribClass::Vertex, name).is_some() {
        range
            .clone()
            .filter_map(|v| read_attrib(g, AttribClass::Vertex, name, v as i32))
            .collect()
    } else {
        let whole = read_attrib(g, AttribClass::Primitive, name, prim as i32)
            .or_else(|| read_attrib(g, AttribClass::Detail, name, 0));
        return Ok(whole.unwrap_or_else(zero));
    };
    let Some(w) = weights(g, prim, uv[0], uv[1]) else {
        return Ok(zero());
    };
    if values.len() != w.len() {
        return Ok(zero());
    }
    let width = values
        .iter()
        .map(|v| v.floats().len().max(1))
        .max()
        .unwrap_or(1);
    let mut acc = vec![0.0f32; width];
    for (v, wk) in values.iter().zip(&w) {
        let f: Vec<f32> = match v {
            Val::I(i) => vec![*i as f32],
            v => v.floats().to_vec(),
        };
        for (s, x) in acc.iter_mut().zip(f) {
            *s += wk * x;
        }
    }
    Ok(match values[0] {
        Val::I(_) => Val::I(acc[0].round() as i32),
        _ => Val::vec(&acc),
    })
}

fn prim_normal(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let n = l
        .host
        .input(a[0].i())
        .and_then(|g| {
            usize::try_from(a[1].i())
                .ok()
                .filter(|&p| p < g.num_prims())
                .map(|p| newell(&corners(g, p)).normalize_or_zero())
        })
        .unwrap_or(Vec3::ZERO);
    Ok(Val::vec(&n.to_array()))
}

/// Where a ray hits: the primitive, the point and its parametric (u, v).
struct Hit {
    prim: u32,
    point: Vec3,
    u: f32,
    v: f32,
}

/// The first (or, `farthest`, the last) hit of the ray `orig + t dir`,
/// t in (0, 1], on input `geo`'s primitives of `group`.
fn ray_hit(l: &Lane, geo: i32, group: &str, orig: Vec3, dir: Vec3, farthest: bool) -> Option<Hit> {
    let (g, s) = (l.host.input(geo)?, surface(l, geo, group)?);
    // t in (0, 1]: the farthest search runs back from just past the end.
    let (hit, point) = s.hit(orig, dir, 0.0, 1.0, farthest)?;
    let (prim, u, v) = s.locate(g, hit.triangle, point, hit.u, hit.v);
    Some(Hit { prim, point, u, v })
}

/// `intersect(geo, [group,] orig, dir, &pos, &uvw)`.
fn intersect(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let (group, at) = group_arg(a);
    let (orig, dir) = (
        Vec3::from_array(a[at].v3()),
        Vec3::from_array(a[at + 1].v3()),
    );
    let hit = ray_hit(l, a[0].i(), &group, orig, dir, false);
    let (prim, point, uvw) = match hit {
        Some(h) => (h.prim as i32, h.point, Vec3::new(h.u, h.v, 0.0)),
        None => (-1, Vec3::ZERO, Vec3::ZERO),
    };
    a[at + 2] = Val::vec(&point.to_array());
    a[at + 3] = Val::vec(&uvw.to_array());
    Ok(Val::I(prim))
}

/// `intersect(geo, orig, dir, &pos, &u, &v, ["farthest", 1])`.
fn intersect_uv(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let farthest = farthest_option(&a[6..])?;
    let (orig, dir) = (Vec3::from_array(a[1].v3()), Vec3::from_array(a[2].v3()));
    let hit = ray_hit(l, a[0].i(), "", orig, dir, farthest);
    let (prim, point, u, v) = match hit {
        Some(h) => (h.prim as i32, h.point, h.u, h.v),
        None => (-1, Vec3::ZERO, 0.0, 0.0),
    };
    a[3] = Val::vec(&point.to_array());
    a[4] = Val::float(u);
    a[5] = Val::float(v);
    Ok(Val::I(prim))
}

/// The options after `intersect`'s u and v, as (name, value) pairs: only
/// "farthest" is documented ("whether to return the last intersection
/// instead of the first").
fn farthest_option(options: &[Val]) -> Result<bool, Stop> {
    let mut farthest = false;
    for pair in options.chunks(2) {
        let name = match &pair[0] {
            Val::S(name) => name.as_str(),
            _ => {
                return Err(Stop::Msg(
                    "intersect: an option is a name (\"farthest\") followed by its value".into(),
                ))
            }
        };
        let Some(value) = pair.get(1) else {
            return Err(Stop::Msg(format!(
                "intersect: option \"{name}\" has no value after it"
            )));
        };
        match name {
            "farthest" => farthest = value.i() != 0 || value.f() != 0.0,
            other => {
                return Err(Stop::Msg(format!(
                    "intersect: unknown option \"{other}\": expected \"farthest\""
                )))
            }
        }
    }
    Ok(farthest)
}
