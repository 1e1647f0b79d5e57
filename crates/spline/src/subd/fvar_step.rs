//! What both ways of refining face-varying values (the span rules of
//! `fvar.rs`, the linear passes of `fvar_linear.rs`) share for one level:
//! which edges are continuous, the child values after the vertices' (a
//! value per face, then per edge one where continuous, else one per side)
//! and how they are computed, the child corners' table, and the vertex rule
//! inside a region.

use rayon::prelude::*;

use super::fvar::FVarChannel;
use super::level::{is_sharp, Level};
use super::refine::{child_slot, corner_of_edge, next_corner, Plan};
use super::scheme::{self, Term};

/// Items per parallel block.
const BLOCK: usize = 1024;

/// A channel refined from level `p` to its child `c` by `plan`.
#[derive(Clone, Copy)]
pub(super) struct Step<'a> {
    pub ch: &'a FVarChannel,
    pub p: &'a Level,
    pub c: &'a Level,
    pub plan: &'a Plan,
}

/// Where the child values after the vertices' go: the first face value,
/// and each edge's first value (one more entry: the end).
pub(super) struct Layout {
    pub face_base: usize,
    pub edge_base: Vec<u32>,
}

impl Layout {
    /// Child values in all.
    pub fn len(&self) -> usize {
        self.edge_base.last().copied().unwrap_or(0) as usize
    }
}

impl<'a> Step<'a> {
    /// The value at a parent corner.
    pub fn corner(&self, corner: usize) -> &'a [f64] {
        let d = self.ch.dim;
        let x = self.ch.corner_value[corner] as usize * d;
        &self.ch.values[x..x + d]
    }

    /// Whether each edge has one value at each end on every side (an
    /// interior edge of one region): two faces that agree on both ends'
    /// values.
    pub fn continuous_edges(&self) -> Vec<bool> {
        let (p, ch) = (self.p, self.ch);
        (0..p.edge_verts.len())
            .into_par_iter()
            .with_min_len(BLOCK)
            .map(|e| {
                let faces = p.edge_faces.row(e);
                if faces.len() != 2 {
                    return false;
                }
                let ends = |f: u32| {
                    let (a, b) = edge_corners(p, f, e as u32);
                    let (va, vb) = (p.faces.items[a], p.faces.items[b]);
                    let (xa, xb) = (ch.corner_value[a], ch.corner_value[b]);
                    if va <= vb {
                        (xa, xb)
                    } else {
                        (xb, xa)
                    }
                };
                ends(faces[0]) == ends(faces[1])
            })
            .collect()
    }

    /// The child values' layout after `vertex_values` values of vertices.
    pub fn layout(&self, continuous: &[bool], vertex_values: usize) -> Layout {
        let face_base = vertex_values;
        let mut edge_base = Vec::with_capacity(continuous.len() + 1);
        let mut n = (face_base + self.p.faces.len()) as u32;
        for (e, &cont) in continuous.iter().enumerate() {
            edge_base.push(n);
            n += if cont {
                1
            } else {
                self.p.edge_faces.row(e).len().max(1) as u32
            };
        }
        edge_base.push(n);
        Layout {
            face_base,
            edge_base,
        }
    }

    /// Fills the face and edge values of `values` (laid out by `layout`):
    /// faces the mean of their corners, continuous edges the edge rule
    /// (unless `all_linear`), other edges the midpoint of each side. Returns
    /// the vertices' part, left to the caller, and the face values.
    pub fn faces_and_edges<'v>(
        &self,
        continuous: &[bool],
        layout: &Layout,
        all_linear: bool,
        values: &'v mut [f64],
    ) -> (&'v mut [f64], &'v [f64]) {
        let (p, d) = (self.p, self.ch.dim);
        let (vertex_part, rest) = values.split_at_mut(layout.face_base * d);
        let (face_part, edge_part) = rest.split_at_mut(p.faces.len() * d);
        face_part
            .par_chunks_mut(d)
            .enumerate()
            .with_min_len(BLOCK)
            .for_each(|(f, out)| {
                let corners = p.faces.offsets[f] as usize..p.faces.offsets[f + 1] as usize;
                let w = 1.0 / corners.len() as f64;
                for (k, out) in out.iter_mut().enumerate() {
                    *out = corners.clone().map(|c| self.corner(c)[k] * w).sum();
                }
            });
        let face_part = &*face_part;
        let start = layout.edge_base[0] as usize;
        let at = |e: usize| (layout.edge_base[e] as usize - start) * d;
        blocks(edge_part, continuous.len(), at).for_each(|(edges, block)| {
            let base = at(edges.start);
            for e in edges {
                let out = &mut block[at(e) - base..at(e + 1) - base];
                let faces = p.edge_faces.row(e);
                let ends = |f: u32| {
                    let (a, b) = edge_corners(p, f, e as u32);
                    (self.corner(a), self.corner(b))
                };
                if continuous[e] && !all_linear {
                    let (xa, xb) = ends(faces[0]);
                    let (end_w, face_w) =
                        scheme::edge_point(self.plan.edge_weight[e] as f64, faces.len());
                    for (k, o) in out.iter_mut().enumerate() {
                        *o = end_w * (xa[k] + xb[k])
                            + faces
                                .iter()
                                .map(|&f| face_w * face_part[f as usize * d + k])
                                .sum::<f64>();
                    }
                } else {
                    // Midpoints, one per side (a continuous edge under
                    // `all_linear` has one value: the first side's).
                    for (&f, o) in faces.iter().zip(out.chunks_mut(d)) {
                        let (xa, xb) = ends(f);
                        for k in 0..d {
                            o[k] = 0.5 * (xa[k] + xb[k]);
                        }
                    }
                }
            }
        });
        (vertex_part, face_part)
    }

    /// The child corners' values: a quad per parent corner (`vertex_child`
    /// of the corner, its next edge's value on this face's side, the face's
    /// value, its previous edge's), placed as the child topology places
    /// them.
    pub fn corners(
        &self,
        continuous: &[bool],
        layout: &Layout,
        vertex_child: impl Fn(usize) -> u32 + Sync,
    ) -> Vec<u32> {
        let p = self.p;
        let mut corner_value = vec![0u32; 4 * p.faces.items.len()];
        let at = |f: usize| 4 * p.faces.offsets[f] as usize;
        blocks(&mut corner_value, p.faces.len(), at).for_each(|(faces, block)| {
            let base = at(faces.start);
            for f in faces {
                let run = &mut block[at(f) - base..at(f + 1) - base];
                let (start, end) = (p.faces.offsets[f] as usize, p.faces.offsets[f + 1] as usize);
                let side = |e: u32| {
                    let first = layout.edge_base[e as usize];
                    if continuous[e as usize] {
                        first
                    } else {
                        let faces = p.edge_faces.row(e as usize);
                        first + faces.iter().position(|&x| x == f as u32).unwrap_or(0) as u32
                    }
                };
                for (corner, quad) in (start..end).zip(run.chunks_mut(4)) {
                    let prev = if corner == start { end - 1 } else { corner - 1 };
                    let items = [
                        vertex_child(corner),
                        side(p.face_edges[corner]),
                        (layout.face_base + f) as u32,
                        side(p.face_edges[prev]),
                    ];
                    for (i, item) in items.into_iter().enumerate() {
                        quad[child_slot(end - start, corner - start, i)] = item;
                    }
                }
            }
        });
        debug_assert_eq!(corner_value.len(), self.c.faces.items.len());
        corner_value
    }

    /// The vertex rule of `v`, whose one value is `own` (every face at `v`
    /// holds it), over its neighbours' values and the child `face_values`;
    /// `limit` takes the limit masks instead.
    pub fn vertex_rule(
        &self,
        v: u32,
        own: &[f64],
        face_values: &[f64],
        limit: bool,
        out: &mut [f64],
    ) {
        let (p, d) = (self.p, self.ch.dim);
        let (edges, faces) = (
            p.vertex_edges.row(v as usize),
            p.vertex_faces.row(v as usize),
        );
        // The value at the far end of an edge, from any of its faces: all
        // hold `own` at `v`.
        let far = |e: u32| {
            let (a, b) = edge_corners(p, p.edge_faces.row(e as usize)[0], e);
            self.corner(if p.faces.items[a] == v { b } else { a })
        };
        let opposite = |f: u32| {
            let r = p.faces.offsets[f as usize] as usize..p.faces.offsets[f as usize + 1] as usize;
            let len = r.len();
            r.clone()
                .find(|&c| p.faces.items[c] == v)
                .map(|c| self.corner(r.start + (c - r.start + len / 2) % len))
        };
        out.iter_mut().for_each(|x| *x = 0.0);
        let mut emit = |t: Term, w: f64| {
            let x: Option<&[f64]> = match t {
                Term::Vertex => Some(own),
                Term::EdgeEnd(k) => Some(far(edges[k])),
                Term::FacePoint(k) => {
                    let f = faces[k] as usize;
                    Some(&face_values[f * d..(f + 1) * d])
                }
                Term::Opposite(k) => opposite(faces[k]),
            };
            if let Some(x) = x {
                (0..d).for_each(|k| out[k] += w * x[k]);
            }
        };
        let parent_sharp = |k: usize| is_sharp(p.edge_sharpness[edges[k] as usize]);
        let child_sharp = |k: usize| {
            let e = edges[k];
            let half = 2 * e + u32::from(p.edge_verts[e as usize][0] != v);
            is_sharp(self.c.edge_sharpness[half as usize])
        };
        let rules = (
            self.plan.parent_rule[v as usize],
            self.plan.child_rule[v as usize],
            self.plan.vertex_weight[v as usize] as f64,
        );
        scheme::blended_vertex_point(
            limit,
            rules,
            edges.len(),
            faces.len(),
            parent_sharp,
            child_sharp,
            &mut emit,
        );
    }
}

/// The corner of face `f` that starts edge `e`, and the next corner.
pub(super) fn edge_corners(p: &Level, f: u32, e: u32) -> (usize, usize) {
    let c = corner_of_edge(p, f, e);
    (c, next_corner(p, f, c))
}

/// `out` cut into one piece per block of `BLOCK` items, item `i`'s output
/// starting at `at(i)` (ascending, `at(n)` the end), for the blocks to
/// fill in parallel: items with outputs of different sizes, placed without
/// a serial pass over every item.
pub(super) fn blocks<T: Send>(
    out: &mut [T],
    n: usize,
    at: impl Fn(usize) -> usize,
) -> impl ParallelIterator<Item = (std::ops::Range<usize>, &mut [T])> {
    let mut pieces = Vec::with_capacity(n.div_ceil(BLOCK));
    let mut rest = out;
    for first in (0..n).step_by(BLOCK) {
        let last = (first + BLOCK).min(n);
        let (piece, tail) = rest.split_at_mut(at(last) - at(first));
        pieces.push((first..last, piece));
        rest = tail;
    }
    pieces.into_par_iter()
}
