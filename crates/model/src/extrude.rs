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

/// Extrudes the polygons and polylines of `g` in `group` (all when
/// `None`); `scale` multiplies each point's distance (a point attribute's
/// values). Other primitives are kept as they are.
pub fn extrude(
    g: &Geometry,
    group: Option<&Group>,
    scale: Option<&[f32]>,
    how: &Extrude,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, ModelError> {
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
    if !faces.is_empty() {
        Faces::new(g, &faces, &is_face, how, scale).build(&mut out, cancel)?;
    }
    for &c in &curves {
        if cancel() {
            return Err(ModelError::Cancelled);
        }
        extrude_curve(g, c, how, scale, &mut out);
    }
    let mut result = out.finish(g).map_err(|e| ModelError::Failed {
        op: "extrude",
        why: e.to_string(),
    })?;
    // The interiors of connected pieces are left without faces.
    let used_before = used_points(g);
    let used_now = used_points(&result);
    let orphan = Group::from_flags(
        (0..result.num_points()).map(|p| p < g.num_points() && used_before[p] && !used_now[p]),
    );
    if orphan.count() > 0 {
        ops::delete_points(&mut result, &orphan);
    }
    Ok(result)
}

fn used_points(g: &Geometry) -> Vec<bool> {
    let mut used = vec![false; g.num_points()];
    g.vertex_points()
        .iter()
        .for_each(|&p| used[p as usize] = true);
    used
}

/// The selected faces and what their extrusion needs: for each face
/// corner, the front point it moves to, and each piece's centre and normal.
struct Faces<'a> {
    g: &'a Geometry,
    faces: &'a [u32],
    is_face: &'a [bool],
    how: &'a Extrude,
    scale: Option<&'a [f32]>,
    /// Face normals (Newell, unit) by face index in `faces`.
    normals: Vec<Vec3>,
    /// Each face's piece (itself when individual).
    piece_of: Vec<u32>,
    /// Per piece: centre and unit normal.
    pieces: Vec<(Vec3, Vec3)>,
}

impl<'a> Faces<'a> {
    fn new(
        g: &'a Geometry,
        faces: &'a [u32],
        is_face: &'a [bool],
        how: &'a Extrude,
        scale: Option<&'a [f32]>,
    ) -> Faces<'a> {
        let p = g.positions();
        let normals: Vec<Vec3> = faces
            .iter()
            .map(|&f| ops::polygon_normal(p, g.prim_points(f as usize)).normalize_or_zero())
            .collect();
        let piece_of = if how.connected {
            connected_pieces(g, faces)
        } else {
            (0..faces.len() as u32).collect()
        };
        let count = piece_of.iter().map(|&k| k as usize + 1).max().unwrap_or(0);
        let mut sums = vec![(Vec3::ZERO, 0usize, Vec3::ZERO); count];
        for (i, &f) in faces.iter().enumerate() {
            let s = &mut sums[piece_of[i] as usize];
            for &q in g.prim_points(f as usize) {
                s.0 += p[q as usize];
                s.1 += 1;
            }
            s.2 += ops::polygon_normal(p, g.prim_points(f as usize));
        }
        let pieces = sums
            .into_iter()
            .map(|(c, n, m)| (c / n.max(1) as f32, m.normalize_or_zero()))
            .collect();
        Faces {
            g,
            faces,
            is_face,
            how,
            scale,
            normals,
            piece_of,
            pieces,
        }
    }

    /// Where corner `j` of face `i` goes at fraction `t` of the way.
    fn place(&self, i: usize, j: usize, dir: Vec3, inset: Vec3, t: f32) -> Vec3 {
        let f = self.faces[i] as usize;
        let pts = self.g.prim_points(f);
        let p = self.g.positions()[pts[j] as usize];
        let s = self.scale.map_or(1.0, |s| s[pts[j] as usize]);
        let moved = p + dir * (self.how.distance * s * t) + inset * t;
        let (centre, normal) = self.pieces[self.piece_of[i] as usize];
        let centre = centre + dir * (self.how.distance * s * t);
        let turn = Quat::from_axis_angle(normal, (self.how.twist * t).to_radians());
        let size = 1.0 + (self.how.front_scale - 1.0) * t;
        centre + turn * ((moved - centre) * size)
    }

    fn build(
        &self,
        out: &mut Rebuild,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<(), ModelError> {
        let g = self.g;
        let rings = self.how.divisions as usize;
        let dirs = self.directions();
        let insets = self.insets();
        // Ring points per (face corner): shared by connected faces through
        // the source point (ring r of point q is one point per piece).
        let mut ring_point: std::collections::HashMap<(u32, u32, usize), u32> = Default::default();
        let mut rings_of = |i: usize, j: usize, out: &mut Rebuild| -> Vec<u32> {
            let f = self.faces[i] as usize;
            let q = g.prim_points(f)[j];
            let key_piece = if self.how.connected {
                self.piece_of[i]
            } else {
                i as u32
            };
            (0..=rings)
                .map(|r| {
                    if r == 0 {
                        return q;
                    }
                    let key = (key_piece, q, r);
                    if let Some(&p) = ring_point.get(&key) {
                        return p;
                    }
                    let (d, n) = if self.how.connected {
                        let inset = insets.get(&(key_piece, q)).copied().unwrap_or(Vec3::ZERO);
                        (dirs[&q], inset)
                    } else {
                        let n = self.normals[i];
                        (n, corner_inset(g, f, j, n, self.how.inset))
                    };
                    let at = self.place(i, j, d, n, r as f32 / rings as f32);
                    let p = out.point(q, at);
                    ring_point.insert(key, p);
                    p
                })
                .collect()
        };
        for (i, &f) in self.faces.iter().enumerate() {
            if i % 4096 == 0 && cancel() {
                return Err(ModelError::Cancelled);
            }
            let f = f as usize;
            let pts = g.prim_points(f);
            let verts: Vec<u32> = g.prim_vertex_range(f).map(|v| v as u32).collect();
            let corner: Vec<Vec<u32>> = (0..pts.len()).map(|j| rings_of(i, j, out)).collect();
            if self.how.output_front {
                let front: Vec<u32> = corner.iter().map(|c| c[rings]).collect();
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
                let jn = (j + 1) % pts.len();
                if self.how.connected && self.shared_with_selection(pts[j], pts[jn], f) {
                    continue;
                }
                for r in 0..rings {
                    let quad = [
                        corner[j][r],
                        corner[jn][r],
                        corner[jn][r + 1],
                        corner[j][r + 1],
                    ];
                    let qv = [verts[j], verts[jn], verts[jn], verts[j]];
                    let k = out.prim(f as u32, PrimKind::Polygon, &quad, &qv);
                    out.mark(SIDE, k);
                }
            }
        }
        Ok(())
    }

    /// Whether the edge a→b of face `f` is shared with another selected
    /// face (so it is inside a connected piece: no wall).
    fn shared_with_selection(&self, a: u32, b: u32, f: usize) -> bool {
        let topo = self.g.topology();
        topo.point_prims(a as usize).iter().any(|&o| {
            let o = o as usize;
            o != f && self.is_face[o] && {
                let q = self.g.prim_points(o);
                (0..q.len()).any(|k| q[k] == b && q[(k + 1) % q.len()] == a)
            }
        })
    }

    /// Connected mode: each point's direction, the area-weighted mean of
    /// its selected faces' normals.
    fn directions(&self) -> std::collections::HashMap<u32, Vec3> {
        let p = self.g.positions();
        let mut sum: std::collections::HashMap<u32, Vec3> = Default::default();
        if !self.how.connected {
            return sum;
        }
        for &f in self.faces {
            let pts = self.g.prim_points(f as usize);
            let n = ops::polygon_normal(p, pts);
            for &q in pts {
                *sum.entry(q).or_default() += n;
            }
        }
        sum.values_mut().for_each(|n| *n = n.normalize_or_zero());
        sum
    }

    /// Connected mode: the in-plane offset of each outline point of each
    /// piece (interior points do not move inward).
    fn insets(&self) -> std::collections::HashMap<(u32, u32), Vec3> {
        let mut at: std::collections::HashMap<(u32, u32), Vec3> = Default::default();
        if !self.how.connected || self.how.inset == 0.0 {
            return at;
        }
        let p = self.g.positions();
        for (i, &f) in self.faces.iter().enumerate() {
            let pts = self.g.prim_points(f as usize);
            let n = pts.len();
            for j in 0..n {
                let (a, b) = (pts[j], pts[(j + 1) % n]);
                if self.shared_with_selection(a, b, f as usize) {
                    continue;
                }
                // The outline edge a→b pushes both its ends inward.
                let e = (p[b as usize] - p[a as usize]).normalize_or_zero();
                let inward = self.normals[i].cross(e);
                for q in [a, b] {
                    let slot = at.entry((self.piece_of[i], q)).or_insert(Vec3::ZERO);
                    *slot += inward;
                }
            }
        }
        // Two edges' inward normals m1 + m2 become the corner's offset
        // (m1 + m2) / (1 + m1·m2) · inset, which keeps both at the inset.
        for v in at.values_mut() {
            let len2 = v.length_squared();
            *v = if len2 > 1e-12 {
                *v * (2.0 / len2) * self.how.inset
            } else {
                Vec3::ZERO
            };
        }
        at
    }
}

/// The in-plane offset of corner `j` of face `f` (normal `n`) that keeps
/// both its edges `inset` inward.
fn corner_inset(g: &Geometry, f: usize, j: usize, n: Vec3, inset: f32) -> Vec3 {
    if inset == 0.0 {
        return Vec3::ZERO;
    }
    let p = g.positions();
    let pts = g.prim_points(f);
    let k = pts.len();
    let (a, c, b) = (
        p[pts[(j + k - 1) % k] as usize],
        p[pts[j] as usize],
        p[pts[(j + 1) % k] as usize],
    );
    let m1 = n.cross((c - a).normalize_or_zero());
    let m2 = n.cross((b - c).normalize_or_zero());
    let m = m1 + m2;
    let len2 = m.length_squared();
    if len2 < 1e-12 {
        return Vec3::ZERO;
    }
    m * (2.0 / len2) * inset
}

/// Faces of the selection joined through shared edges, numbered in order
/// of their first face.
fn connected_pieces(g: &Geometry, faces: &[u32]) -> Vec<u32> {
    let mut parent: Vec<usize> = (0..faces.len()).collect();
    fn root(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    let mut edges: std::collections::HashMap<(u32, u32), usize> = Default::default();
    for (i, &f) in faces.iter().enumerate() {
        let q = g.prim_points(f as usize);
        for k in 0..q.len() {
            let (a, b) = (q[k], q[(k + 1) % q.len()]);
            if let Some(&o) = edges.get(&(b, a)) {
                let (x, y) = (root(&mut parent, i), root(&mut parent, o));
                parent[x.max(y)] = x.min(y);
            }
            edges.insert((a, b), i);
        }
    }
    let mut number = std::collections::HashMap::new();
    (0..faces.len())
        .map(|i| {
            let r = root(&mut parent, i);
            let next = number.len() as u32;
            *number.entry(r).or_insert(next)
        })
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
