//! Clip phase 4: the cut loops of one side found from the piece edges in
//! the plane, nested (outer loops and their holes), bridged and closed by
//! caps (see the clip module doc).

use geode_geo::glam::DVec2;

use super::{Cap, Corner, Parts, Piece, PlaneEdge, Splitter, ABOVE};
use crate::carry::Blend;
use crate::fill::{chain_loops, ear_clip, plane_basis, signed_area2};
use crate::ModelError;

/// A directed edge of a cap, and what its corner at `from` copies.
#[derive(Clone, Copy)]
struct CapCorner {
    from: u32,
    to: u32,
    vb: Blend,
    face: u32,
}

/// A loop of a cap with its corners' positions in the cap's frame.
struct Loop {
    corners: Vec<CapCorner>,
    q: Vec<DVec2>,
    area2: f64,
}

impl Splitter<'_> {
    /// Caps every closed loop of `side`; returns how many chains did not
    /// close (or closed with no area) and stay open.
    pub(super) fn caps(
        &self,
        parts: &mut Parts,
        side: u8,
        style: Cap,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<usize, ModelError> {
        let edges = cap_edges(&parts.plane_edges, side);
        let outward = if side == ABOVE {
            -self.field.normal
        } else {
            self.field.normal
        };
        let (u, v) = plane_basis(outward);
        let q = |r: u32| {
            let p = self.position(r);
            DVec2::new(p.dot(u), p.dot(v))
        };
        let pairs: Vec<(u32, u32)> = edges.iter().map(|e| (e.from, e.to)).collect();
        let (chains, mut open) = chain_loops(&pairs, |incoming, candidates| {
            let e = &edges[incoming];
            let d_in = q(e.to) - q(e.from);
            let turn = |c: usize| {
                let d_out = q(edges[c].to) - q(edges[c].from);
                d_in.perp_dot(d_out).atan2(d_in.dot(d_out))
            };
            *candidates
                .iter()
                .max_by(|&&a, &&b| turn(a).total_cmp(&turn(b)).then(b.cmp(&a)))
                .expect("candidates are not empty")
        });
        if cancel() {
            return Err(ModelError::Cancelled);
        }
        let loops: Vec<Loop> = chains
            .into_iter()
            .map(|c| {
                let corners: Vec<CapCorner> = c.into_iter().map(|e| edges[e]).collect();
                let q: Vec<DVec2> = corners.iter().map(|c| q(c.from)).collect();
                let area2 = signed_area2(&q);
                Loop { corners, q, area2 }
            })
            .collect();
        open += loops.iter().filter(|l| l.area2 == 0.0).count();
        let (outers, holes): (Vec<usize>, Vec<usize>) = (0..loops.len())
            .filter(|&k| loops[k].area2 != 0.0)
            .partition(|&k| loops[k].area2 > 0.0);
        let mut held: Vec<Vec<usize>> = vec![Vec::new(); outers.len()];
        for &h in &holes {
            match holder(&loops, &outers, h) {
                Some(k) => held[k].push(h),
                // A hole in nothing: capped on its own, wound as it is.
                None => self.cap(parts, side, style, &loops[h].corners, &loops[h].q),
            }
        }
        for (k, &o) in outers.iter().enumerate() {
            let (corners, q, unbridged) = bridged(&loops, o, &held[k]);
            self.cap(parts, side, style, &corners, &q);
            for h in unbridged {
                self.cap(parts, side, style, &loops[h].corners, &loops[h].q);
            }
        }
        Ok(open)
    }

    /// Appends the cap over the ring `corners` (2D positions `q`).
    fn cap(&self, parts: &mut Parts, side: u8, style: Cap, corners: &[CapCorner], q: &[DVec2]) {
        let source = corners[0].face;
        let mut face = |ids: &[usize]| {
            parts.pieces.push(Piece {
                closed: true,
                count: ids.len() as u32,
                source,
                side,
            });
            parts.corners.extend(ids.iter().map(|&i| Corner {
                r: self.side_ref(corners[i].from, side),
                vb: corners[i].vb,
            }));
        };
        match style {
            Cap::Triangles => {
                for t in ear_clip(q) {
                    face(&t.map(|i| i as usize));
                }
            }
            _ => face(&(0..corners.len()).collect::<Vec<_>>()),
        }
    }
}

/// The edges bounding `side`'s caps, reversed (the way a cap runs): plane
/// edges used once on the side and at least once on the other.
fn cap_edges(plane_edges: &[PlaneEdge], side: u8) -> Vec<CapCorner> {
    let mut order: Vec<usize> = (0..plane_edges.len()).collect();
    order.sort_by_key(|&i| (plane_edges[i].key, i));
    let mut out = Vec::new();
    for group in order.chunk_by(|&a, &b| plane_edges[a].key == plane_edges[b].key) {
        let mut ours = group.iter().filter(|&&i| plane_edges[i].side == side);
        let others = group.len() - ours.clone().count();
        if let (Some(&i), None) = (ours.next(), ours.next()) {
            if others > 0 {
                let e = &plane_edges[i];
                out.push(CapCorner {
                    from: e.to,
                    to: e.from,
                    vb: e.to_vb,
                    face: e.face,
                });
            }
        }
    }
    out
}

/// The smallest outer loop (index into `outers`) holding hole `h`.
fn holder(loops: &[Loop], outers: &[usize], h: usize) -> Option<usize> {
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
fn bridged(loops: &[Loop], o: usize, holes: &[usize]) -> (Vec<CapCorner>, Vec<DVec2>, Vec<usize>) {
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
    (corners, q, unbridged)
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
