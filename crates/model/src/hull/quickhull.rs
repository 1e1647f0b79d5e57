//! The 3D quickhull loop: faces with neighbours and outside sets, the
//! visible region of an eye point, the cone that replaces it (see the
//! hull module doc).

use std::cmp::Ordering;

use geode_geo::glam::Vec3;
use rayon::prelude::*;

use super::exact::Plane;
use super::orient3d;
use crate::ModelError;

/// Point sets larger than this are reassigned in parallel.
const PARALLEL_POINTS: usize = 1 << 15;
const NONE: u32 = u32::MAX;

/// An outside point with its position beside its number: moving points
/// between faces then reads memory in order (gathering positions by
/// number was most of the time).
#[derive(Clone, Copy)]
struct Outside {
    i: u32,
    p: Vec3,
}

/// A hull triangle, wound outward: `adj[i]` is the face across the edge
/// from `v[i]` to `v[(i + 1) % 3]`; `outside` the points strictly above
/// it that no earlier face took.
struct Face {
    v: [u32; 3],
    adj: [u32; 3],
    plane: Plane,
    outside: Vec<Outside>,
    alive: bool,
}

pub(super) struct Quickhull<'a> {
    p: &'a [Vec3],
    faces: Vec<Face>,
    /// Faces that may still have outside points.
    pending: Vec<u32>,
    /// Per face: the step that last tested it and whether the eye saw it.
    seen: Vec<(u32, bool)>,
    step: u32,
    /// Buffers reused by every step.
    visible: Vec<u32>,
    horizon: Vec<(u32, usize)>,
    starts: Vec<(u32, u32)>,
    moving: Vec<Outside>,
    targets: Vec<u32>,
}

impl<'a> Quickhull<'a> {
    /// The tetrahedron `t` (four points not on one plane) with every other
    /// point given to the first face it lies above.
    pub(super) fn new(
        p: &'a [Vec3],
        t: [u32; 4],
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<Quickhull<'a>, ModelError> {
        let [a, mut b, mut c, d] = t;
        let at = |i: u32| p[i as usize];
        if orient3d(at(a), at(b), at(c), at(d)) == Ordering::Greater {
            std::mem::swap(&mut b, &mut c);
        }
        let mut hull = Quickhull {
            p,
            faces: Vec::new(),
            pending: Vec::new(),
            seen: Vec::new(),
            step: 0,
            visible: Vec::new(),
            horizon: Vec::new(),
            starts: Vec::new(),
            moving: Vec::new(),
            targets: Vec::new(),
        };
        for v in [[a, b, c], [a, d, b], [b, d, c], [c, d, a]] {
            hull.push_face(v);
        }
        for f in 0..4 {
            for i in 0..3 {
                let (u, w) = (hull.faces[f].v[i], hull.faces[f].v[(i + 1) % 3]);
                let across = (0..4)
                    .find(|&g| g != f && hull.edge_index(g, w, u).is_some())
                    .expect("a tetrahedron's faces meet at every edge");
                hull.faces[f].adj[i] = across as u32;
            }
        }
        hull.assign_initial(&t, cancel)?;
        Ok(hull)
    }

    fn push_face(&mut self, v: [u32; 3]) -> u32 {
        let [a, b, c] = v.map(|i| self.p[i as usize]);
        self.faces.push(Face {
            v,
            adj: [NONE; 3],
            plane: Plane::new(a, b, c),
            outside: Vec::new(),
            alive: true,
        });
        self.seen.push((0, false));
        self.faces.len() as u32 - 1
    }

    /// The index of face `f`'s edge from `u` to `w`.
    fn edge_index(&self, f: usize, u: u32, w: u32) -> Option<usize> {
        let v = self.faces[f].v;
        (0..3).find(|&i| v[i] == u && v[(i + 1) % 3] == w)
    }

    /// Whether point `p` lies strictly above face `f`'s plane.
    fn above(&self, f: u32, p: Vec3) -> bool {
        self.faces[f as usize].plane.orient(p) == Ordering::Greater
    }

    /// Whether point `p` lies above face `f`'s plane or on it.
    fn weakly_above(&self, f: u32, p: Vec3) -> bool {
        self.faces[f as usize].plane.orient(p) != Ordering::Less
    }

    fn assign_initial(
        &mut self,
        t: &[u32; 4],
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<(), ModelError> {
        const CHUNK: usize = 1 << 14;
        let n = self.p.len();
        let this = &*self;
        let chunks: Option<Vec<[Vec<Outside>; 4]>> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                if cancel() {
                    return None;
                }
                let mut sets: [Vec<Outside>; 4] = Default::default();
                for i in (c * CHUNK..((c + 1) * CHUNK).min(n)).map(|i| i as u32) {
                    let p = this.p[i as usize];
                    if t.contains(&i) {
                        continue;
                    }
                    if let Some(f) = (0..4).find(|&f| this.above(f, p)) {
                        sets[f as usize].push(Outside { i, p });
                    }
                }
                Some(sets)
            })
            .collect();
        for sets in chunks.ok_or(ModelError::Cancelled)? {
            for (f, s) in sets.into_iter().enumerate() {
                self.faces[f].outside.extend(s);
            }
        }
        self.pending = (0..4u32).rev().collect();
        Ok(())
    }

    /// Adds eye points until no face has points outside; the hull's
    /// triangles, in the order their faces were made.
    pub(super) fn run(
        mut self,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<Vec<[u32; 3]>, ModelError> {
        while let Some(f) = self.pending.pop() {
            let face = &self.faces[f as usize];
            if !face.alive || face.outside.is_empty() {
                continue;
            }
            // An iteration can move a hundred thousand points: poll each.
            if cancel() {
                return Err(ModelError::Cancelled);
            }
            let eye = self.farthest(f);
            self.visible_from(f, eye);
            let first_new = self.cone(eye);
            let mut moving = std::mem::take(&mut self.moving);
            moving.clear();
            for &v in &self.visible {
                let face = &mut self.faces[v as usize];
                face.alive = false;
                moving.extend(
                    std::mem::take(&mut face.outside)
                        .into_iter()
                        .filter(|o| o.i != eye),
                );
            }
            self.assign(&moving, first_new);
            self.moving = moving;
            for g in (first_new..self.faces.len() as u32).rev() {
                if !self.faces[g as usize].outside.is_empty() {
                    self.pending.push(g);
                }
            }
        }
        Ok(self.faces.iter().filter(|f| f.alive).map(|f| f.v).collect())
    }

    /// The outside point of face `f` farthest from its plane (the first
    /// of equals).
    fn farthest(&self, f: u32) -> u32 {
        let face = &self.faces[f as usize];
        let normal = face.plane.normal();
        let mut best = (f64::NEG_INFINITY, NONE);
        for o in &face.outside {
            let d = normal.dot(o.p.as_dvec3());
            if d > best.0 {
                best = (d, o.i);
            }
        }
        best.1
    }

    /// The faces `eye` sees (a walk from `f`, which it sees strictly) and
    /// their horizon: `(visible face, edge)` pairs whose neighbour it does
    /// not. A face whose plane holds the eye counts as seen: the cone
    /// replaces it too, so a point that became a vertex inside what is
    /// now a flat face of the hull drops out (no degenerate face comes of
    /// it: the eye never lies on a horizon edge's line, whose far face
    /// it would then see).
    fn visible_from(&mut self, f: u32, eye: u32) {
        self.step += 1;
        let step = self.step;
        self.seen[f as usize] = (step, true);
        let mut visible = std::mem::take(&mut self.visible);
        let mut horizon = std::mem::take(&mut self.horizon);
        visible.clear();
        horizon.clear();
        visible.push(f);
        let mut k = 0;
        while k < visible.len() {
            let face = visible[k];
            k += 1;
            for i in 0..3 {
                let nb = self.faces[face as usize].adj[i];
                let (when, seen) = self.seen[nb as usize];
                let sees = if when == step {
                    seen
                } else {
                    let sees = self.weakly_above(nb, self.p[eye as usize]);
                    self.seen[nb as usize] = (step, sees);
                    if sees {
                        visible.push(nb);
                    }
                    sees
                };
                if !sees {
                    horizon.push((face, i));
                }
            }
        }
        self.visible = visible;
        self.horizon = horizon;
    }

    /// New faces from each horizon edge to `eye`, linked to the faces
    /// beyond the horizon and to each other; returns the first new face.
    fn cone(&mut self, eye: u32) -> u32 {
        let first = self.faces.len() as u32;
        let horizon = std::mem::take(&mut self.horizon);
        let mut starts = std::mem::take(&mut self.starts);
        starts.clear();
        for &(face, i) in &horizon {
            let f = &self.faces[face as usize];
            let (u, w, beyond) = (f.v[i], f.v[(i + 1) % 3], f.adj[i]);
            let id = self.push_face([u, w, eye]);
            self.faces[id as usize].adj[0] = beyond;
            let j = self
                .edge_index(beyond as usize, w, u)
                .expect("the face beyond a horizon edge shares it");
            debug_assert!(self.visible.contains(&self.faces[beyond as usize].adj[j]));
            self.faces[beyond as usize].adj[j] = id;
            starts.push((u, id));
        }
        starts.sort_unstable();
        let starting_at = |x: u32| {
            let k = starts.partition_point(|s| s.0 < x);
            debug_assert!(
                k < starts.len() && starts[k].0 == x,
                "the horizon is a cycle"
            );
            starts[k].1
        };
        for id in first..self.faces.len() as u32 {
            // Across this face's edge (w, eye) lies the new face whose edge
            // (eye, u') runs back: the one starting at u' = w.
            let w = self.faces[id as usize].v[1];
            let next = starting_at(w);
            self.faces[id as usize].adj[1] = next;
            self.faces[next as usize].adj[2] = id;
        }
        self.horizon = horizon;
        self.starts = starts;
        first
    }

    /// Gives each of `points` to the first face from `first_new` on that
    /// it lies above (the others are inside the hull now).
    fn assign(&mut self, points: &[Outside], first_new: u32) {
        let mut targets = std::mem::take(&mut self.targets);
        targets.clear();
        let faces = first_new..self.faces.len() as u32;
        let target = |o: &Outside| faces.clone().find(|&f| self.above(f, o.p)).unwrap_or(NONE);
        if points.len() > PARALLEL_POINTS {
            points.par_iter().map(target).collect_into_vec(&mut targets);
        } else {
            targets.extend(points.iter().map(target));
        }
        for (o, &f) in points.iter().zip(&targets) {
            if f != NONE {
                self.faces[f as usize].outside.push(*o);
            }
        }
        self.targets = targets;
    }
}
