//! Clip phase 3: each primitive kept whole, dropped, or split into its
//! pieces on each side of the plane (see the clip module doc).

use geode_geo::glam::DVec3;
use geode_geo::PrimKind;
use rayon::prelude::*;

use super::{
    edge_key, Corner, Entry, Keep, Parts, Piece, PlaneEdge, Splitter, ABOVE, BELOW, CHUNK,
};
use crate::carry::copy;
use crate::fill::newell_normal;
use crate::ModelError;

/// Which classes a side keeps: above keeps 1 and 0, below -1 and 0.
fn sign(side: u8) -> i8 {
    if side == ABOVE {
        1
    } else {
        -1
    }
}

impl Splitter<'_> {
    pub(super) fn kept(&self, side: u8) -> bool {
        match self.keep {
            Keep::Above => side == ABOVE,
            Keep::Below => side == BELOW,
            Keep::Both => true,
        }
    }

    /// References of source points and cuts together.
    pub(super) fn references(&self) -> usize {
        self.g.num_points() + self.cuts.len()
    }

    /// Whether reference `r` lies on the plane (a cut, or a point on it).
    pub(super) fn on_plane(&self, r: u32) -> bool {
        let n = self.g.num_points();
        r as usize >= n || self.field.class[r as usize] == 0
    }

    /// Reference `r` as side `side` uses it: the side below has its own
    /// copies of points on the plane when points are split.
    pub(super) fn side_ref(&self, r: u32, side: u8) -> u32 {
        if self.split_points && side == BELOW && self.on_plane(r) {
            r + self.references() as u32
        } else {
            r
        }
    }

    /// The position of a reference (before copies).
    pub(super) fn position(&self, r: u32) -> DVec3 {
        let n = self.g.num_points();
        if (r as usize) < n {
            self.g.positions()[r as usize].as_dvec3()
        } else {
            self.cuts.positions[r as usize - n]
        }
    }

    /// Every primitive's pieces, chunk by chunk in parallel, in order.
    pub(super) fn run(&self, cancel: &(dyn Fn() -> bool + Sync)) -> Result<Parts, ModelError> {
        let nprims = self.g.num_prims();
        let chunks: Option<Vec<Parts>> = (0..nprims.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                if cancel() {
                    return None;
                }
                let mut out = Parts::default();
                let mut ring = Vec::new();
                for prim in c * CHUNK..((c + 1) * CHUNK).min(nprims) {
                    self.primitive(prim, &mut ring, &mut out);
                }
                Some(out)
            })
            .collect();
        let chunks = chunks.ok_or(ModelError::Cancelled)?;
        let mut parts = Parts {
            pieces: Vec::with_capacity(chunks.iter().map(|c| c.pieces.len()).sum()),
            corners: Vec::with_capacity(chunks.iter().map(|c| c.corners.len()).sum()),
            plane_edges: Vec::new(),
        };
        for c in chunks {
            parts.extend(c);
        }
        Ok(parts)
    }

    fn primitive(&self, prim: usize, ring: &mut Vec<Entry>, out: &mut Parts) {
        let g = self.g;
        let pts = g.prim_points(prim);
        let first_vertex = g.prim_vertex_range(prim).start as u32;
        let cls = &self.field.class;
        let has = |c: i8| pts.iter().any(|&p| cls[p as usize] == c);
        let (above, below) = (has(1), has(-1));
        let closed = g.prim_kind(prim) == PrimKind::Polygon;
        ring.clear();
        if above && below {
            self.cut_ring(pts, first_vertex, closed, ring);
        } else {
            ring.extend(pts.iter().enumerate().map(|(k, &p)| Entry {
                r: p,
                c: cls[p as usize],
                vb: copy(first_vertex + k as u32),
            }));
        }
        let whole_side = if above && below {
            None
        } else if above {
            Some(ABOVE)
        } else if below {
            Some(BELOW)
        } else {
            Some(self.in_plane_side(pts, closed))
        };
        for side in [ABOVE, BELOW] {
            let kept = self.kept(side);
            let needed = kept || (closed && self.capping);
            if !needed {
                continue;
            }
            let mut take = |piece: &[Entry]| {
                if closed && self.capping {
                    record_plane_edges(piece, side, prim as u32, out);
                }
                if kept {
                    self.emit(piece, closed, prim as u32, side, out);
                }
            };
            match (whole_side, closed) {
                (Some(s), _) if s != side => {}
                (Some(_), _) => take(ring),
                (None, true) => self.polygon_pieces(ring, side).iter().for_each(|p| take(p)),
                (None, false) => polyline_pieces(ring, side).iter().for_each(|p| take(p)),
            }
        }
    }

    /// The ring of a crossing primitive with a cut inserted on every
    /// crossing edge.
    fn cut_ring(&self, pts: &[u32], first_vertex: u32, closed: bool, ring: &mut Vec<Entry>) {
        let cls = &self.field.class;
        let n = pts.len();
        let np = self.g.num_points() as u32;
        for k in 0..n {
            let (a, v) = (pts[k], first_vertex + k as u32);
            ring.push(Entry {
                r: a,
                c: cls[a as usize],
                vb: copy(v),
            });
            if !closed && k + 1 == n {
                break;
            }
            let (b, w) = (pts[(k + 1) % n], first_vertex + ((k + 1) % n) as u32);
            if cls[a as usize] * cls[b as usize] < 0 {
                let (j, t) = self.cuts.find(a, b);
                ring.push(Entry {
                    r: np + j,
                    c: 0,
                    vb: (v, w, t as f32),
                });
            }
        }
    }

    /// The side a primitive lying in the plane belongs to: a polygon
    /// facing along the normal bounds what is below it.
    fn in_plane_side(&self, pts: &[u32], closed: bool) -> u8 {
        if !closed {
            return ABOVE;
        }
        let p: Vec<DVec3> = pts
            .iter()
            .map(|&i| self.g.positions()[i as usize].as_dvec3())
            .collect();
        if newell_normal(&p).dot(self.field.normal) > 0.0 {
            BELOW
        } else {
            ABOVE
        }
    }

    /// The pieces of a crossing polygon on `side`.
    fn polygon_pieces(&self, ring: &[Entry], side: u8) -> Vec<Vec<Entry>> {
        let s = sign(side);
        let n = ring.len();
        let removed = |i: usize| ring[i % n].c == -s;
        // Start just after a removed run: every arc then lies in one pass.
        let start = (0..n)
            .find(|&i| removed(i) && !removed(i + 1))
            .map_or(0, |i| i + 1);
        let mut arcs: Vec<Vec<Entry>> = Vec::new();
        let mut arc = Vec::new();
        for k in 0..n {
            let i = (start + k) % n;
            if removed(i) {
                if !arc.is_empty() {
                    arcs.push(std::mem::take(&mut arc));
                }
            } else {
                arc.push(ring[i]);
            }
        }
        if !arc.is_empty() {
            arcs.push(arc);
        }
        // An arc only touching the plane adds no area on this side.
        arcs.retain(|a| a.iter().any(|e| e.c == s));
        if arcs.len() <= 1 {
            return arcs;
        }
        self.join_arcs(arcs, ring)
    }

    /// Several arcs of one polygon joined into pieces along the segments
    /// where the plane runs inside the polygon.
    fn join_arcs(&self, arcs: Vec<Vec<Entry>>, ring: &[Entry]) -> Vec<Vec<Entry>> {
        let p: Vec<DVec3> = ring.iter().map(|e| self.position(e.r)).collect();
        let line = newell_normal(&p).cross(self.field.normal);
        // (position along the cut line, arc, whether it is the arc's end)
        let mut ends: Vec<(f64, usize, bool)> = arcs
            .iter()
            .enumerate()
            .flat_map(|(k, a)| {
                let at = |e: &Entry| self.position(e.r).dot(line);
                [(at(&a[0]), k, false), (at(&a[a.len() - 1]), k, true)]
            })
            .collect();
        ends.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
        let mut next = vec![usize::MAX; arcs.len()];
        for pair in ends.chunks_exact(2) {
            let (end, start) = match (pair[0].2, pair[1].2) {
                (true, false) => (pair[0].1, pair[1].1),
                (false, true) => (pair[1].1, pair[0].1),
                _ => return vec![arcs.concat()],
            };
            next[end] = start;
        }
        let mut seen = vec![false; arcs.len()];
        let mut pieces = Vec::new();
        for first in 0..arcs.len() {
            if seen[first] {
                continue;
            }
            let mut piece = Vec::new();
            let mut k = first;
            while !seen[k] {
                seen[k] = true;
                piece.extend_from_slice(&arcs[k]);
                k = next[k];
            }
            pieces.push(piece);
        }
        pieces
    }

    fn emit(&self, piece: &[Entry], closed: bool, source: u32, side: u8, out: &mut Parts) {
        if piece.len() < if closed { 3 } else { 2 } {
            return;
        }
        out.pieces.push(Piece {
            closed,
            count: piece.len() as u32,
            source,
            side,
        });
        out.corners.extend(piece.iter().map(|e| Corner {
            r: self.side_ref(e.r, side),
            vb: e.vb,
        }));
    }
}

/// The runs of a crossing polyline on `side` (a run lying in the plane
/// goes above).
fn polyline_pieces(ring: &[Entry], side: u8) -> Vec<Vec<Entry>> {
    let s = sign(side);
    ring.split(|e| e.c == -s)
        .filter(|run| run.len() >= 2 && (side == ABOVE || run.iter().any(|e| e.c == s)))
        .map(<[Entry]>::to_vec)
        .collect()
}

/// The edges of a piece lying in the plane.
fn record_plane_edges(piece: &[Entry], side: u8, face: u32, out: &mut Parts) {
    let n = piece.len();
    for k in 0..n {
        let (a, b) = (piece[k], piece[(k + 1) % n]);
        if a.c == 0 && b.c == 0 && a.r != b.r {
            out.plane_edges.push(PlaneEdge {
                key: edge_key(a.r, b.r),
                from: a.r,
                to: b.r,
                side,
                face,
                to_vb: b.vb,
            });
        }
    }
}
