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
//! short for the radius) until one does.

use std::collections::HashSet;

use geode_geo::glam::Vec3;

use super::tube::{Ring, Shape};
use crate::hull::{span, Span};
use crate::ModelError;

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
    pub triangles: Vec<[(u32, u32); 3]>,
    /// The source primitive of the first end's ring (the triangles').
    pub prim: u32,
}

/// Narrowing factors tried in turn when no distance joins the rings.
const SCALES: [f64; 8] = [1.0, 0.6, 0.35, 0.2, 0.1, 0.05, 0.02, 0.005];

/// The rings of a joint at `point` for `ends` (see the module doc).
pub(super) fn solve(
    point: u32,
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
    let r_joint = ends
        .iter()
        .map(|e| {
            let sh = &shapes[e.chain as usize];
            if e.at_start {
                sh.radius[0]
            } else {
                *sh.radius.last().expect("a chain has points")
            }
        })
        .fold(0.0, f64::max);
    let longest = avail.iter().cloned().fold(0.0, f64::max);
    for scale in SCALES {
        let mut t = 0.25 * r_joint * scale;
        if t <= 0.0 {
            t = 1e-3 * longest;
        }
        for _ in 0..40 {
            if cancel() {
                return Err(ModelError::Cancelled);
            }
            let distance: Vec<f64> = avail.iter().map(|&a| t.min(a)).collect();
            let rings: Vec<Ring> = ends
                .iter()
                .zip(&distance)
                .map(|(e, &d)| ring(&shapes[e.chain as usize], *e, d, scale, n))
                .collect();
            if let Some(triangles) = bridge(&ends, &rings, n, cancel)? {
                let prim = rings[0].prim;
                return Ok(Joint {
                    prim,
                    ends,
                    distance,
                    scale,
                    triangles,
                });
            }
            if t >= longest {
                break;
            }
            t *= 1.3;
        }
    }
    Err(ModelError::Failed {
        op: "polywire",
        why: format!(
            "the {} edges meeting at point {point} could not be joined (do two of them overlap?)",
            ends.len()
        ),
    })
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
) -> Result<Option<Vec<[(u32, u32); 3]>>, ModelError> {
    let pts: Vec<Vec3> = rings.iter().flat_map(|r| r.pts.iter().copied()).collect();
    let Span::Solid(tris) = span(&pts, cancel)? else {
        return Ok(None);
    };
    let at = |i: u32| (i / n as u32, i % n as u32);
    let kept: Vec<[(u32, u32); 3]> = tris
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
