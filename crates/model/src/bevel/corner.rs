//! One bevelled point: where its new points go and how its faces, the
//! profiles of its bevelled edges and the patch over it join them.
//!
//! Around point v the faces are a fan; a spoke is an edge of v, spoke i
//! the edge face i comes in along (face i leaves along spoke i + 1). Each
//! face's corner at v becomes a short chain of new points:
//! - edges mode: a spoke not bevelled gets one point slid along it,
//!   shared by the faces on either side; a corner between two bevelled
//!   spokes gets the point in its face at the offset from both edges; a
//!   corner between a bevelled spoke and one not bevelled ends on the
//!   slid point (slid as far as keeps it at the offset from the bevelled
//!   edge, the mean of what the faces on either side ask); a corner
//!   between two spokes not bevelled is cut straight between their slid
//!   points.
//! - points mode: every spoke gets a point at the offset along it; each
//!   corner is cut between its two, along an arc in the face when there
//!   are several segments.
//!
//! Each bevelled spoke gets a profile from its side point in the face
//! before to the one in the face after. Going round the fan, chains and
//! profiles close a loop; where it is more than an edge, a patch fills it
//! (a triangular grid where three profiles or arcs meet, one polygon
//! otherwise). Where exactly two bevelled edges meet with nothing else in
//! the loop, their profiles are averaged into one (Blender's weld) and no
//! patch is needed. On the boundary the loop stays open and becomes the
//! new boundary.

use geode_geo::glam::Vec3;
use geode_geo::Geometry;

use super::mesh::{HalfEdges, NONE};
use super::patch::{centre, profile, tri_faces, tri_inside};
use crate::carry::Blend;

/// What one point needs to know of the mesh.
pub(super) struct Mesh<'a> {
    pub g: &'a Geometry,
    pub he: &'a HalfEdges,
    /// Per half-edge: its edge is bevelled (both twins alike).
    pub bevelled: &'a [bool],
    /// Per face: its unit normal.
    pub normals: &'a [Vec3],
    pub points_mode: bool,
}

struct Spoke {
    dir: Vec3,
    len: f32,
    far: u32,
    bevelled: bool,
    /// The half-edge leaving v along this spoke (`NONE` for a boundary
    /// spoke entering the fan's first face).
    out: u32,
}

#[derive(Clone, Copy)]
enum Kind {
    /// Slid along spoke `s` by `factor` times the offset.
    Slide { s: usize, factor: f32 },
    /// In a face: v + offset × `dir`.
    Meet { dir: Vec3 },
}

/// A point's faces and new points for an offset of 1 (everything a point
/// makes moves in proportion to the offset).
pub(super) struct Layout {
    pub v: u32,
    fan: Vec<u32>,
    closed: bool,
    spokes: Vec<Spoke>,
    kinds: Vec<Kind>,
    face_in: Vec<u32>,
    face_out: Vec<u32>,
}

/// How a chain's vertex takes its attributes from its face's corner.
#[derive(Clone, Copy)]
pub(super) enum VSrc {
    Copy,
    /// Blended toward the previous corner (along the incoming edge).
    Prev(f32),
    /// Blended toward the next corner.
    Next(f32),
}

/// What one point makes, numbered locally from 0.
pub(super) struct Corner {
    pub fan: Vec<u32>,
    pub points: Vec<(Vec3, Blend)>,
    /// Per fan face: the chain replacing its corner at v.
    pub chains: Vec<Vec<(u32, VSrc)>>,
    /// Per bevelled spoke: the half-edge leaving v along it, and its
    /// profile from the side of that half-edge's face to the other.
    pub profiles: Vec<(u32, Vec<u32>)>,
    /// Patch polygons: (local point, source vertex) each, and the source
    /// primitive.
    pub patches: Vec<(u32, Vec<(u32, u32)>)>,
}

impl Layout {
    pub fn new(m: &Mesh, v: u32, fan: Vec<u32>, closed: bool) -> Layout {
        let (g, he) = (m.g, m.he);
        let pv = g.positions()[v as usize];
        let faces = fan.len();
        let n_spokes = if closed { faces } else { faces + 1 };
        let spoke = |far: u32, out: u32| {
            let d = g.positions()[far as usize] - pv;
            Spoke {
                dir: d.normalize_or_zero(),
                len: d.length(),
                far,
                bevelled: out != NONE && m.bevelled[out as usize],
                out,
            }
        };
        let mut spokes: Vec<Spoke> = (0..faces)
            .map(|i| {
                let far = he.origin(g, he.prev(g, fan[i]));
                let out = if closed {
                    fan[(i + faces - 1) % faces]
                } else if i == 0 {
                    NONE
                } else {
                    fan[i - 1]
                };
                spoke(far, out)
            })
            .collect();
        if !closed {
            spokes.push(spoke(he.dest(g, fan[faces - 1]), fan[faces - 1]));
        }
        let out_of = |i: usize| (i + 1) % n_spokes;
        // Signed sine of each face's corner angle (positive when convex).
        let sines: Vec<f32> = (0..faces)
            .map(|i| {
                let f = he.face[fan[i] as usize] as usize;
                let (a, b) = (spokes[i].dir, spokes[out_of(i)].dir);
                m.normals[f].dot(b.cross(a))
            })
            .collect();
        let mut kinds = Vec::new();
        let mut slid = vec![NONE; n_spokes];
        for s in 0..n_spokes {
            if spokes[s].bevelled {
                continue;
            }
            let factor = if m.points_mode {
                1.0
            } else {
                slide_factor(&spokes, &sines, s, faces, closed)
            };
            slid[s] = kinds.len() as u32;
            kinds.push(Kind::Slide { s, factor });
        }
        let (mut face_in, mut face_out) = (vec![NONE; faces], vec![NONE; faces]);
        for i in 0..faces {
            let (a, b) = (i, out_of(i));
            let (ba, bb) = (spokes[a].bevelled, spokes[b].bevelled);
            let meet = if ba && bb {
                let f = he.face[fan[i] as usize] as usize;
                kinds.push(Kind::Meet {
                    dir: meet_dir(spokes[a].dir, spokes[b].dir, sines[i], m.normals[f]),
                });
                kinds.len() as u32 - 1
            } else {
                NONE
            };
            face_in[i] = match (ba, bb) {
                (true, true) => meet,
                (true, false) => slid[b],
                _ => slid[a],
            };
            face_out[i] = match (ba, bb) {
                (true, true) => meet,
                (false, true) => slid[a],
                _ => slid[b],
            };
        }
        Layout {
            v,
            fan,
            closed,
            spokes,
            kinds,
            face_in,
            face_out,
        }
    }

    fn offset(&self, k: u32) -> Vec3 {
        match self.kinds[k as usize] {
            Kind::Slide { s, factor } => self.spokes[s].dir * factor,
            Kind::Meet { dir } => dir,
        }
    }

    /// Per spoke: (far point, how far along it this point's new points
    /// reach at offset 1, its length). An edge's two ends together may
    /// reach no further than its length: that bounds the offset.
    pub fn reaches(&self) -> impl Iterator<Item = (u32, f32, f32)> + '_ {
        let faces = self.fan.len();
        self.spokes.iter().enumerate().map(move |(s, sp)| {
            let reach = match sp.bevelled {
                false => self.offset(self.slid_of(s)).dot(sp.dir),
                true => {
                    let before = self.face_out[(s + faces - 1) % faces];
                    let after = self.face_in[s % faces];
                    self.offset(before)
                        .dot(sp.dir)
                        .max(self.offset(after).dot(sp.dir))
                }
            };
            (sp.far, reach.max(0.0), sp.len)
        })
    }

    fn slid_of(&self, s: usize) -> u32 {
        self.kinds
            .iter()
            .position(|k| matches!(k, Kind::Slide { s: t, .. } if *t == s))
            .expect("every spoke not bevelled slides") as u32
    }

    /// The new points and faces at offset `d` with `n` segments of
    /// profile exponent `e`.
    pub fn build(&self, m: &Mesh, d: f32, n: u32, e: f32) -> Corner {
        let g = m.g;
        let pv = g.positions()[self.v as usize];
        let faces = self.fan.len();
        let mut points: Vec<(Vec3, Blend)> = self
            .kinds
            .iter()
            .enumerate()
            .map(|(k, kind)| {
                let at = pv + self.offset(k as u32) * d;
                let src = match *kind {
                    Kind::Slide { s, factor } => {
                        let sp = &self.spokes[s];
                        (self.v, sp.far, (factor * d / sp.len).min(1.0))
                    }
                    Kind::Meet { .. } => (self.v, self.v, 0.0),
                };
                (at, src)
            })
            .collect();
        let vsrc = |k: u32, i: usize| match self.kinds[k as usize] {
            Kind::Slide { s, factor } => {
                let t = (factor * d / self.spokes[s].len).min(1.0);
                if s == i {
                    VSrc::Prev(t)
                } else {
                    VSrc::Next(t)
                }
            }
            Kind::Meet { .. } => VSrc::Copy,
        };
        let add = |points: &mut Vec<(Vec3, Blend)>, at: Vec3| {
            points.push((at, (self.v, self.v, 0.0)));
            points.len() as u32 - 1
        };
        let mut chains = Vec::with_capacity(faces);
        let mut profiles = Vec::new();
        // Per face: the points after its chain on the loop round v (the
        // profile of its outgoing spoke, or its arc), and the centres of
        // those curves.
        let mut between: Vec<Vec<u32>> = vec![Vec::new(); faces];
        let mut centres = Vec::new();
        if m.points_mode {
            for i in 0..faces {
                let (a, b) = (self.face_in[i], self.face_out[i]);
                let (l, r) = (points[a as usize].0, points[b as usize].0);
                let arc: Vec<u32> = profile(l, r, pv, e, n)
                    .into_iter()
                    .map(|p| add(&mut points, p))
                    .collect();
                centres.push(centre(l, r, pv));
                let mut chain = vec![(a, vsrc(a, i))];
                chain.extend(arc.iter().map(|&k| (k, VSrc::Copy)));
                chain.push((b, vsrc(b, i)));
                chains.push(chain);
            }
        } else {
            for i in 0..faces {
                let (a, b) = (self.face_in[i], self.face_out[i]);
                let mut chain = vec![(a, vsrc(a, i))];
                if b != a {
                    chain.push((b, vsrc(b, i)));
                }
                chains.push(chain);
            }
            let bevelled: Vec<usize> = (0..self.spokes.len())
                .filter(|&s| self.spokes[s].bevelled)
                .collect();
            let welded = self.weld(&bevelled, n);
            for &s in &bevelled {
                let (before, after) = ((s + faces - 1) % faces, s % faces);
                let (l, r) = (self.face_out[before], self.face_in[after]);
                let (pl, pr) = (points[l as usize].0, points[r as usize].0);
                let sp = &self.spokes[s];
                let c = pv + sp.dir * ((pl + pr) * 0.5 - pv).dot(sp.dir);
                centres.push(centre(pl, pr, c));
                let mut inside = profile(pl, pr, c, e, n);
                if let Some((first, second)) = welded {
                    if s == second {
                        // The second of a weld takes the first's points.
                        let ids = first_reversed(&profiles[0]);
                        profiles.push((sp.out, ids));
                        continue;
                    }
                    debug_assert_eq!(s, first);
                    let osp = &self.spokes[second];
                    let oc = pv + osp.dir * ((pl + pr) * 0.5 - pv).dot(osp.dir);
                    let mirror = profile(pr, pl, oc, e, n);
                    for (j, p) in inside.iter_mut().enumerate() {
                        *p = (*p + mirror[mirror.len() - 1 - j]) * 0.5;
                    }
                }
                let mut ids = vec![l];
                ids.extend(inside.into_iter().map(|p| add(&mut points, p)));
                ids.push(r);
                between[before] = ids[1..ids.len() - 1].to_vec();
                profiles.push((sp.out, ids));
            }
            if welded.is_some() {
                return Corner {
                    fan: self.fan.clone(),
                    points,
                    chains,
                    profiles,
                    patches: Vec::new(),
                };
            }
        }
        let patches = if self.closed {
            self.patch(m, &chains, &between, &centres, &mut points, n)
        } else {
            Vec::new()
        };
        Corner {
            fan: self.fan.clone(),
            points,
            chains,
            profiles,
            patches,
        }
    }

    /// Whether two bevelled spokes alone meet here (the loop round v is
    /// their two profiles and one point on each side): the two, in order.
    fn weld(&self, bevelled: &[usize], n: u32) -> Option<(usize, usize)> {
        if !self.closed || bevelled.len() != 2 || n < 2 {
            return None;
        }
        let faces = self.fan.len();
        let (k1, k2) = (bevelled[0], bevelled[1]);
        let one_point = |from: usize, to: usize| {
            let first = self.face_in[from % faces];
            let mut i = from;
            while i != to {
                let f = i % faces;
                if self.face_in[f] != first || self.face_out[f] != first {
                    return false;
                }
                i = (i + 1) % faces;
            }
            true
        };
        (one_point(k1, k2) && one_point(k2, k1)).then_some((k1, k2))
    }

    /// The patch over a closed fan's loop: faces in the loop's order
    /// reversed (the faces round v run the other way along it).
    fn patch(
        &self,
        m: &Mesh,
        chains: &[Vec<(u32, VSrc)>],
        between: &[Vec<u32>],
        centres: &[Vec3],
        points: &mut Vec<(Vec3, Blend)>,
        n: u32,
    ) -> Vec<(u32, Vec<(u32, u32)>)> {
        let mut cycle: Vec<(u32, u32)> = Vec::new();
        for (i, chain) in chains.iter().enumerate() {
            let h = self.fan[i];
            let mut push = |k: u32| {
                if cycle.last().is_none_or(|&(last, _)| last != k) {
                    cycle.push((k, h));
                }
            };
            chain.iter().for_each(|&(k, _)| push(k));
            between[i].iter().for_each(|&k| push(k));
        }
        while cycle.len() > 1 && cycle[0].0 == cycle[cycle.len() - 1].0 {
            cycle.pop();
        }
        if cycle.len() < 3 {
            return Vec::new();
        }
        let src = m.he.face[self.fan[0] as usize];
        let n = n as usize;
        let three =
            self.fan.len() == 3 && (m.points_mode || self.spokes.iter().all(|s| s.bevelled));
        if !(three && n >= 2 && cycle.len() == 3 * n) {
            cycle.reverse();
            return vec![(src, cycle)];
        }
        // Forward sides F_j from corner j n to (j + 1) n; the patch runs
        // them backwards, so its sides are F_2, F_1, F_0 reversed.
        let side = |j: usize| -> Vec<u32> {
            let mut s: Vec<u32> = (0..=n).map(|k| cycle[(j * n + k) % (3 * n)].0).collect();
            s.reverse();
            s
        };
        let sides = [side(2), side(1), side(0)];
        let at = |s: &[u32]| -> Vec<Vec3> { s.iter().map(|&k| points[k as usize].0).collect() };
        let pos = [at(&sides[0]), at(&sides[1]), at(&sides[2])];
        let c = centres.iter().copied().sum::<Vec3>() / centres.len().max(1) as f32;
        let inside_at = tri_inside([&pos[0], &pos[1], &pos[2]], n, Some(c));
        let inside: Vec<u32> = inside_at
            .into_iter()
            .map(|p| {
                points.push((p, (self.v, self.v, 0.0)));
                points.len() as u32 - 1
            })
            .collect();
        let src_of = |k: u32| {
            cycle
                .iter()
                .find(|&&(c, _)| c == k)
                .map_or(self.fan[0], |&(_, h)| h)
        };
        tri_faces([&sides[0], &sides[1], &sides[2]], &inside, n)
            .into_iter()
            .map(|t| (src, t.iter().map(|&k| (k, src_of(k))).collect()))
            .collect()
    }
}

fn first_reversed(first: &(u32, Vec<u32>)) -> Vec<u32> {
    first.1.iter().rev().copied().collect()
}

/// How far (times the offset) spoke `s`, not bevelled, slides: far enough
/// to be the offset from the bevelled edge of each face beside it that
/// has one (the mean of the two when both do), else the offset itself.
fn slide_factor(spokes: &[Spoke], sines: &[f32], s: usize, faces: usize, closed: bool) -> f32 {
    let n_spokes = spokes.len();
    let mut sum = 0.0;
    let mut count = 0;
    // Face s comes in along s and leaves along s + 1.
    if s < faces && spokes[(s + 1) % n_spokes].bevelled {
        sum += 1.0 / sines[s].abs().max(0.05);
        count += 1;
    }
    // Face s - 1 leaves along s.
    let before = if closed {
        Some((s + faces - 1) % faces)
    } else {
        s.checked_sub(1)
    };
    if let Some(f) = before {
        if spokes[f].bevelled {
            sum += 1.0 / sines[f].abs().max(0.05);
            count += 1;
        }
    }
    if count == 0 {
        1.0
    } else {
        sum / count as f32
    }
}

/// The point in a face at distance 1 from both its edges at a corner
/// (unit directions `a` in, `b` out from the corner, signed sine `sin`),
/// or, where the edges are nearly in line, 1 straight into the face.
fn meet_dir(a: Vec3, b: Vec3, sin: f32, normal: Vec3) -> Vec3 {
    if sin.abs() < 0.05 && a.dot(b) < 0.0 {
        return normal.cross(-a).normalize_or_zero();
    }
    let sin = if sin.abs() < 0.05 {
        0.05f32.copysign(sin)
    } else {
        sin
    };
    (a + b) / sin
}
