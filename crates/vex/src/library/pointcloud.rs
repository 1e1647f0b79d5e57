//! Point clouds and nearest points (SideFX's "Point clouds" category):
//! `nearpoint(s)` and `pcfind` answer with point numbers; `pcopen` keeps
//! the found points (nearest first) for `pcfilter`, `pcnumfound`,
//! `pciterate` and `pcimport`. Searches use the input's k-d tree, built
//! once per run (per point group when one is named).

use super::{a, form, lane, out, Category, Function, Ret, F, I, S, T, V};
use crate::program::{Host, Lane, PointQuery, Request, Stop};
use crate::ty::{Elem, Ty};
use crate::value::read_attrib;
use crate::value::Val;

const C: Category = Category::PointClouds;
const INTS: Ret = Ret::Is(Ty::Array(Elem::Int));
const FILTERED: Ret = Ret::Context(&[Ty::Float, Ty::Vec3, Ty::Vec2, Ty::Vec4]);

#[rustfmt::skip]
pub const FUNCTIONS: &[Function] = &[
    lane("nearpoint", C, "The closest point to pos (of a point group when one is named); -1 if none within maxdist.", &[
        form(Ret::Is(Ty::Int), &[a(I, "geo"), a(V, "pos"), a(F, "maxdist")], nearpoint).opt(1),
        form(Ret::Is(Ty::Int), &[a(I, "geo"), a(S, "group"), a(V, "pos"), a(F, "maxdist")], nearpoint_group).opt(1),
    ]),
    lane("nearpoints", C, "The points within maxdist of pos (of a point group when one is named), closest first, at most maxpoints.", &[
        form(INTS, &[a(I, "geo"), a(V, "pos"), a(F, "maxdist"), a(I, "maxpoints")], nearpoints).opt(1).bytes(|a, h| found_bytes(a, h, 3)),
        form(INTS, &[a(I, "geo"), a(S, "group"), a(V, "pos"), a(F, "maxdist"), a(I, "maxpoints")], nearpoints_group).opt(1).bytes(|a, h| found_bytes(a, h, 4)),
    ]),
    lane("pcfind", C, "The points within radius of pos (searching by P), closest first, at most maxpoints.", &[
        form(INTS, &[a(I, "geo"), a(S, "Pchannel"), a(V, "pos"), a(F, "radius"), a(I, "maxpoints")], pcfind).bytes(|a, h| found_bytes(a, h, 4)),
    ]),
    lane("pcopen", C, "Opens a point cloud query: the points within radius of pos (searching by P), closest first, at most maxpoints; a handle for pcfilter, pcnumfound, pciterate and pcimport.", &[
        form(Ret::Is(Ty::Int), &[a(I, "geo"), a(S, "Pchannel"), a(V, "pos"), a(F, "radius"), a(I, "maxpoints")], pcopen).bytes(|a, h| found_bytes(a, h, 4)),
    ]),
    lane("pcnumfound", C, "How many points a pcopen query found.", &[
        form(Ret::Is(Ty::Int), &[a(I, "handle")], pcnumfound),
    ]),
    lane("pcfilter", C, "The found points' attribute, weighted by 1 - smooth(0, 1.1 * farthest distance, distance).", &[
        form(FILTERED, &[a(I, "handle"), a(S, "channel")], pcfilter),
    ]),
    lane("pciterate", C, "Moves to the next found point; 0 when there is none left.", &[
        form(Ret::Is(Ty::Int), &[a(I, "handle")], pciterate),
    ]),
    lane("pcimport", C, "Reads an attribute (or point.number, point.distance) of the current found point into value; 1 if it exists.", &[
        form(Ret::Is(Ty::Int), &[a(I, "handle"), a(S, "channel"), out(T::Any, "value")], pcimport),
    ]),
    lane("pcclose", C, "Ends a point cloud query (its memory goes with the element).", &[
        form(Ret::Is(Ty::Void), &[a(I, "handle")], pcclose),
    ]),
];

/// What a query's result will hold: up to the input's points (found as
/// indices, then converted), before the query runs.
fn found_bytes(a: &[Val], h: &dyn Host, count_at: usize) -> Option<(Request, u64)> {
    let points = h.input(a[0].i()).map_or(0, |g| g.num_points()) as u64;
    let count = a.get(count_at).map_or(u64::MAX, |c| c.i().max(0) as u64);
    let n = points.min(count);
    // The search heap (distance, index), the indices and their conversion.
    Some((Request::NearPoints(n), n * 16))
}

fn count_of(v: Option<&Val>) -> usize {
    v.map_or(usize::MAX, |c| c.i().max(0) as usize)
}

fn nearpoint(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let max = a.get(2).map_or(f32::INFINITY, Val::f);
    let found = l.host.nearest(a[0].i(), "", a[1].v3(), max, 1);
    Ok(Val::I(found.first().map_or(-1, |&p| p as i32)))
}

fn nearpoint_group(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let max = a.get(3).map_or(f32::INFINITY, Val::f);
    let found = l.host.nearest(a[0].i(), a[1].s(), a[2].v3(), max, 1);
    Ok(Val::I(found.first().map_or(-1, |&p| p as i32)))
}

fn points(found: Vec<u32>) -> Val {
    Val::AI(found.into_iter().map(|p| p as i32).collect())
}

fn nearpoints(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let found = l
        .host
        .nearest(a[0].i(), "", a[1].v3(), a[2].f(), count_of(a.get(3)));
    Ok(points(found))
}

fn nearpoints_group(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let found = l
        .host
        .nearest(a[0].i(), a[1].s(), a[2].v3(), a[3].f(), count_of(a.get(4)));
    Ok(points(found))
}

/// Point clouds search by position only.
fn by_position(channel: &str) -> Result<(), Stop> {
    if channel == "P" {
        Ok(())
    } else {
        Err(Stop::Msg(format!(
            "point clouds search by \"P\", not \"{channel}\""
        )))
    }
}

fn pcfind(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    by_position(a[1].s())?;
    let found = l
        .host
        .nearest(a[0].i(), "", a[2].v3(), a[3].f(), count_of(a.get(4)));
    Ok(points(found))
}

fn pcopen(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    by_position(a[1].s())?;
    let input = a[0].i();
    let q = a[2].v3();
    let found = l.host.nearest(input, "", q, a[3].f(), count_of(a.get(4)));
    let distances = match l.host.input(input) {
        Some(g) => found
            .iter()
            .map(|&p| {
                let d = g.positions()[p as usize] - geode_geo::glam::Vec3::from_array(q);
                d.length()
            })
            .collect(),
        None => Vec::new(),
    };
    let handle = l.host.open_query(PointQuery {
        input,
        points: found,
        distances,
        cursor: 0,
    });
    Ok(Val::I(handle))
}

fn pcnumfound(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(
        l.host.query(a[0].i()).map_or(0, |q| q.points.len() as i32),
    ))
}

fn pcfilter(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let width = l.out.floats().max(1);
    let Some(q) = l.host.query(a[0].i()).cloned() else {
        return Ok(Val::vec(&vec![0.0; width]));
    };
    let Some(g) = l.host.input(q.input) else {
        return Ok(Val::vec(&vec![0.0; width]));
    };
    let far = q.distances.iter().copied().fold(0.0f32, f32::max) * 1.1;
    let mut sum = vec![0.0f64; width];
    let mut total = 0.0f64;
    for (&p, &d) in q.points.iter().zip(&q.distances) {
        let t = if far > 0.0 {
            (d / far).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let w = 1.0 - f64::from(t * t * (3.0 - 2.0 * t));
        let Some(v) = read_attrib(g, geode_geo::AttribClass::Point, a[1].s(), p as i32) else {
            continue;
        };
        let f = match &v {
            Val::I(i) => vec![*i as f32],
            v => v.floats().to_vec(),
        };
        for (k, s) in sum.iter_mut().enumerate() {
            let x = f.get(k).or(f.first()).copied().unwrap_or(0.0);
            *s += w * f64::from(x);
        }
        total += w;
    }
    let out: Vec<f32> = sum
        .iter()
        .map(|s| if total > 0.0 { (s / total) as f32 } else { 0.0 })
        .collect();
    Ok(Val::vec(&out))
}

fn pciterate(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(match l.host.query(a[0].i()) {
        Some(q) if q.cursor < q.points.len() => {
            q.cursor += 1;
            1
        }
        _ => 0,
    }))
}

fn pcimport(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let Some(q) = l.host.query(a[0].i()).cloned() else {
        return Ok(Val::I(0));
    };
    let Some(k) = q.cursor.checked_sub(1) else {
        return Ok(Val::I(0));
    };
    let (p, d) = (q.points[k], q.distances[k]);
    let value = match a[1].s() {
        "point.number" => Some(Val::I(p as i32)),
        "point.distance" => Some(Val::float(d)),
        name => l
            .host
            .input(q.input)
            .and_then(|g| read_attrib(g, geode_geo::AttribClass::Point, name, p as i32)),
    };
    Ok(match value {
        Some(v) => {
            a[2] = v;
            Val::I(1)
        }
        None => Val::I(0),
    })
}

fn pcclose(_: &mut Lane, _: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(0))
}
