//! Nesting the loops of one plane: the loops wound one way (positive area
//! in the plane's frame) are outer boundaries, the others holes; each hole
//! goes to the smallest outer loop holding it and is joined to it by a
//! keyhole bridge (from its rightmost point along +x to the corner the ray
//! meets first, as in Eberly's ear-clipping notes), so that one ring
//! bounds a face with holes. Clip's caps and polyfill share it.

use geode_geo::glam::DVec2;

/// A loop of corners (whatever a caller's corner is) with their positions
/// in the plane's frame and twice its signed area there.
pub(crate) struct Ring<T> {
    pub corners: Vec<T>,
    pub q: Vec<DVec2>,
    pub area2: f64,
}

impl<T> Ring<T> {
    pub fn new(corners: Vec<T>, q: Vec<DVec2>) -> Ring<T> {
        let area2 = super::signed_area2(&q);
        Ring { corners, q, area2 }
    }
}

/// What nesting made of a plane's loops.
pub(crate) struct Nested<T> {
    /// Each outer loop with its holes bridged in.
    pub bridged: Vec<Ring<T>>,
    /// Loops (indices) to close on their own: holes in no outer loop, or
    /// ones no bridge reached.
    pub alone: Vec<usize>,
    /// Loops with no area (left open).
    pub flat: usize,
}

/// Nests `loops` (see the module doc).
pub(crate) fn nest<T: Copy>(loops: &[Ring<T>]) -> Nested<T> {
    let flat = loops.iter().filter(|l| l.area2 == 0.0).count();
    let (outers, holes): (Vec<usize>, Vec<usize>) = (0..loops.len())
        .filter(|&k| loops[k].area2 != 0.0)
        .partition(|&k| loops[k].area2 > 0.0);
    let mut held: Vec<Vec<usize>> = vec![Vec::new(); outers.len()];
    let mut alone = Vec::new();
    for &h in &holes {
        match holder(loops, &outers, h) {
            Some(k) => held[k].push(h),
            None => alone.push(h),
        }
    }
    let mut bridged_rings = Vec::with_capacity(outers.len());
    for (k, &o) in outers.iter().enumerate() {
        let (ring, unbridged) = bridged(loops, o, &held[k]);
        bridged_rings.push(ring);
        alone.extend(unbridged);
    }
    Nested {
        bridged: bridged_rings,
        alone,
        flat,
    }
}

/// The smallest outer loop (index into `outers`) holding hole `h`.
fn holder<T>(loops: &[Ring<T>], outers: &[usize], h: usize) -> Option<usize> {
    let probe = loops[h].q[rightmost(&loops[h].q)];
    (0..outers.len())
        .filter(|&k| contains(&loops[outers[k]].q, probe))
        .min_by(|&a, &b| {
            loops[outers[a]]
                .area2
                .total_cmp(&loops[outers[b]].area2)
                .then(a.cmp(&b))
        })
}

/// Even-odd point in polygon.
fn contains(ring: &[DVec2], p: DVec2) -> bool {
    let n = ring.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (ring[i], ring[(i + 1) % n]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y) {
            inside = !inside;
        }
    }
    inside
}

fn rightmost(q: &[DVec2]) -> usize {
    (0..q.len())
        .max_by(|&a, &b| q[a].x.total_cmp(&q[b].x).then(q[a].y.total_cmp(&q[b].y)))
        .expect("a loop has corners")
}

/// Outer loop `o` with its holes joined in by keyhole bridges, right to
/// left, and the holes no bridge reached.
fn bridged<T: Copy>(loops: &[Ring<T>], o: usize, holes: &[usize]) -> (Ring<T>, Vec<usize>) {
    let mut unbridged = Vec::new();
    let mut corners = loops[o].corners.clone();
    let mut q = loops[o].q.clone();
    let mut holes = holes.to_vec();
    holes.sort_by(|&a, &b| {
        let (xa, xb) = (
            loops[a].q[rightmost(&loops[a].q)],
            loops[b].q[rightmost(&loops[b].q)],
        );
        xb.x.total_cmp(&xa.x).then(a.cmp(&b))
    });
    for h in holes {
        let hole = &loops[h];
        let m = rightmost(&hole.q);
        let Some(p) = bridge_point(&q, hole.q[m]) else {
            unbridged.push(h);
            continue;
        };
        let n = hole.q.len();
        let around = (0..=n).map(|k| (m + k) % n);
        let mut nc = corners[..=p].to_vec();
        let mut nq = q[..=p].to_vec();
        for k in around {
            nc.push(hole.corners[k]);
            nq.push(hole.q[k]);
        }
        nc.push(corners[p]);
        nq.push(q[p]);
        nc.extend_from_slice(&corners[p + 1..]);
        nq.extend_from_slice(&q[p + 1..]);
        corners = nc;
        q = nq;
    }
    let area2 = loops[o].area2;
    (Ring { corners, q, area2 }, unbridged)
}

/// The corner of `ring` a hole's rightmost point `m` bridges to: the
/// corner the ray from `m` along +x meets first, or the corner inside the
/// triangle that ray spans that is closest to the ray's direction.
fn bridge_point(ring: &[DVec2], m: DVec2) -> Option<usize> {
    let n = ring.len();
    let mut hit = f64::INFINITY;
    let mut best = None;
    for i in 0..n {
        let j = (i + 1) % n;
        let (a, b) = (ring[i], ring[j]);
        if a.y == b.y || (a.y - m.y) * (b.y - m.y) > 0.0 {
            continue;
        }
        let x = a.x + (m.y - a.y) * (b.x - a.x) / (b.y - a.y);
        if x >= m.x && x < hit {
            hit = x;
            best = Some(if a.x > b.x { i } else { j });
            if a.y == m.y && a.x == x {
                best = Some(i);
            } else if b.y == m.y && b.x == x {
                best = Some(j);
            }
        }
    }
    let p = best?;
    let hit = DVec2::new(hit, m.y);
    if ring[p] == hit {
        return Some(p);
    }
    let tri = [m, hit, ring[p]];
    let mut choice = (p, tangent(m, ring[p]), (ring[p] - m).length_squared());
    for (i, &r) in ring.iter().enumerate() {
        if i == p || r.x <= m.x || !in_triangle(r, tri) {
            continue;
        }
        let key = (tangent(m, r), (r - m).length_squared());
        if key.0 < choice.1 || key.0 == choice.1 && key.1 < choice.2 {
            choice = (i, key.0, key.1);
        }
    }
    Some(choice.0)
}

fn tangent(m: DVec2, r: DVec2) -> f64 {
    (r.y - m.y).abs() / (r.x - m.x)
}

fn in_triangle(p: DVec2, [a, b, c]: [DVec2; 3]) -> bool {
    let s = [
        (b - a).perp_dot(p - a),
        (c - b).perp_dot(p - b),
        (a - c).perp_dot(p - c),
    ];
    s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0)
}
