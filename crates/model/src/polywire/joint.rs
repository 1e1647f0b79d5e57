//! Joints where three or more chains meet: each chain's tube stops at a
//! ring some way along it, and the convex hull of those rings closes the
//! joint. The hull's triangles inside one ring (its cap) are dropped; the
//! rest bridge the rings, and each ring's sides are hull edges, so the
//! joint and the tubes share their rings' edges exactly (watertight).
//!
//! That holds when every ring is a face of the hull: every other ring's
//! points lie strictly on the joint's side of its plane. Rings far enough
//! out are (the distance grows as the angle between two chains shrinks:
//! about `r cot(angle / 2)`), so the search moves the rings out in steps
//! until the exact hull shows every ring whole. A chain too short for the
//! distance needed keeps its ring within its own length, and when no
//! distance works the joint's rings are narrowed (a pinch where edges are
//! short for the radius) until one does. Where none does (dozens of twigs
//! a degree or two apart), the twigs nearest in angle to a kept tube are
//! left out of the hull and capped (see `solve`). Where every tube leaves
//! on one side (a broom of near-parallel edges), a hull of the rings stays
//! far from the joint point, so the tubes instead run to the point, capped
//! there, overlapping (polywire's union joins them).

use std::collections::HashSet;

use geode_geo::glam::{DVec3, Vec3};

use super::tube::{Ring, Shape};
use crate::hull::{span, Span};
use crate::ModelError;

/// A joint triangle's corners: (end, ring point).
pub(super) type Triangle = [(u32, u32); 3];

/// One chain end at a joint.
#[derive(Clone, Copy, Debug)]
pub(super) struct End {
    pub chain: u32,
    pub at_start: bool,
}

/// A solved joint: each end's distance from the joint point and radius
/// scale, and the bridging triangles as (end, ring point) corners.
pub(super) struct Joint {
    pub ends: Vec<End>,
    pub distance: Vec<f64>,
    pub scale: f64,
    pub triangles: Vec<Triangle>,
    /// The source primitive of the first end's ring (the triangles').
    pub prim: u32,
    /// Ends left out of the hull, capped at these distances (see solve).
    pub capped: Vec<(End, f64)>,
}

/// The rings of a joint for `ends` (see the module doc). Never fails but
/// for cancellation: where no hull joins every ring (many nearly parallel
/// twigs, as space colonization leaves, or overlapping edges), twigs
/// closer in angle than a threshold to a thicker or longer kept tube are
/// left out of the hull and capped (their tubes start inside the kept
/// ones), the threshold doubling until the rest join; with fewer than two
/// left every tube is capped. Each tube so stays closed: watertight by
/// construction, in a fixed order (deterministic).
pub(super) fn solve(
    ends: Vec<End>,
    shapes: &[Shape],
    free_far_end: &dyn Fn(u32) -> bool,
    n: usize,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Joint, ModelError> {
    // How far along its chain each ring may go: most of a chain that ends
    // freely, under half of one with a joint (or this one) at both ends.
    let avail: Vec<f64> = ends
        .iter()
        .map(|e| {
            let l = shapes[e.chain as usize].length();
            if free_far_end(e.chain) {
                0.9 * l
            } else {
                0.45 * l
            }
        })
        .collect();
    // Each tube's direction leaving the joint, and its widest radius near
    // it (at the joint or as far out as its ring may go).
    let (dirs, radii): (Vec<DVec3>, Vec<f64>) = ends
        .iter()
        .zip(&avail)
        .map(|(e, &a)| {
            let sh = &shapes[e.chain as usize];
            let far = ring(sh, *e, a, 1.0, 3);
            let far_r = (far.pts[0].as_dvec3() - centre(&far)).length();
            if e.at_start {
                (sh.dir[0], sh.radius[0].max(far_r))
            } else {
                let last = sh.dir.len() - 1;
                (-sh.dir[last], sh.radius[last + 1].max(far_r))
            }
        })
        .unzip();
    let all: Vec<usize> = (0..ends.len()).collect();
    let joined = |kept: &[usize]| -> Result<Option<Joint>, ModelError> {
        let pick = |i: &usize| (ends[*i], avail[*i], dirs[*i], radii[*i]);
        let sub: Vec<_> = kept.iter().map(pick).collect();
        let found = attempt(&sub, shapes, n, cancel)?;
        Ok(found.map(|(distance, scale, triangles, prim)| {
            // A left-out twig's cap sits as far out as the kept tube
            // nearest its direction has its ring (inside that tube for a
            // twig nearly parallel to it), within its own chain.
            let capped = (0..ends.len())
                .filter(|i| !kept.contains(i))
                .map(|i| {
                    let near = (0..kept.len())
                        .max_by(|&a, &b| {
                            let (da, db) = (dirs[kept[a]].dot(dirs[i]), dirs[kept[b]].dot(dirs[i]));
                            da.total_cmp(&db).then(b.cmp(&a))
                        })
                        .expect("two kept ends");
                    (ends[i], distance[near].min(avail[i]))
                })
                .collect();
            Joint {
                ends: kept.iter().map(|&i| ends[i]).collect(),
                distance,
                scale,
                triangles,
                prim,
                capped,
            }
        }))
    };
    // Every tube capped at the joint point: they overlap there (and
    // polywire's union joins them).
    let at_the_point = || Joint {
        ends: Vec::new(),
        distance: Vec::new(),
        scale: 1.0,
        triangles: Vec::new(),
        prim: 0,
        capped: all.iter().map(|&i| (ends[i], 0.0)).collect(),
    };
    let apart = |j: &Joint| {
        let kept: Vec<usize> = j
            .ends
            .iter()
            .map(|e| {
                ends.iter()
                    .position(|x| x.chain == e.chain && x.at_start == e.at_start)
                    .expect("a kept end is an end")
            })
            .collect();
        far_from_the_point(&kept, &dirs, &radii, &j.distance, j.scale)
    };
    if let Some(j) = joined(&all)? {
        return Ok(if apart(&j) { at_the_point() } else { j });
    }
    // Thicker, then longer tubes first.
    let mut order = all.clone();
    order.sort_by(|&a, &b| {
        let la = shapes[ends[a].chain as usize].length();
        let lb = shapes[ends[b].chain as usize].length();
        radii[b]
            .total_cmp(&radii[a])
            .then(lb.total_cmp(&la))
            .then(a.cmp(&b))
    });
    // The first subset whose rings keep a third of their radius, else the
    // one that narrows them least (a pinch of the trunk is worse than a
    // twig more left out).
    let mut best: Option<Joint> = None;
    let mut angle: f64 = 0.05;
    loop {
        let mut kept: Vec<usize> = Vec::new();
        for &i in &order {
            if kept.iter().all(|&k| dirs[i].angle_between(dirs[k]) > angle) {
                kept.push(i);
            }
        }
        kept.sort_unstable();
        if kept.len() < 2 {
            if let Some(j) = best {
                return Ok(j);
            }
            // Every tube capped, short of the joint point.
            let capped = all
                .iter()
                .map(|&i| (ends[i], (0.5 * radii[i]).min(avail[i])))
                .collect();
            return Ok(Joint {
                ends: Vec::new(),
                distance: Vec::new(),
                scale: 1.0,
                triangles: Vec::new(),
                prim: 0,
                capped,
            });
        }
        if let Some(j) = joined(&kept)? {
            if apart(&j) {
                return Ok(at_the_point());
            }
            if j.scale >= 1.0 / 3.0 {
                return Ok(j);
            }
            if best.as_ref().is_none_or(|b| j.scale > b.scale) {
                best = Some(j);
            }
        }
        angle *= 2.0;
    }
}

/// Whether a hull of the rings of ends `kept` (at `distance`, radii times
/// `scale`) stays further than the widest radius from the joint point: the
/// tubes all leave on one side (a broom of near-parallel twigs), and the
/// hull would join them far out, leaving the joint point and most of every
/// edge bare. Measured along the mean direction: the nearest ring point's
/// height there.
fn far_from_the_point(
    kept: &[usize],
    dirs: &[DVec3],
    radii: &[f64],
    distance: &[f64],
    scale: f64,
) -> bool {
    let Some(mean) = kept.iter().map(|&i| dirs[i]).sum::<DVec3>().try_normalize() else {
        return false;
    };
    let widest = kept.iter().map(|&i| radii[i] * scale).fold(0.0, f64::max);
    let nearest = kept
        .iter()
        .zip(distance)
        .map(|(&i, &d)| {
            let c = mean.dot(dirs[i]);
            d * c - radii[i] * scale * (1.0 - c * c).max(0.0).sqrt()
        })
        .fold(f64::INFINITY, f64::min);
    nearest > widest
}

/// A hull joining every one of `sub`'s ends (end, available length,
/// direction, radius): the rings' distances, scale, the bridging
/// triangles and their primitive; None when no attempt joins them.
#[allow(clippy::type_complexity)]
fn attempt(
    sub: &[(End, f64, DVec3, f64)],
    shapes: &[Shape],
    n: usize,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Option<(Vec<f64>, f64, Vec<Triangle>, u32)>, ModelError> {
    let ends: Vec<End> = sub.iter().map(|s| s.0).collect();
    let avail: Vec<f64> = sub.iter().map(|s| s.1).collect();
    let dirs: Vec<DVec3> = sub.iter().map(|s| s.2).collect();
    let radii: Vec<f64> = sub.iter().map(|s| s.3).collect();
    let Some(mut distance) = distances(&dirs, &radii) else {
        return Ok(None);
    };
    // Rings beyond what a chain allows: all come in and narrow together
    // (the constraints scale with the radii).
    let fit = distance
        .iter()
        .zip(&avail)
        .map(|(&t, &a)| a / t)
        .fold(1.0, f64::min);
    distance.iter_mut().for_each(|t| *t *= fit);
    let mut attempts = vec![(distance, fit)];
    // Failing that (bent chains, or rings so narrow that rounding tilts
    // them): every ring at one distance, the nearest any chain allows,
    // narrowed to half what clears each pair there, then narrower.
    let t = avail.iter().cloned().fold(f64::INFINITY, f64::min);
    let mut scale: f64 = 1.0;
    for i in 0..dirs.len() {
        for j in 0..dirs.len() {
            let (c, s) = (dirs[i].dot(dirs[j]), dirs[i].cross(dirs[j]).length());
            if i != j && s > 0.0 && c > -1.0 {
                scale = scale.min(t * (1.0 - c) / (2.0 * radii[j] * s));
            }
        }
    }
    for _ in 0..12 {
        attempts.push((vec![t; dirs.len()], scale));
        scale *= 0.6;
    }
    for (distance, scale) in attempts {
        if cancel() {
            return Err(ModelError::Cancelled);
        }
        let rings: Vec<Ring> = ends
            .iter()
            .zip(&distance)
            .map(|(e, &d)| ring(&shapes[e.chain as usize], *e, d, scale, n))
            .collect();
        if let Some(triangles) = bridge(&ends, &rings, n, cancel)? {
            return Ok(Some((distance, scale, triangles, rings[0].prim)));
        }
    }
    Ok(None)
}

/// The centre of a ring (the mean of its points).
fn centre(r: &Ring) -> DVec3 {
    r.pts.iter().map(|p| p.as_dvec3()).sum::<DVec3>() / r.pts.len() as f64
}

/// Distances from the joint that make every ring a hull face when tubes
/// run straight along `dirs` with radii `radii`: ring `i`'s plane must
/// clear every other ring `j`, `t_i > t_j cos a + r_j sin a` (`a` the
/// angle between them), solved by raising each `t_i` to what the others
/// need until none moves (the least solution), from each pair's
/// symmetric answer `r cot(a / 2)`, or else the largest of those for all.
/// None when two directions coincide.
fn distances(dirs: &[DVec3], radii: &[f64]) -> Option<Vec<f64>> {
    let k = dirs.len();
    let mut t: Vec<f64> = radii.iter().map(|r| 0.05 * r).collect();
    let mut need = vec![vec![(0.0, 0.0); k]; k];
    for i in 0..k {
        for j in 0..k {
            if i == j {
                continue;
            }
            let c = dirs[i].dot(dirs[j]).clamp(-1.0, 1.0);
            let s = dirs[i].cross(dirs[j]).length();
            if 1.0 - c < 1e-12 {
                return None;
            }
            need[i][j] = (c, s);
            let r = radii[i].max(radii[j]);
            t[i] = t[i].max((r * s + 1e-2 * radii[i]) / (1.0 - c));
        }
    }
    for _ in 0..64 {
        let mut moved = false;
        for i in 0..k {
            let want = (0..k)
                .filter(|&j| j != i)
                .map(|j| t[j] * need[i][j].0 + radii[j] * need[i][j].1 + 1e-2 * radii[i])
                .fold(0.0, f64::max);
            if want > t[i] {
                t[i] = want;
                moved = true;
            }
        }
        if !moved {
            return Some(t);
        }
    }
    // Near-parallel tubes converge slowly (by cos a a round): one distance
    // for all, each pair's symmetric answer, satisfies every constraint.
    let all = t.iter().cloned().fold(0.0, f64::max);
    Some(vec![all; k])
}

/// The ring of chain end `e` at distance `d` from the joint.
pub(super) fn ring(shape: &Shape, e: End, d: f64, scale: f64, n: usize) -> Ring {
    if e.at_start {
        let (k, f) = shape.locate(d, true);
        shape.plain(k, f, scale, n)
    } else {
        let (k, f) = shape.locate(shape.length() - d, false);
        shape.plain(k, f, scale, n)
    }
}

/// The hull's bridging triangles when every ring is a face of the hull
/// whose sides run against the tubes' (None otherwise).
fn bridge(
    ends: &[End],
    rings: &[Ring],
    n: usize,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Option<Vec<Triangle>>, ModelError> {
    // The hull's combinatorics in coordinates centred on the joint and
    // scaled to it: far from the origin f32 would round rings a few ulps
    // wide into each other.
    let world: Vec<DVec3> = rings
        .iter()
        .flat_map(|r| r.pts.iter().map(|p| p.as_dvec3()))
        .collect();
    let mid = world.iter().sum::<DVec3>() / world.len() as f64;
    let size = world
        .iter()
        .map(|p| (*p - mid).length())
        .fold(0.0, f64::max)
        .max(1e-300);
    let pts: Vec<Vec3> = world
        .iter()
        .map(|p| ((*p - mid) / size).as_vec3())
        .collect();
    let Span::Solid(tris) = span(&pts, cancel)? else {
        return Ok(None);
    };
    let at = |i: u32| (i / n as u32, i % n as u32);
    let kept: Vec<Triangle> = tris
        .iter()
        .map(|t| t.map(at))
        .filter(|t| !(t[0].0 == t[1].0 && t[1].0 == t[2].0))
        .collect();
    let k = rings.len();
    // A convex polytope on k rings of n points with every ring a face.
    if kept.len() != k * n + 2 * k - 4 {
        return Ok(None);
    }
    let directed: HashSet<((u32, u32), (u32, u32))> = kept
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .collect();
    for (i, e) in ends.iter().enumerate() {
        let i = i as u32;
        for j in 0..n as u32 {
            let (a, b) = ((i, j), (i, (j + 1) % n as u32));
            // The tube runs a -> b at its start ring, b -> a at its end.
            let want = if e.at_start { (b, a) } else { (a, b) };
            if !directed.contains(&want) {
                return Ok(None);
            }
        }
    }
    Ok(Some(kept))
}
