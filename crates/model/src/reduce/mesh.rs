//! The working mesh of a reduction: positions and quadrics per point,
//! triangles as flat corner triples, each point's corners as a linked list
//! through the corners (so a collapse relinks a point's corners onto its
//! neighbour without allocating), each corner's wedge (the first corner of
//! its point with the same vertex attribute values: corners of one wedge
//! are one "vertex" to the eye, and a point with two wedges is on a seam),
//! and each point's kind, which says how it may move.

use geode_geo::glam::{DVec3, Vec3};
use rayon::prelude::*;

use geode_geo::ops::Quadric;

/// No corner, no triangle.
pub(crate) const NONE: u32 = u32::MAX;

/// How a point may move, fixed before the first collapse (a collapse keeps
/// every kind: points move onto points of their own kind or locked ones).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// A manifold fan of one wedge: moves anywhere.
    Interior,
    /// On one open border (two border edges, one wedge): moves along it.
    Border,
    /// On one seam (two seam edges, two wedges): moves along it.
    Seam,
    /// Never moves: a locked border or seam, a corner where borders and
    /// seams meet, non-manifold edges or fans.
    Locked,
}

/// What the setup is told about the input.
pub(crate) struct Setup<'a> {
    pub positions: &'a [Vec3],
    pub triangles: Vec<[u32; 3]>,
    /// Whether two corners' vertex attributes are equal (None: the input
    /// has no vertex attributes).
    pub same_vertex: Option<&'a (dyn Fn(u32, u32) -> bool + Sync)>,
    pub lock_borders: bool,
    pub lock_seams: bool,
    pub cancel: &'a (dyn Fn() -> bool + Sync),
}

pub(crate) struct Mesh {
    pub pos: Vec<DVec3>,
    /// The input's bounding box: no placement goes outside it.
    pub bounds: [DVec3; 2],
    /// The least cost a collapse is keyed with (a trace of the box's
    /// diagonal to the fourth: costs are area times squared distance).
    pub cost_floor: f64,
    /// Point indices per triangle; `[NONE; 3]` once collapsed away.
    pub tris: Vec<[u32; 3]>,
    /// Per point: its first corner (NONE: none).
    pub head: Vec<u32>,
    /// Per corner: the next corner of the same point.
    pub next: Vec<u32>,
    pub wedge: Vec<u32>,
    pub quadric: Vec<Quadric>,
    pub kind: Vec<Kind>,
    pub removed: Vec<bool>,
    /// Per point: bumped at each change, so heap entries made before it
    /// are known stale.
    pub stamp: Vec<u32>,
    pub live: usize,
}

/// Constraint planes along borders and seams weigh this many times the
/// squared edge length (a triangle's plane weighs its area), so moving a
/// border point off its line costs more than any bend of the surface.
const CONSTRAINT_WEIGHT: f64 = 10.0;

impl Mesh {
    /// The working mesh, or None if cancelled while it was set up.
    pub fn new(s: Setup) -> Option<Mesh> {
        let n = s.positions.len();
        let mut tris = s.triangles;
        // Triangles repeating a point are no triangles.
        let mut live = 0;
        for t in tris.iter_mut() {
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                *t = [NONE; 3];
            } else {
                live += 1;
            }
        }
        let corners = tris.len() * 3;
        let mut head = vec![NONE; n];
        let mut next = vec![NONE; corners];
        // Prepending in reverse keeps each list in corner order.
        for c in (0..corners).rev() {
            let p = tris[c / 3][c % 3];
            if p != NONE {
                next[c] = head[p as usize];
                head[p as usize] = c as u32;
            }
        }
        let pos: Vec<DVec3> = s.positions.iter().map(|p| p.as_dvec3()).collect();
        let wedge = wedges(&tris, &head, &next, s.same_vertex);
        if (s.cancel)() {
            return None;
        }
        let bounds = pos
            .iter()
            .fold([DVec3::INFINITY, DVec3::NEG_INFINITY], |[lo, hi], &p| {
                [lo.min(p), hi.max(p)]
            });
        let diagonal = (bounds[1] - bounds[0]).length();
        let mut mesh = Mesh {
            pos,
            bounds,
            cost_floor: 1e-14 * diagonal.powi(4),
            tris,
            head,
            next,
            wedge,
            quadric: Vec::new(),
            kind: Vec::new(),
            removed: vec![false; n],
            stamp: vec![0; n],
            live,
        };
        let (quadric, kind) = (0..n)
            .into_par_iter()
            .map_init(Vec::new, |scratch, v| {
                // Every point asks: in a parallel map only the items that
                // ask are skipped once it says stop.
                if (s.cancel)() {
                    return (Quadric::default(), Kind::Locked);
                }
                mesh.classify(v as u32, scratch, s.lock_borders, s.lock_seams)
            })
            .unzip();
        mesh.quadric = quadric;
        mesh.kind = kind;
        (!(s.cancel)()).then_some(mesh)
    }

    /// The corners of point `v` (live and dead), in list order.
    pub fn corners(&self, v: u32) -> Corners<'_> {
        Corners {
            next: &self.next,
            at: self.head[v as usize],
        }
    }

    /// The wedge of point `p`'s corner in triangle `t`.
    pub fn wedge_in(&self, t: usize, p: u32) -> u32 {
        let k = self.tris[t]
            .iter()
            .position(|&q| q == p)
            .expect("p is in t");
        self.wedge[3 * t + k]
    }

    /// Point `v`'s quadric (its triangles' planes and the constraint
    /// planes of its border and seam edges) and its kind.
    fn classify(
        &self,
        v: u32,
        edges: &mut Vec<(u32, u32)>,
        lock_borders: bool,
        lock_seams: bool,
    ) -> (Quadric, Kind) {
        let mut q = Quadric::default();
        edges.clear();
        let mut wedges = 0;
        let mut tris = 0;
        for c in self.corners(v) {
            let t = self.tris[c as usize / 3];
            q.add(&Quadric::triangle(t.map(|p| self.pos[p as usize])));
            // Wedges are first corners, so a point's distinct wedges are
            // counted by how many of its corners are their own.
            if self.wedge[c as usize] == c {
                wedges += 1;
            }
            tris += 1;
            let k = c as usize % 3;
            edges.push((t[(k + 1) % 3], c / 3));
            edges.push((t[(k + 2) % 3], c / 3));
        }
        if tris == 0 {
            return (q, Kind::Locked);
        }
        edges.sort_unstable();
        let (mut neighbours, mut borders, mut seams, mut complex) = (0, 0, 0, false);
        let pv = self.pos[v as usize];
        let mut i = 0;
        while i < edges.len() {
            let nb = edges[i].0;
            let mut j = i;
            while j < edges.len() && edges[j].0 == nb {
                j += 1;
            }
            neighbours += 1;
            let on = &edges[i..j];
            let seam = on.len() == 2 && {
                let (t0, t1) = (on[0].1 as usize, on[1].1 as usize);
                self.wedge_in(t0, v) != self.wedge_in(t1, v)
                    || self.wedge_in(t0, nb) != self.wedge_in(t1, nb)
            };
            match on.len() {
                1 => borders += 1,
                2 if seam => seams += 1,
                2 => {}
                _ => complex = true,
            }
            if on.len() == 1 || seam {
                for &(_, t) in on {
                    q.add(&self.constraint(t as usize, pv, self.pos[nb as usize]));
                }
            }
            i = j;
        }
        let kind = match (borders, seams, wedges) {
            _ if complex => Kind::Locked,
            (0, 0, 1) if neighbours == tris => Kind::Interior,
            (2, 0, 1) if neighbours == tris + 1 && !lock_borders => Kind::Border,
            (0, 2, 2) if neighbours == tris && !lock_seams => Kind::Seam,
            _ => Kind::Locked,
        };
        (q, kind)
    }

    /// The plane through edge `a b` of triangle `t` at right angles to it,
    /// weighted by the squared edge length; its weight is left out of the
    /// area the error is measured over.
    fn constraint(&self, t: usize, a: DVec3, b: DVec3) -> Quadric {
        let p = self.tris[t].map(|p| self.pos[p as usize]);
        let normal = (p[1] - p[0]).cross(p[2] - p[0]);
        let edge = b - a;
        let n = edge.cross(normal);
        let len = n.length();
        if !(len > 0.0 && len.is_finite()) {
            return Quadric::default();
        }
        Quadric::plane(n / len, a, CONSTRAINT_WEIGHT * edge.length_squared()).uncounted()
    }
}

/// Each corner's wedge: the first corner of its point whose vertex
/// attributes equal its own.
fn wedges(
    tris: &[[u32; 3]],
    head: &[u32],
    next: &[u32],
    same: Option<&(dyn Fn(u32, u32) -> bool + Sync)>,
) -> Vec<u32> {
    (0..tris.len() * 3)
        .into_par_iter()
        .map(|c| {
            let p = tris[c / 3][c % 3];
            if p == NONE {
                return NONE;
            }
            let first = head[p as usize];
            let Some(same) = same else { return first };
            let mut at = first;
            while at != c as u32 {
                if same(at, c as u32) {
                    return at;
                }
                at = next[at as usize];
            }
            c as u32
        })
        .collect()
}

/// A point's corners: follows the list.
pub(crate) struct Corners<'a> {
    next: &'a [u32],
    at: u32,
}

impl Iterator for Corners<'_> {
    type Item = u32;
    fn next(&mut self) -> Option<u32> {
        (self.at != NONE).then(|| {
            let c = self.at;
            self.at = self.next[c as usize];
            c
        })
    }
}
