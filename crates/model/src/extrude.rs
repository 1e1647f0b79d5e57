//! Extrusion of polygons (Houdini's PolyExtrude, Blender's Extrude Faces
//! and Extrude Individual) and of polylines into surfaces.
//!
//! Faces: the selected polygons move to a front copy of their points and
//! walls join each edge of the selection's outline (every edge of each
//! face when faces extrude individually) to its front copy, in rings when
//! the walls are divided. A front point goes along its direction (the
//! face's normal, or for connected faces the area-weighted mean of the
//! selected faces' normals at the point) by the distance, times a point
//! attribute when one is named; inset moves it in the face's plane by
//! offsetting the outline's edges inward (each corner along its bisector
//! as far as keeps both edges at the inset distance); then twist turns and
//! scale scales it about the centre of its piece (its face, or its
//! connected piece of the selection), about the piece's mean normal. Each
//! ring is the same construction at its fraction of the way. Walls take
//! their face's primitive attributes and the vertex attributes of the
//! edge's corners; front points take their source point's attributes.
//!
//! Polylines: each point is copied along the extrusion direction (its `N`
//! when the curve has one, else the given direction) by the distance, in
//! rings, and consecutive points of consecutive rings are joined by quads.

use geode_geo::glam::{Quat, Vec3};
use geode_geo::{ops, Geometry, Group, PrimKind};

use crate::rebuild::Rebuild;
use crate::ModelError;

/// How to extrude.
#[derive(Clone, Debug)]
pub struct Extrude {
    pub distance: f32,
    pub inset: f32,
    /// Rings of the walls (at least 1).
    pub divisions: u32,
    /// Degrees about the piece's normal at the front.
    pub twist: f32,
    /// Scale of the front about the piece's centre.
    pub front_scale: f32,
    /// Faces sharing edges extrude as one piece (else each on its own).
    pub connected: bool,
    /// Keep the selected faces (reversed) as a back: a grid becomes a slab.
    pub output_back: bool,
    pub output_front: bool,
    /// For polylines without `N`: the direction to extrude along.
    pub direction: Vec3,
}

impl Default for Extrude {
    fn default() -> Extrude {
        Extrude {
            distance: 0.1,
            inset: 0.0,
            divisions: 1,
            twist: 0.0,
            front_scale: 1.0,
            connected: true,
            output_back: false,
            output_front: true,
            direction: Vec3::Y,
        }
    }
}

/// Front, wall and back groups, as Houdini's PolyExtrude names them.
pub const FRONT: &str = "extrudeFront";
pub const SIDE: &str = "extrudeSide";
pub const BACK: &str = "extrudeBack";

/// An extrusion and what went wrong in it short of an error.
#[derive(Debug)]
pub struct Extruded {
    pub geometry: Geometry,
    /// Fronts the inset took past where their edges meet: an outline edge
    /// came out pointing the other way, so the front turned inside out
    /// (Blender's Clamp Overlap would have stopped the inset there).
    pub overrun_fronts: usize,
}

/// Extrudes the polygons and polylines of `g` in `group` (all when
/// `None`); `scale` multiplies each point's distance (a point attribute's
/// values). Other primitives are kept as they are.
pub fn extrude(
    g: &Geometry,
    group: Option<&Group>,
    scale: Option<&[f32]>,
    how: &Extrude,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Extruded, ModelError> {
    if how.divisions == 0 {
        return Err(ModelError::Invalid("divisions must be at least 1".into()));
    }
    let selected = |k: usize| group.is_none_or(|s| s.contains(k));
    let faces: Vec<u32> = (0..g.num_prims() as u32)
        .filter(|&k| selected(k as usize) && g.prim_kind(k as usize) == PrimKind::Polygon)
        .collect();
    let curves: Vec<u32> = (0..g.num_prims() as u32)
        .filter(|&k| selected(k as usize) && g.prim_kind(k as usize) == PrimKind::Polyline)
        .collect();
    let mut out = Rebuild::new();
    for p in 0..g.num_points() as u32 {
        out.point(p, g.positions()[p as usize]);
    }
    let mut is_face = vec![false; g.num_prims()];
    faces.iter().for_each(|&f| is_face[f as usize] = true);
    let mut is_curve = vec![false; g.num_prims()];
    curves.iter().for_each(|&c| is_curve[c as usize] = true);
    // Unselected primitives first, as they were.
    for k in 0..g.num_prims() {
        if !is_face[k] && !is_curve[k] {
            let r = g.prim_vertex_range(k);
            let verts: Vec<u32> = r.map(|v| v as u32).collect();
            out.prim(k as u32, g.prim_kind(k), g.prim_points(k), &verts);
        }
    }
    for name in [FRONT, SIDE, BACK] {
        out.declare(name);
    }
    let mut overrun_fronts = 0;
    if !faces.is_empty() {
        let plan = Faces::new(g, &faces, how, scale);
        if cancel() {
            return Err(ModelError::Cancelled);
        }
        overrun_fronts = plan.build(&mut out, cancel)?;
    }
    for &c in &curves {
        if cancel() {
            return Err(ModelError::Cancelled);
        }
        extrude_curve(g, c, how, scale, &mut out);
    }
    let mut result = out.finish(g, "polyextrude", cancel)?;
    if cancel() {
        return Err(ModelError::Cancelled);
    }
    // The interiors of connected pieces are left without faces.
    let used_before = used_points(g);
    let used_now = used_points(&result);
    let orphan = Group::from_flags(
        (0..result.num_points()).map(|p| p < g.num_points() && used_before[p] && !used_now[p]),
    );
    if orphan.count() > 0 {
        ops::delete_points(&mut result, &orphan);
    }
    Ok(Extruded {
        geometry: result,
        overrun_fronts,
    })
}

fn used_points(g: &Geometry) -> Vec<bool> {
    let mut used = vec![false; g.num_points()];
    g.vertex_points()
        .iter()
        .for_each(|&p| used[p as usize] = true);
    used
}

/// The selected faces and what their extrusion needs. A slot is a point of
/// a piece (connected faces share their points' slots; a face extruded on
/// its own has a slot per corner): each slot moves along its direction,
/// insets by its outline edges, and makes one point per ring.
struct Faces<'a> {
    g: &'a Geometry,
    faces: &'a [u32],
    how: &'a Extrude,
    scale: Option<&'a [f32]>,
    /// First corner of each face in the corner lists.
    first: Vec<u32>,
    /// Per corner: its slot, and whether the edge from it to the next
    /// corner is inside its piece (shared with another selected face).
    slot_of: Vec<u32>,
    inner: Vec<bool>,
    /// Per slot: its source point and piece.
    slots: Vec<(u32, u32)>,
    /// Per piece: centre and unit normal.
    pieces: Vec<(Vec3, Vec3)>,
}

impl<'a> Faces<'a> {
    fn new(
        g: &'a Geometry,
        faces: &'a [u32],
        how: &'a Extrude,
        scale: Option<&'a [f32]>,
    ) -> Faces<'a> {
        let mut first = Vec::with_capacity(faces.len() + 1);
        let mut corners = 0u32;
        for &f in faces {
            first.push(corners);
            corners += g.prim_points(f as usize).len() as u32;
        }
        first.push(corners);
        // Faces on their own share no edge with each other.
        let twins = if how.connected {
            twin_corners(g, faces, &first)
        } else {
            vec![NONE; corners as usize]
        };
        let piece_of = if how.connected {
            connected_pieces(faces.len(), &first, &twins)
        } else {
            (0..faces.len() as u32).collect()
        };
        let inner: Vec<bool> = twins.iter().map(|t| *t != NONE).collect();
        let (slot_of, slots) = slots(g, faces, &first, &piece_of);
        let pieces = piece_frames(g, faces, &piece_of);
        Faces {
            g,
            faces,
            how,
            scale,
            first,
            slot_of,
            inner,
            slots,
            pieces,
        }
    }

    fn corners(&self, i: usize) -> std::ops::Range<usize> {
        self.first[i] as usize..self.first[i + 1] as usize
    }

    /// Per slot: the direction (the unit sum of its faces' area-weighted
    /// normals) and the inset offset: its outline edges' inward normals
    /// m1 and m2 make (m1 + m2) / (1 + m1·m2) · inset, which keeps both
    /// edges at the inset; a corner inside the piece does not move inward.
    fn directions_and_insets(&self) -> (Vec<Vec3>, Vec<Vec3>) {
        let p = self.g.positions();
        let mut dir = vec![Vec3::ZERO; self.slots.len()];
        let mut inward = vec![Vec3::ZERO; self.slots.len()];
        for (i, &f) in self.faces.iter().enumerate() {
            let pts = self.g.prim_points(f as usize);
            let n = ops::polygon_normal(p, pts);
            let unit = n.normalize_or_zero();
            let c0 = self.first[i] as usize;
            for j in 0..pts.len() {
                let c = c0 + j;
                dir[self.slot_of[c] as usize] += n;
                if self.inner[c] || self.how.inset == 0.0 {
                    continue;
                }
                let jn = (j + 1) % pts.len();
                let e = (p[pts[jn] as usize] - p[pts[j] as usize]).normalize_or_zero();
                let m = unit.cross(e);
                inward[self.slot_of[c] as usize] += m;
                inward[self.slot_of[c0 + jn] as usize] += m;
            }
        }
        dir.iter_mut().for_each(|d| *d = d.normalize_or_zero());
        for v in &mut inward {
            let len2 = v.length_squared();
            *v = if len2 > 1e-12 {
                *v * (2.0 / len2) * self.how.inset
            } else {
                Vec3::ZERO
            };
        }
        (dir, inward)
    }

    /// Where slot `s` goes at fraction `t` of the way.
    fn place(&self, s: usize, dir: Vec3, inset: Vec3, t: f32) -> Vec3 {
        let (q, piece) = self.slots[s];
        let p = self.g.positions()[q as usize];
        let k = self.scale.map_or(1.0, |sc| sc[q as usize]);
        let along = dir * (self.how.distance * k * t);
        let (centre, normal) = self.pieces[piece as usize];
        let centre = centre + along;
        let moved = p + along + inset * t;
        let turn = Quat::from_axis_angle(normal, (self.how.twist * t).to_radians());
        let size = 1.0 + (self.how.front_scale - 1.0) * t;
        centre + turn * ((moved - centre) * size)
    }

    /// Faces whose front the inset overran: an outline edge of the front
    /// points against the same edge placed without the inset (twist and
    /// scale turn both alike, so only the inset can reverse it).
    fn overrun(&self, dir: &[Vec3], inset: &[Vec3]) -> usize {
        use rayon::prelude::*;
        if self.how.inset == 0.0 {
            return 0;
        }
        (0..self.faces.len())
            .into_par_iter()
            .filter(|&i| {
                let cs = self.corners(i);
                let n = cs.len();
                cs.clone().any(|c| {
                    let cn = cs.start + (c - cs.start + 1) % n;
                    if self.inner[c] {
                        return false;
                    }
                    let (s, sn) = (self.slot_of[c] as usize, self.slot_of[cn] as usize);
                    let edge = |a: Vec3, b: Vec3| {
                        self.place(sn, dir[sn], b, 1.0) - self.place(s, dir[s], a, 1.0)
                    };
                    edge(inset[s], inset[sn]).dot(edge(Vec3::ZERO, Vec3::ZERO)) < 0.0
                })
            })
            .count()
    }

    /// Adds the fronts, backs and walls; returns how many fronts the inset
    /// overran.
    fn build(
        &self,
        out: &mut Rebuild,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<usize, ModelError> {
        use rayon::prelude::*;
        let g = self.g;
        let rings = self.how.divisions as usize;
        let (dir, inset) = self.directions_and_insets();
        // Ring r (1..=rings) of slot s is point base + s * rings + r - 1.
        let base = out.num_points() as u32;
        // Every item asks (an atomic load), and the first None ends the
        // collect: a cancel stops the whole parallel map at once.
        let placed: Vec<Vec3> = (0..self.slots.len() * rings)
            .into_par_iter()
            .map(|k| {
                if cancel() {
                    return None;
                }
                let (s, r) = (k / rings, k % rings + 1);
                Some(self.place(s, dir[s], inset[s], r as f32 / rings as f32))
            })
            .collect::<Option<_>>()
            .ok_or(ModelError::Cancelled)?;
        for (k, at) in placed.into_iter().enumerate() {
            if k % POLL_EVERY == 0 && cancel() {
                return Err(ModelError::Cancelled);
            }
            out.point(self.slots[k / rings].0, at);
        }
        let ring = |c: usize, r: usize, q: u32| {
            if r == 0 {
                q
            } else {
                base + (self.slot_of[c] as usize * rings + r - 1) as u32
            }
        };
        // Poll about as often in new primitives however many rings a face
        // makes.
        let faces_per_poll = (POLL_EVERY / (4 * (rings + 1))).max(1);
        for (i, &f) in self.faces.iter().enumerate() {
            if i % faces_per_poll == 0 && cancel() {
                return Err(ModelError::Cancelled);
            }
            let f = f as usize;
            let pts = g.prim_points(f);
            let verts: Vec<u32> = g.prim_vertex_range(f).map(|v| v as u32).collect();
            let cs = self.corners(i);
            if self.how.output_front {
                let front: Vec<u32> = cs
                    .clone()
                    .zip(pts)
                    .map(|(c, &q)| ring(c, rings, q))
                    .collect();
                let k = out.prim(f as u32, PrimKind::Polygon, &front, &verts);
                out.mark(FRONT, k);
            }
            if self.how.output_back {
                let back: Vec<u32> = pts.iter().rev().copied().collect();
                let back_verts: Vec<u32> = verts.iter().rev().copied().collect();
                let k = out.prim(f as u32, PrimKind::Polygon, &back, &back_verts);
                out.mark(BACK, k);
            }
            for j in 0..pts.len() {
                let (c, jn) = (cs.start + j, (j + 1) % pts.len());
                if self.inner[c] {
                    continue;
                }
                let cn = cs.start + jn;
                for r in 0..rings {
                    let quad = [
                        ring(c, r, pts[j]),
                        ring(cn, r, pts[jn]),
                        ring(cn, r + 1, pts[jn]),
                        ring(c, r + 1, pts[j]),
                    ];
                    let qv = [verts[j], verts[jn], verts[jn], verts[j]];
                    let k = out.prim(f as u32, PrimKind::Polygon, &quad, &qv);
                    out.mark(SIDE, k);
                }
            }
        }
        Ok(self.overrun(&dir, &inset))
    }
}

/// Per corner of the selected faces, the corner of another selected face
/// whose edge runs the other way along this corner's edge (`NONE` where
/// the edge is the selection's outline, or shared by more than two).
/// Half-edges are sorted by their points, in parallel and totally, so the
/// pairing does not depend on threads.
fn twin_corners(g: &Geometry, faces: &[u32], first: &[u32]) -> Vec<u32> {
    use rayon::prelude::*;
    let mut half: Vec<(u32, u32, u32)> = faces
        .par_iter()
        .enumerate()
        .flat_map_iter(|(i, &f)| {
            let pts = g.prim_points(f as usize);
            let c0 = first[i];
            (0..pts.len()).map(move |j| {
                let (a, b) = (pts[j], pts[(j + 1) % pts.len()]);
                (a.min(b), a.max(b), c0 + j as u32)
            })
        })
        .collect();
    half.par_sort_unstable();
    let mut twin = vec![NONE; half.len()];
    let mut k = 0;
    while k < half.len() {
        let mut e = k + 1;
        while e < half.len() && (half[e].0, half[e].1) == (half[k].0, half[k].1) {
            e += 1;
        }
        if e - k == 2 {
            let (x, y) = (half[k].2, half[k + 1].2);
            twin[x as usize] = y;
            twin[y as usize] = x;
        }
        k = e;
    }
    twin
}

const NONE: u32 = u32::MAX;

/// Points or primitives made between two polls of the cancel.
const POLL_EVERY: usize = 1 << 16;

/// Faces joined through twin corners, numbered in order of their first
/// face.
fn connected_pieces(faces: usize, first: &[u32], twins: &[u32]) -> Vec<u32> {
    let mut face_of = vec![0u32; twins.len()];
    for i in 0..faces {
        face_of[first[i] as usize..first[i + 1] as usize].fill(i as u32);
    }
    let mut parent: Vec<u32> = (0..faces as u32).collect();
    fn root(p: &mut [u32], mut x: u32) -> u32 {
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }
    for (c, &t) in twins.iter().enumerate() {
        if t != NONE {
            let (x, y) = (
                root(&mut parent, face_of[c]),
                root(&mut parent, face_of[t as usize]),
            );
            parent[x.max(y) as usize] = x.min(y);
        }
    }
    let mut number = vec![NONE; faces];
    let mut next = 0;
    (0..faces as u32)
        .map(|i| {
            let r = root(&mut parent, i) as usize;
            if number[r] == NONE {
                number[r] = next;
                next += 1;
            }
            number[r]
        })
        .collect()
}

/// Each corner's slot (one per point of a piece, numbered in order of
/// first use) and each slot's (point, piece).
fn slots(
    g: &Geometry,
    faces: &[u32],
    first: &[u32],
    piece_of: &[u32],
) -> (Vec<u32>, Vec<(u32, u32)>) {
    let corners = *first.last().unwrap_or(&0) as usize;
    let mut slot_of = vec![NONE; corners];
    let mut slots = Vec::new();
    // A point is in one piece but where pieces touch at it: its first
    // piece's slot is kept per point, others go through a map.
    let mut first_slot = vec![NONE; g.num_points()];
    let mut others: std::collections::BTreeMap<(u32, u32), u32> = Default::default();
    for (i, &f) in faces.iter().enumerate() {
        let piece = piece_of[i];
        for (j, &q) in g.prim_points(f as usize).iter().enumerate() {
            let fs = first_slot[q as usize];
            let s = if fs != NONE && slots[fs as usize] == (q, piece) {
                fs
            } else if let Some(&s) = others.get(&(q, piece)) {
                s
            } else {
                let s = slots.len() as u32;
                slots.push((q, piece));
                if fs == NONE {
                    first_slot[q as usize] = s;
                } else {
                    others.insert((q, piece), s);
                }
                s
            };
            slot_of[first[i] as usize + j] = s;
        }
    }
    (slot_of, slots)
}

/// Each piece's centre (mean of its faces' corners) and unit normal (its
/// faces' area-weighted normals summed).
fn piece_frames(g: &Geometry, faces: &[u32], piece_of: &[u32]) -> Vec<(Vec3, Vec3)> {
    let p = g.positions();
    let count = piece_of.iter().map(|&k| k as usize + 1).max().unwrap_or(0);
    let mut sums = vec![(Vec3::ZERO, 0usize, Vec3::ZERO); count];
    for (i, &f) in faces.iter().enumerate() {
        let pts = g.prim_points(f as usize);
        let s = &mut sums[piece_of[i] as usize];
        for &q in pts {
            s.0 += p[q as usize];
            s.1 += 1;
        }
        s.2 += ops::polygon_normal(p, pts);
    }
    sums.into_iter()
        .map(|(c, n, m)| (c / n.max(1) as f32, m.normalize_or_zero()))
        .collect()
}

/// A polyline's points copied along the direction in rings, consecutive
/// points joined by quads (wrapping when the curve is closed, that is its
/// first point is its last).
fn extrude_curve(g: &Geometry, c: u32, how: &Extrude, scale: Option<&[f32]>, out: &mut Rebuild) {
    let pts = g.prim_points(c as usize);
    let verts: Vec<u32> = g.prim_vertex_range(c as usize).map(|v| v as u32).collect();
    let normal = g
        .attrib(geode_geo::AttribClass::Point, "N")
        .and_then(|a| a.as_vec3());
    let rings = how.divisions as usize;
    let ring: Vec<Vec<u32>> = pts
        .iter()
        .map(|&q| {
            let p = g.positions()[q as usize];
            let dir = normal
                .map_or(how.direction, |n| n[q as usize])
                .normalize_or_zero();
            let s = scale.map_or(1.0, |s| s[q as usize]);
            (0..=rings)
                .map(|r| {
                    if r == 0 {
                        q
                    } else {
                        out.point(q, p + dir * (how.distance * s * r as f32 / rings as f32))
                    }
                })
                .collect()
        })
        .collect();
    for j in 0..pts.len().saturating_sub(1) {
        for r in 0..rings {
            let quad = [
                ring[j][r],
                ring[j + 1][r],
                ring[j + 1][r + 1],
                ring[j][r + 1],
            ];
            let qv = [verts[j], verts[j + 1], verts[j + 1], verts[j]];
            let k = out.prim(c, PrimKind::Polygon, &quad, &qv);
            out.mark(SIDE, k);
        }
    }
    if how.output_front {
        let front: Vec<u32> = ring.iter().map(|r| r[rings]).collect();
        let k = out.prim(c, PrimKind::Polyline, &front, &verts);
        out.mark(FRONT, k);
    }
}
