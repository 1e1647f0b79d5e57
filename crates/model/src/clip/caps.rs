//! Clip phase 4: the cut loops of one side found from the piece edges in
//! the plane, nested (outer loops and their holes), bridged and closed by
//! caps (see the clip module doc).

use geode_geo::glam::DVec2;

use super::{Cap, Corner, Parts, Piece, PlaneEdge, Splitter, ABOVE};
use crate::carry::Blend;
use crate::fill::nest::{nest, Ring};
use crate::fill::{chain_loops, ear_clip, plane_basis};
use crate::ModelError;

/// A directed edge of a cap, and what its corner at `from` copies.
#[derive(Clone, Copy)]
struct CapCorner {
    from: u32,
    to: u32,
    vb: Blend,
    face: u32,
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
        let loops: Vec<Ring<CapCorner>> = chains
            .into_iter()
            .map(|c| {
                let corners: Vec<CapCorner> = c.into_iter().map(|e| edges[e]).collect();
                let q: Vec<DVec2> = corners.iter().map(|c| q(c.from)).collect();
                Ring::new(corners, q)
            })
            .collect();
        let nested = nest(&loops);
        open += nested.flat;
        for ring in &nested.bridged {
            self.cap(parts, side, style, &ring.corners, &ring.q);
        }
        // A hole in nothing is capped on its own, wound as it is.
        for h in nested.alone {
            self.cap(parts, side, style, &loops[h].corners, &loops[h].q);
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
