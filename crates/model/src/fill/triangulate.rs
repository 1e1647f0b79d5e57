//! Triangulating one loop of points: ear clipping in the plane (any size,
//! holes bridged in beforehand), and the minimum-weight triangulation by
//! dynamic programming for loops of up to [`MIN_WEIGHT_MAX`] points.
//!
//! Ear clipping keeps a ring of the loop's corners and cuts off a convex
//! corner whose triangle holds no other corner that is reflex or flat
//! (only those can lie in an ear of a simple polygon, so a convex loop
//! costs O(n)); after a cut it moves two corners on (fewer slivers, as
//! earcut does). Corners at the same position as one of the ear's are
//! ignored, so the keyhole rings of bridged holes clip. When a full turn
//! finds no ear (a self-touching or degenerate loop) the test relaxes step
//! by step (corners on the ear's edges allowed, then any convex corner,
//! then any corner), so it always ends with n - 2 triangles over the
//! loop's own corners.
//!
//! The minimum-weight triangulation minimises the summed perimeters of its
//! triangles (so the summed lengths of the diagonals: short diagonals,
//! well-shaped triangles) over triangulations whose every triangle keeps
//! the loop's orientation in its best-fit plane. Such a triangulation
//! covers the (projected) loop exactly once, so it is valid wherever the
//! projection is simple; when no triangle set qualifies (a projection that
//! crosses itself) the caller falls back to ear clipping. O(n^3) time,
//! O(n^2) memory: 200 points take about a millisecond.

use geode_geo::glam::{DVec2, DVec3};

/// Loops longer than this are ear clipped even when the minimum-weight
/// triangulation is asked for.
pub const MIN_WEIGHT_MAX: usize = 200;

fn cross(a: DVec2, b: DVec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Twice the signed area of a ring (positive anticlockwise).
pub(crate) fn signed_area2(q: &[DVec2]) -> f64 {
    let n = q.len();
    (0..n).map(|i| cross(q[i], q[(i + 1) % n])).sum()
}

/// An orthonormal basis `(u, v)` of the plane normal to `normal` with
/// `u x v = normal` (so a loop anticlockwise about `normal` is
/// anticlockwise in `(u, v)`).
pub(crate) fn plane_basis(normal: DVec3) -> (DVec3, DVec3) {
    let n = normal.normalize_or_zero();
    let n = if n == DVec3::ZERO { DVec3::Z } else { n };
    let u = n.any_orthonormal_vector();
    (u, n.cross(u))
}

/// The Newell normal of a loop (its area vector, twice the area long).
pub(crate) fn newell_normal(p: &[DVec3]) -> DVec3 {
    let n = p.len();
    (0..n).map(|i| p[i].cross(p[(i + 1) % n])).sum()
}

/// Triangles of the ring `q` as corner indices, wound as the ring is.
pub(crate) fn ear_clip(q: &[DVec2]) -> Vec<[u32; 3]> {
    ear_clip_avoiding(q, &|_| false)
}

/// [`ear_clip`], cutting an ear that `avoid` names (corner indices) only
/// when nothing else is left to cut.
pub(crate) fn ear_clip_avoiding(q: &[DVec2], avoid: &dyn Fn([u32; 3]) -> bool) -> Vec<[u32; 3]> {
    let n = q.len();
    let mut out = Vec::with_capacity(n.saturating_sub(2));
    if n < 3 {
        return out;
    }
    // Work anticlockwise; a clockwise ring is walked backwards and its
    // triangles turned back.
    let flip = signed_area2(q) < 0.0;
    let order: Vec<u32> = if flip {
        (0..n as u32).rev().collect()
    } else {
        (0..n as u32).collect()
    };
    let mut ring = Ring::new(order.iter().map(|&i| q[i as usize]).collect());
    let emit = |out: &mut Vec<[u32; 3]>, [a, b, c]: [usize; 3]| {
        let t = [order[a], order[b], order[c]];
        out.push(if flip { [t[0], t[2], t[1]] } else { t });
    };
    let mut k = 0;
    let mut misses = 0;
    let mut relax = 0;
    while ring.remaining > 3 {
        let avoided = || {
            let t = [ring.prev[k], k, ring.next[k]].map(|i| order[i]);
            avoid(t)
        };
        if ring.is_ear(k, relax) && (relax >= 3 || !avoided()) {
            let (a, c) = (ring.prev[k], ring.next[k]);
            emit(&mut out, [a, k, c]);
            ring.unlink(k);
            k = ring.next[c];
            misses = 0;
            relax = 0;
        } else {
            k = ring.next[k];
            misses += 1;
            if misses > ring.remaining {
                relax += 1;
                misses = 0;
            }
        }
    }
    emit(&mut out, [ring.prev[k], k, ring.next[k]]);
    out
}

/// The ring of corners still to clip, anticlockwise.
struct Ring {
    q: Vec<DVec2>,
    prev: Vec<usize>,
    next: Vec<usize>,
    removed: Vec<bool>,
    /// Corners that are reflex or flat (`concave`), the only ones that
    /// can block an ear, binned in a grid over the ring's bounds so an ear
    /// test looks only near the ear (a 65k-point circle in f32 has
    /// thousands of flat corners); bins keep stale entries, skipped by
    /// flag.
    concave: Vec<bool>,
    bins: ConcaveBins,
    /// Corners clipped since the bins were last pruned.
    stale: usize,
    remaining: usize,
}

/// A uniform grid of corner indices over the ring's bounding box, about
/// one bin per corner.
struct ConcaveBins {
    lo: DVec2,
    cell: f64,
    side: usize,
    bins: Vec<Vec<usize>>,
}

impl ConcaveBins {
    fn new(q: &[DVec2]) -> ConcaveBins {
        let lo = q.iter().fold(DVec2::splat(f64::INFINITY), |a, &b| a.min(b));
        let hi = q
            .iter()
            .fold(DVec2::splat(f64::NEG_INFINITY), |a, &b| a.max(b));
        let side = ((q.len() as f64).sqrt().ceil() as usize).clamp(1, 1024);
        let extent = (hi - lo).max_element();
        let cell = if extent > 0.0 && extent.is_finite() {
            extent / side as f64
        } else {
            1.0
        };
        ConcaveBins {
            lo,
            cell,
            side,
            bins: vec![Vec::new(); side * side],
        }
    }

    fn coord(&self, x: f64) -> usize {
        let c = (x / self.cell).floor();
        if c.is_finite() {
            (c.max(0.0) as usize).min(self.side - 1)
        } else {
            0
        }
    }

    fn insert(&mut self, i: usize, p: DVec2) {
        let (x, y) = (self.coord(p.x - self.lo.x), self.coord(p.y - self.lo.y));
        self.bins[y * self.side + x].push(i);
    }

    /// The entries of the bins meeting the box `lo..hi`.
    fn near(&self, lo: DVec2, hi: DVec2) -> impl Iterator<Item = usize> + '_ {
        let (x0, x1) = (self.coord(lo.x - self.lo.x), self.coord(hi.x - self.lo.x));
        let (y0, y1) = (self.coord(lo.y - self.lo.y), self.coord(hi.y - self.lo.y));
        (y0..=y1).flat_map(move |y| {
            (x0..=x1).flat_map(move |x| self.bins[y * self.side + x].iter().copied())
        })
    }

    /// Drops the entries `keep` refuses (stale ones), bin by bin.
    fn prune(&mut self, keep: impl Fn(usize) -> bool) {
        for b in &mut self.bins {
            b.retain(|&j| keep(j));
        }
    }
}

impl Ring {
    fn new(q: Vec<DVec2>) -> Ring {
        let n = q.len();
        let prev: Vec<usize> = (0..n).map(|i| (i + n - 1) % n).collect();
        let next: Vec<usize> = (0..n).map(|i| (i + 1) % n).collect();
        let bins = ConcaveBins::new(&q);
        let mut ring = Ring {
            q,
            prev,
            next,
            removed: vec![false; n],
            concave: vec![false; n],
            bins,
            stale: 0,
            remaining: n,
        };
        for i in 0..n {
            ring.update(i);
        }
        ring
    }

    fn turn(&self, i: usize) -> f64 {
        let (a, b, c) = (self.q[self.prev[i]], self.q[i], self.q[self.next[i]]);
        cross(b - a, c - b)
    }

    fn update(&mut self, i: usize) {
        let concave = self.turn(i) <= 0.0;
        if concave && !self.concave[i] {
            self.bins.insert(i, self.q[i]);
        }
        self.concave[i] = concave;
    }

    fn unlink(&mut self, k: usize) {
        let (a, c) = (self.prev[k], self.next[k]);
        self.next[a] = c;
        self.prev[c] = a;
        self.removed[k] = true;
        self.remaining -= 1;
        self.update(a);
        self.update(c);
        self.stale += 1;
        if self.stale > 64 && self.stale > self.remaining {
            let (removed, concave) = (&self.removed, &self.concave);
            self.bins.prune(|j| !removed[j] && concave[j]);
            self.stale = 0;
        }
    }

    /// Whether corner `k` may be cut off at relaxation level `relax`: 0
    /// strict, 1 blocking corners on the ear's edges allowed, 2 any convex
    /// corner, 3 any corner.
    fn is_ear(&self, k: usize, relax: u32) -> bool {
        if relax >= 3 {
            return true;
        }
        if self.turn(k) <= 0.0 {
            return false;
        }
        if relax == 2 {
            return true;
        }
        let (ia, ic) = (self.prev[k], self.next[k]);
        let (a, b, c) = (self.q[ia], self.q[k], self.q[ic]);
        let strict = relax == 0;
        let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
        !self.bins.near(lo, hi).any(|j| {
            if self.removed[j] || !self.concave[j] || j == ia || j == k || j == ic {
                return false;
            }
            let p = self.q[j];
            p != a && p != b && p != c && inside(p, a, b, c, strict)
        })
    }
}

/// Whether `p` lies in the anticlockwise triangle `abc` (on its edges
/// included when `closed`).
fn inside(p: DVec2, a: DVec2, b: DVec2, c: DVec2, closed: bool) -> bool {
    let s = [
        cross(b - a, p - a),
        cross(c - b, p - b),
        cross(a - c, p - c),
    ];
    if closed {
        s.iter().all(|&x| x >= 0.0)
    } else {
        s.iter().all(|&x| x > 0.0)
    }
}

/// The minimum-weight triangulation of the loop `p` (3D) whose projection
/// `q` is anticlockwise, with no triangle `avoid` names; None when no
/// triangulation keeps every triangle anticlockwise in `q`.
pub(crate) fn min_weight(
    p: &[DVec3],
    q: &[DVec2],
    avoid: &dyn Fn([u32; 3]) -> bool,
) -> Option<Vec<[u32; 3]>> {
    let n = p.len();
    if n < 3 {
        return Some(Vec::new());
    }
    let at = |i: usize, j: usize| i * n + j;
    let mut cost = vec![f64::INFINITY; n * n];
    let mut split = vec![u32::MAX; n * n];
    for i in 0..n - 1 {
        cost[at(i, i + 1)] = 0.0;
    }
    let len = |i: usize, j: usize| (p[i] - p[j]).length();
    for span in 2..n {
        for i in 0..n - span {
            let j = i + span;
            let mut best = f64::INFINITY;
            let mut best_k = u32::MAX;
            for k in i + 1..j {
                let (left, right) = (cost[at(i, k)], cost[at(k, j)]);
                if !left.is_finite() || !right.is_finite() {
                    continue;
                }
                if cross(q[k] - q[i], q[j] - q[k]) <= 0.0 || avoid([i, k, j].map(|x| x as u32)) {
                    continue;
                }
                let c = left + right + len(i, k) + len(k, j) + len(i, j);
                if c < best {
                    best = c;
                    best_k = k as u32;
                }
            }
            cost[at(i, j)] = best;
            split[at(i, j)] = best_k;
        }
    }
    if !cost[at(0, n - 1)].is_finite() {
        return None;
    }
    let mut out = Vec::with_capacity(n - 2);
    let mut stack = vec![(0usize, n - 1)];
    while let Some((i, j)) = stack.pop() {
        if j - i < 2 {
            continue;
        }
        let k = split[at(i, j)] as usize;
        out.push([i as u32, k as u32, j as u32]);
        stack.push((i, k));
        stack.push((k, j));
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(q: &[DVec2], t: &[[u32; 3]]) -> f64 {
        t.iter()
            .map(|&[a, b, c]| {
                let (a, b, c) = (q[a as usize], q[b as usize], q[c as usize]);
                cross(b - a, c - a) / 2.0
            })
            .sum()
    }

    #[test]
    fn ear_clipping_covers_a_concave_loop_once_in_either_winding() {
        // An L shape: area 3.
        let l = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]
            .map(|(x, y)| DVec2::new(x, y));
        let t = ear_clip(&l);
        assert_eq!(t.len(), 4);
        assert!((area(&l, &t) - 3.0).abs() < 1e-12);
        let mut r = l.to_vec();
        r.reverse();
        let t = ear_clip(&r);
        assert!((area(&r, &t) + 3.0).abs() < 1e-12);
    }

    #[test]
    fn flat_corners_are_kept_in_the_triangulation() {
        // A square with its edge midpoints: every triangle has area.
        let q = [
            (0., 0.),
            (1., 0.),
            (2., 0.),
            (2., 1.),
            (2., 2.),
            (1., 2.),
            (0., 2.),
            (0., 1.),
        ]
        .map(|(x, y)| DVec2::new(x, y));
        let t = ear_clip(&q);
        assert_eq!(t.len(), 6);
        assert!((area(&q, &t) - 4.0).abs() < 1e-12);
        let p: Vec<DVec3> = q.iter().map(|v| v.extend(0.0)).collect();
        let t = min_weight(&p, &q, &|_| false).unwrap();
        assert_eq!(t.len(), 6);
        assert!((area(&q, &t) - 4.0).abs() < 1e-12);
        assert!(t.iter().all(|&[a, b, c]| {
            let (a, b, c) = (q[a as usize], q[b as usize], q[c as usize]);
            cross(b - a, c - a) > 0.0
        }));
    }

    #[test]
    fn min_weight_picks_the_short_diagonal() {
        // A kite: the short diagonal (length 2) beats the long one (4).
        let q = [(0., -2.), (1., 0.), (0., 2.), (-1., 0.)].map(|(x, y)| DVec2::new(x, y));
        let p: Vec<DVec3> = q.iter().map(|v| v.extend(0.0)).collect();
        let t = min_weight(&p, &q, &|_| false).unwrap();
        let uses = |a: u32, b: u32| {
            t.iter()
                .filter(|x| x.contains(&a) && x.contains(&b))
                .count()
        };
        assert_eq!(uses(1, 3), 2);
        assert_eq!(uses(0, 2), 0);
    }
}
