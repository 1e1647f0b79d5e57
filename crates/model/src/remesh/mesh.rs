//! The remesher's working mesh: flat arrays of triangles (three corners
//! and three feature bits each) and per-vertex data, with the adjacency a
//! phase reads (vertex-to-face lists, opposite half-edges, valences)
//! rebuilt from the triangles at the start of each phase.
//!
//! Half-edge `3 f + k` runs from corner `k` of face `f` to corner `k + 1`;
//! its feature bit is bit `k` of the face's mask. A border edge is always
//! a feature, so one rule (never flip, collapse only along) covers both.

use geode_geo::glam::Vec3;
use rayon::prelude::*;

/// The split (4/3) and collapse (4/5) thresholds are taken of the
/// target length times this: Botsch and Kobbelt's own leave the mean edge
/// 5% to 10% short of the target (collapses stop at 4/5 but splits halve
/// at 4/3); aimed 4% long, the mean lands within 3% of it (sphere, torus,
/// car beside pymeshlab).
pub(super) const AIM: f32 = 1.04;

/// No element (a border half-edge's opposite, an unset index).
pub(super) const NONE: u32 = u32::MAX;

/// Where a vertex lies on the original surface: an original triangle and
/// the barycentric weights of its three corners.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Proj {
    pub tri: u32,
    pub w: [f32; 3],
}

/// The mesh being remeshed.
pub(super) struct Mesh {
    pub pos: Vec<Vec3>,
    /// Target edge length at each vertex.
    pub size: Vec<f32>,
    pub proj: Vec<Proj>,
    /// Corners: where feature lines meet, end or turn sharply; they never
    /// move or go.
    pub fixed: Vec<bool>,
    pub faces: Vec<[u32; 3]>,
    /// Bit `k`: edge `k` (corner `k` to `k + 1`) is a feature.
    pub mask: Vec<u8>,
}

pub(super) fn next(h: u32) -> u32 {
    if h % 3 == 2 {
        h - 2
    } else {
        h + 1
    }
}

pub(super) fn prev(h: u32) -> u32 {
    if h.is_multiple_of(3) {
        h + 2
    } else {
        h - 1
    }
}

impl Mesh {
    /// The vertex half-edge `h` starts at.
    pub fn from(&self, h: u32) -> u32 {
        self.faces[(h / 3) as usize][(h % 3) as usize]
    }

    /// The vertex half-edge `h` ends at.
    pub fn to(&self, h: u32) -> u32 {
        self.from(next(h))
    }

    pub fn is_feature(&self, h: u32) -> bool {
        self.mask[(h / 3) as usize] & (1 << (h % 3)) != 0
    }

    pub fn set_feature(&mut self, h: u32) {
        self.mask[(h / 3) as usize] |= 1 << (h % 3);
    }

    /// The target length of the edge from `a` to `b`.
    pub fn edge_size(&self, a: u32, b: u32) -> f32 {
        0.5 * AIM * (self.size[a as usize] + self.size[b as usize])
    }

    /// Drops the faces marked in `dead` and the vertices no face uses,
    /// keeping the order of what stays; returns each old vertex's new
    /// number (NONE if gone).
    pub fn compact(&mut self, dead: &[bool]) -> Vec<u32> {
        let mut keep_face = 0;
        for (f, &gone) in dead.iter().enumerate() {
            if !gone {
                self.faces[keep_face] = self.faces[f];
                self.mask[keep_face] = self.mask[f];
                keep_face += 1;
            }
        }
        self.faces.truncate(keep_face);
        self.mask.truncate(keep_face);
        let mut map = vec![NONE; self.pos.len()];
        for f in &self.faces {
            for &v in f {
                map[v as usize] = 0;
            }
        }
        let mut n = 0u32;
        for (v, slot) in map.iter_mut().enumerate() {
            if *slot == 0 {
                *slot = n;
                self.pos[n as usize] = self.pos[v];
                self.size[n as usize] = self.size[v];
                self.proj[n as usize] = self.proj[v];
                self.fixed[n as usize] = self.fixed[v];
                n += 1;
            }
        }
        self.pos.truncate(n as usize);
        self.size.truncate(n as usize);
        self.proj.truncate(n as usize);
        self.fixed.truncate(n as usize);
        self.faces
            .par_iter_mut()
            .for_each(|f| *f = f.map(|v| map[v as usize]));
        map
    }
}

/// Adjacency of a mesh as it was when last built. Rebuilt in place, so
/// its arrays keep their memory from one phase to the next (fresh ones
/// cost page faults of the same order as the build itself).
#[derive(Default)]
pub(super) struct Topo {
    /// Faces of vertex `v`: `vf[off[v]..off[v + 1]]`, in increasing order.
    off: Vec<u32>,
    vf: Vec<u32>,
    /// Beside `vf`: the half-edge leaving the vertex in that face and the
    /// face's other two corners in order (the opposites and the
    /// relaxation read these contiguous lists rather than the faces).
    leaving: Vec<Leaving>,
    fill: Vec<u32>,
    /// Per half-edge: the opposite half-edge, or NONE on a border.
    pub opp: Vec<u32>,
    /// Per vertex: the number of neighbouring vertices.
    pub valence: Vec<u32>,
    /// Per vertex: the number of feature edges it ends.
    pub feature: Vec<u8>,
    /// Per vertex: on a border.
    pub border: Vec<bool>,
}

/// A half-edge leaving a vertex: the face's other corners in order, `to`
/// where it ends.
#[derive(Clone, Copy, Default)]
pub(super) struct Leaving {
    pub edge: u32,
    pub to: u32,
    pub third: u32,
}

/// `v` cleared and refilled with `len` copies of `x`, its memory kept.
fn refill<T: Clone>(v: &mut Vec<T>, len: usize, x: T) {
    v.clear();
    v.resize(len, x);
}

impl Topo {
    pub fn build(m: &Mesh) -> Topo {
        let mut topo = Topo::default();
        topo.rebuild(m);
        topo
    }

    /// The adjacency of `m` as it is now.
    pub fn rebuild(&mut self, m: &Mesh) {
        let n = m.pos.len();
        let corners = 3 * m.faces.len();
        refill(&mut self.off, n + 1, 0);
        for f in &m.faces {
            for &v in f {
                self.off[v as usize + 1] += 1;
            }
        }
        for v in 0..n {
            self.off[v + 1] += self.off[v];
        }
        self.fill.clear();
        self.fill.extend_from_slice(&self.off[..n]);
        refill(&mut self.leaving, corners, Leaving::default());
        for (fi, f) in m.faces.iter().enumerate() {
            for (k, &v) in f.iter().enumerate() {
                let slot = &mut self.fill[v as usize];
                self.leaving[*slot as usize] = Leaving {
                    edge: 3 * fi as u32 + k as u32,
                    to: f[(k + 1) % 3],
                    third: f[(k + 2) % 3],
                };
                *slot += 1;
            }
        }
        refill(&mut self.vf, corners, 0);
        self.vf
            .par_iter_mut()
            .zip(self.leaving.par_iter())
            .for_each(|(f, l)| *f = l.edge / 3);
        // The opposite of a to b is the half-edge leaving b for a.
        refill(&mut self.opp, corners, NONE);
        let (off, leaving) = (&self.off, &self.leaving);
        self.opp
            .par_chunks_mut(3)
            .zip(m.faces.par_iter())
            .for_each(|(out, t)| {
                for k in 0..3 {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    let slots = off[b as usize] as usize..off[b as usize + 1] as usize;
                    if let Some(l) = leaving[slots].iter().find(|l| l.to == a) {
                        out[k] = l.edge;
                    }
                }
            });
        refill(&mut self.border, n, false);
        refill(&mut self.feature, n, 0);
        for h in 0..corners as u32 {
            let o = self.opp[h as usize];
            if o == NONE {
                self.border[m.from(h) as usize] = true;
            }
            if m.is_feature(h) && (o == NONE || h < o) {
                for v in [m.from(h), m.to(h)] {
                    self.feature[v as usize] = self.feature[v as usize].saturating_add(1);
                }
            }
        }
        refill(&mut self.valence, n, 0);
        let (off, border) = (&self.off, &self.border);
        self.valence
            .par_iter_mut()
            .enumerate()
            .for_each(|(v, val)| *val = off[v + 1] - off[v] + border[v] as u32);
    }

    /// The half-edges leaving `v`, one per face, as `faces_of` orders them.
    pub fn leaving(&self, v: u32) -> &[Leaving] {
        &self.leaving[self.off[v as usize] as usize..self.off[v as usize + 1] as usize]
    }

    pub fn faces_of(&self, v: u32) -> &[u32] {
        &self.vf[self.off[v as usize] as usize..self.off[v as usize + 1] as usize]
    }

    /// The half-edge from `a` to `b`, or NONE.
    pub fn half_edge(&self, m: &Mesh, a: u32, b: u32) -> u32 {
        for &f in self.faces_of(a) {
            let t = m.faces[f as usize];
            for k in 0..3 {
                if t[k] == a && t[(k + 1) % 3] == b {
                    return 3 * f + k as u32;
                }
            }
        }
        NONE
    }

    /// Whether `a` and `b` share an edge.
    pub fn adjacent(&self, m: &Mesh, a: u32, b: u32) -> bool {
        self.faces_of(a)
            .iter()
            .any(|&f| m.faces[f as usize].contains(&b))
    }

    /// The two other ends of `v`'s feature edges, if it has two.
    pub fn feature_ends(&self, m: &Mesh, v: u32) -> Option<[u32; 2]> {
        let mut ends = [v; 2];
        let mut found = 0;
        for &f in self.faces_of(v) {
            for k in 0..3u32 {
                let h = 3 * f + k;
                let (a, b) = (m.from(h), m.to(h));
                if !m.is_feature(h) || (a != v && b != v) {
                    continue;
                }
                let other = if a == v { b } else { a };
                if !ends[..found].contains(&other) {
                    if found == 2 {
                        return None;
                    }
                    ends[found] = other;
                    found += 1;
                }
            }
        }
        (found == 2).then_some(ends)
    }

    /// The neighbours of `v` into `out` (cleared first), each once or
    /// twice (once per face they share with `v`): for maxima, in time
    /// linear in the valence.
    pub fn neighbours(&self, m: &Mesh, v: u32, out: &mut Vec<u32>) {
        out.clear();
        for &f in self.faces_of(v) {
            out.extend(m.faces[f as usize].iter().filter(|&&x| x != v));
        }
    }
}
