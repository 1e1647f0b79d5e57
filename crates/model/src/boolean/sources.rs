//! The boolean's sources: both inputs triangulated and merged, the faces
//! manifold is given (one per planar source polygon, so it can lay a cut
//! polygon's triangles out afresh), and the result read back: attributes
//! by barycentric weights in the source triangle each corner lies in,
//! primitive attributes and groups from the source polygon, origin groups.

use geode_geo::glam::{DVec3, Vec3};
use geode_geo::{ops, AttribClass, AttribData, Attribute, Geometry, Group, PrimKind, TypeInfo};
use geode_manifold::Mesh;
use rayon::prelude::*;

use super::{BooleanOp, Side, SolidInput};
use crate::ModelError;

/// Both inputs triangulated and merged: A's triangles first, then B's.
/// manifold is given faces: edge-connected triangles of one side in one
/// plane, with equal primitive attributes and groups and vertex attributes
/// continuous across their shared edges, are one face (up to
/// [`FACE_MAX`] triangles), numbered by its lowest triangle. So manifold
/// lays a cut face's triangles out afresh, as it does for its own coplanar
/// faces, instead of keeping every input triangle's edges (and an earlier
/// boolean's): on the boolean example, 1558 triangles with 12 under a
/// tenth of a degree, not 1930 with 34, as manifold3d gives with no face
/// numbers at all.
pub(super) struct Sources {
    pub(super) both: Geometry,
    /// A's triangles (B's are numbered from here).
    pub(super) a_triangles: usize,
    pub(super) a_points: usize,
    /// Per triangle: its face (the lowest triangle in it).
    face: Vec<u32>,
    /// Per triangle: its place in `members` (the face's triangles are
    /// `members[start[face]..]`, as many as `size[face]`).
    start: Vec<u32>,
    size: Vec<u8>,
    members: Vec<u32>,
}

/// The most triangles one face holds (each output corner is looked up
/// among its face's triangles).
const FACE_MAX: usize = 64;

/// A point is in a triangle's plane within this much of its longest edge.
const PLANAR: f64 = 1e-6;

impl Sources {
    pub(super) fn new(
        a: &Geometry,
        b: &Geometry,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<Sources, ModelError> {
        let (ta, tb) = rayon::join(
            || triangles_of(a, "A", cancel),
            || triangles_of(b, "B", cancel),
        );
        let (ta, tb) = (ta?, tb?);
        let (a_triangles, a_points) = (ta.num_prims(), ta.num_points());
        // Each side's faces (a face never spans the two) beside the merge.
        let ((fa, fb), both) = rayon::join(
            || rayon::join(|| Faces::grow(&ta), || Faces::grow(&tb)),
            || ops::merge(&[&ta, &tb]),
        );
        let both = both.map_err(|e| ModelError::Failed {
            op: "boolean",
            why: e.to_string(),
        })?;
        Ok(Sources::with_faces(
            both,
            a_triangles,
            a_points,
            fa.followed_by(fb, a_triangles),
        ))
    }

    /// One mesh as side A (for [`super::union_pieces`]).
    pub(super) fn one(
        g: &Geometry,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<Sources, ModelError> {
        let t = triangles_of(g, "input", cancel)?;
        let (n, points) = (t.num_prims(), t.num_points());
        let faces = Faces::grow(&t);
        Ok(Sources::with_faces(t, n, points, faces))
    }

    fn with_faces(both: Geometry, a_triangles: usize, a_points: usize, faces: Faces) -> Sources {
        Sources {
            both,
            a_triangles,
            a_points,
            face: faces.face,
            start: faces.start,
            size: faces.size,
            members: faces.members,
        }
    }

    /// The triangle of face `face` that `p` lies in (the one it is most
    /// inside: the runs are planar), its points and `p`'s clamped weights.
    fn locate(&self, positions: &[Vec3], face: usize, p: DVec3) -> (usize, [u32; 3], [f32; 3]) {
        let mut best = (f64::NEG_INFINITY, face, [0u32; 3], [1.0, 0.0, 0.0]);
        let first = self.start[face] as usize;
        let members = &self.members[first..first + self.size[face] as usize];
        for &t in members {
            let t = t as usize;
            let (points, at) = self.corners(positions, t);
            let w = barycentric(p, at);
            let inside = w[0].min(w[1]).min(w[2]);
            if inside > best.0 {
                best = (inside, t, points, w);
            }
            if inside >= 0.0 {
                break;
            }
        }
        (best.1, best.2, clamped(best.3))
    }

    /// Source triangle `t`'s points and their positions.
    fn corners(&self, positions: &[Vec3], t: usize) -> ([u32; 3], [DVec3; 3]) {
        let p = self.both.prim_points(t);
        let points = [p[0], p[1], p[2]];
        (points, points.map(|k| positions[k as usize].as_dvec3()))
    }

    fn side_of(&self, triangle: usize) -> Side {
        if triangle < self.a_triangles {
            Side::A
        } else {
            Side::B
        }
    }

    /// One side's solid as arrays, each triangle's face number its
    /// number in the merge.
    pub(super) fn solid_input(&self, side: Side) -> SolidInput {
        let (prims, points) = match side {
            Side::A => (0..self.a_triangles, 0..self.a_points),
            Side::B => (
                self.a_triangles..self.both.num_prims(),
                self.a_points..self.both.num_points(),
            ),
        };
        let base = points.start as u32;
        let positions: Vec<[f32; 3]> = self.both.positions()[points]
            .iter()
            .map(|p| p.to_array())
            .collect();
        let triangles: Vec<[u32; 3]> = prims
            .clone()
            .map(|t| {
                let p = self.both.prim_points(t);
                [p[0] - base, p[1] - base, p[2] - base]
            })
            .collect();
        let faces: Vec<u32> = self.face[prims].to_vec();
        SolidInput {
            positions,
            triangles,
            faces,
        }
    }

    /// The geometry of manifold's result `r`: triangles, attributes from
    /// their sources, the origin groups of `op` when given; `piece` numbers
    /// a shatter piece.
    pub(super) fn output(
        &self,
        r: &Mesh,
        op: Option<BooleanOp>,
        piece: Option<i32>,
    ) -> Result<Geometry, ModelError> {
        let failed = |why: String| ModelError::Failed { op: "boolean", why };
        if r.triangles.is_empty() {
            return Ok(Geometry::new());
        }
        if let Some(&face) = r
            .faces
            .iter()
            .find(|&&f| f as usize >= self.both.num_prims())
        {
            return Err(failed(format!("a face lost its source ({face})")));
        }
        let sources = &r.faces;
        // Per output corner: the source triangle's points, the corner's
        // weights there (manifold keeps every output triangle inside the
        // source triangle it names, so a corner is in it up to rounding: a
        // few parts in a thousand of a sliver's height on a hundred-sphere
        // union, and the clamped weights are its nearest point there) and
        // the source triangle.
        let source_positions = self.both.positions();
        let mut corners = vec![([0u32; 3], [0f32; 3], 0usize); 3 * r.triangles.len()];
        corners
            .par_chunks_mut(3)
            .zip(r.triangles.par_iter().zip(sources.par_iter()))
            .for_each(|(out, (tri, &face))| {
                for (slot, &v) in out.iter_mut().zip(tri) {
                    let p = Vec3::from_array(r.positions[v as usize]).as_dvec3();
                    let (t, points, w) = self.locate(source_positions, face as usize, p);
                    *slot = (points, w, t);
                }
            });
        let triangles = &r.triangles;
        let positions: Vec<Vec3> = r.positions.iter().map(|p| Vec3::from_array(*p)).collect();
        let mut out =
            Geometry::from_triangles(positions, triangles).map_err(|e| failed(e.to_string()))?;
        self.carry_points(&mut out, triangles, &corners)?;
        self.carry_vertices(&mut out, &corners)?;
        self.carry_prims(&mut out, sources)?;
        if let Some(op) = op {
            self.mark_origins(&mut out, triangles, sources, op)?;
        }
        if let Some(piece) = piece {
            let n = out.num_prims();
            let piece_attr = Attribute::from_data(AttribData::Int(vec![piece; n]), TypeInfo::None);
            out.set_attrib(AttribClass::Primitive, "piece", piece_attr)
                .map_err(|e| failed(e.to_string()))?;
        }
        Ok(out)
    }

    /// Point attributes (P aside: the output's own) from the first corner
    /// that uses each point, in triangle order.
    fn carry_points(
        &self,
        out: &mut Geometry,
        triangles: &[[u32; 3]],
        corners: &[([u32; 3], [f32; 3], usize)],
    ) -> Result<(), ModelError> {
        let mut first = vec![u32::MAX; out.num_points()];
        for (k, &p) in triangles.iter().flatten().enumerate() {
            if first[p as usize] == u32::MAX {
                first[p as usize] = k as u32;
            }
        }
        let items: Vec<([u32; 3], [f32; 3])> = first
            .iter()
            .map(|&k| match corners.get(k as usize) {
                Some((pts, w, _)) => (*pts, *w),
                None => ([0; 3], [1.0, 0.0, 0.0]),
            })
            .collect();
        for (name, attr) in self.both.attribs(AttribClass::Point).iter() {
            if name == "P" {
                continue;
            }
            set(out, AttribClass::Point, name, attr.mix3(&items))?;
        }
        for (name, group) in self.both.point_groups() {
            let members = items.iter().map(|(pts, w)| {
                let best = (1..3).fold(0, |b, j| if w[j] > w[b] { j } else { b });
                group.contains(pts[best] as usize)
            });
            out.set_point_group(name, Group::from_flags(members))
                .map_err(|e| ModelError::Failed {
                    op: "boolean",
                    why: e.to_string(),
                })?;
        }
        Ok(())
    }

    /// Vertex attributes: each corner weighted over its source triangle's
    /// three vertices.
    fn carry_vertices(
        &self,
        out: &mut Geometry,
        corners: &[([u32; 3], [f32; 3], usize)],
    ) -> Result<(), ModelError> {
        let table = self.both.attribs(AttribClass::Vertex);
        if table.num_attribs() == 0 {
            return Ok(());
        }
        let items: Vec<([u32; 3], [f32; 3])> = corners
            .iter()
            .map(|(_, w, s)| {
                let r = self.both.prim_vertex_range(*s);
                ([r.start as u32, r.start as u32 + 1, r.start as u32 + 2], *w)
            })
            .collect();
        for (name, attr) in table.iter() {
            set(out, AttribClass::Vertex, name, attr.mix3(&items))?;
        }
        Ok(())
    }

    /// Primitive attributes and groups of each face's source polygon.
    fn carry_prims(&self, out: &mut Geometry, sources: &[u32]) -> Result<(), ModelError> {
        for (name, attr) in self.both.attribs(AttribClass::Primitive).iter() {
            set(out, AttribClass::Primitive, name, attr.gather(sources))?;
        }
        for (name, group) in self.both.prim_groups() {
            let members = sources.iter().map(|&s| group.contains(s as usize));
            out.set_prim_group(name, Group::from_flags(members))
                .map_err(|e| ModelError::Failed {
                    op: "boolean",
                    why: e.to_string(),
                })?;
        }
        for (name, attr) in self.both.attribs(AttribClass::Detail).iter() {
            set(out, AttribClass::Detail, name, attr.clone())?;
        }
        Ok(())
    }

    /// The origin groups (which side each face came from and where it
    /// lies relative to the other) and the seam's points.
    fn mark_origins(
        &self,
        out: &mut Geometry,
        triangles: &[[u32; 3]],
        sources: &[u32],
        op: BooleanOp,
    ) -> Result<(), ModelError> {
        // A face of A kept by a union or a subtraction lies outside B; by
        // an intersection, inside. B's faces: outside A in a union, inside
        // it otherwise (a subtraction keeps B's faces inside A, reversed).
        let (a_group, b_group) = match op {
            BooleanOp::Union => ("a_outside_b", "b_outside_a"),
            BooleanOp::Intersect => ("a_inside_b", "b_inside_a"),
            BooleanOp::Subtract | BooleanOp::Shatter => ("a_outside_b", "b_inside_a"),
        };
        let from_a: Vec<bool> = sources
            .iter()
            .map(|&s| self.side_of(s as usize) == Side::A)
            .collect();
        for name in ["a_inside_b", "a_outside_b", "b_inside_a", "b_outside_a"] {
            let members = from_a
                .iter()
                .map(|&a| if a { name == a_group } else { name == b_group });
            out.set_prim_group(name, Group::from_flags(members))
                .map_err(|e| ModelError::Failed {
                    op: "boolean",
                    why: e.to_string(),
                })?;
        }
        let mut touched = vec![0u8; out.num_points()];
        for (tri, &a) in triangles.iter().zip(&from_a) {
            for &p in tri {
                touched[p as usize] |= if a { 1 } else { 2 };
            }
        }
        out.set_point_group("seam", Group::from_flags(touched.iter().map(|&t| t == 3)))
            .map_err(|e| ModelError::Failed {
                op: "boolean",
                why: e.to_string(),
            })
    }
}

fn set(
    out: &mut Geometry,
    class: AttribClass,
    name: &str,
    attr: Attribute,
) -> Result<(), ModelError> {
    out.set_attrib(class, name, attr)
        .map_err(|e| ModelError::Failed {
            op: "boolean",
            why: e.to_string(),
        })
}

/// Input `name` as triangles: polygons only (a boolean needs solids).
pub(super) fn triangles_of(
    g: &Geometry,
    name: &'static str,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, ModelError> {
    if let Some(k) = g.prim_kinds().iter().position(|k| *k != PrimKind::Polygon) {
        return Err(ModelError::NotClosed {
            input: name,
            why: format!(
                "primitive {k} is a {}: a boolean takes closed polygon meshes",
                g.prim_kinds()[k].name()
            ),
        });
    }
    let t = ops::triangulate_with(g, None, cancel).ok_or(ModelError::Cancelled)?;
    // manifold takes a solid's winding as given: inside out, A's shell
    // came back as two coincident copies of B's.
    let volume = f64::from(ops::signed_volume(&t));
    if volume < 0.0 {
        return Err(ModelError::InsideOut {
            input: name,
            volume,
        });
    }
    Ok(t)
}

/// The faces manifold is given (see [`Sources`]), grown from each
/// triangle not yet in one, in order, over shared edges.
struct Faces {
    face: Vec<u32>,
    start: Vec<u32>,
    size: Vec<u8>,
    members: Vec<u32>,
}

impl Faces {
    /// `b`'s faces after `self`'s, `b`'s triangles numbered from `first`.
    fn followed_by(mut self, b: Faces, first: usize) -> Faces {
        let (shift, at) = (first as u32, self.members.len() as u32);
        self.face.extend(b.face.iter().map(|f| f + shift));
        self.start.extend(b.start.iter().map(|s| s + at));
        self.size.extend(b.size);
        self.members.extend(b.members.iter().map(|m| m + shift));
        self
    }

    fn grow(both: &Geometry) -> Faces {
        let n = both.num_prims();
        let twin = twins(both);
        let p = both.positions();
        let vp = both.vertex_points();
        let corners = |t: usize| -> [DVec3; 3] {
            let q = both.prim_points(t);
            [0, 1, 2].map(|k| p[q[k] as usize].as_dvec3())
        };
        // Edges between two triangles in one plane, found in parallel: most
        // triangles of a curved mesh have none and are faces of their own.
        let flat: Vec<[bool; 3]> = (0..n)
            .into_par_iter()
            .map(|t| {
                let Some((a, normal, tol)) = plane_of(corners(t)) else {
                    return [false; 3];
                };
                [0, 1, 2].map(|k| {
                    let tw = twin[3 * t + k] as usize;
                    tw != u32::MAX as usize && {
                        let far = p[vp[tw - tw % 3 + (tw + 2) % 3] as usize].as_dvec3();
                        (far - a).dot(normal).abs() <= tol
                    }
                })
            })
            .collect();
        let alike = Alike::new(both);
        let mut faces = Faces {
            face: vec![u32::MAX; n],
            start: vec![0; n],
            size: vec![0; n],
            members: Vec::with_capacity(n),
        };
        for seed in 0..n {
            if faces.face[seed] != u32::MAX {
                continue;
            }
            let first = faces.members.len();
            faces.face[seed] = seed as u32;
            faces.members.push(seed as u32);
            let any_flat = flat[seed].iter().any(|&f| f);
            let plane = if any_flat {
                plane_of(corners(seed))
            } else {
                None
            };
            let mut next = first;
            while let (Some((a, normal, tol)), true) = (plane, next < faces.members.len()) {
                let t = faces.members[next] as usize;
                next += 1;
                for (k, &is_flat) in flat[t].iter().enumerate() {
                    if faces.members.len() - first >= FACE_MAX {
                        break;
                    }
                    let h = 3 * t + k;
                    let tw = twin[h];
                    if !is_flat {
                        continue;
                    }
                    let (tw, u) = (tw as usize, tw as usize / 3);
                    let next = |x: usize| x - x % 3 + (x + 1) % 3;
                    let joins = faces.face[u] == u32::MAX
                        && corners(u).iter().all(|&q| (q - a).dot(normal).abs() <= tol)
                        && alike.prims(seed, u)
                        && alike.across(h, next(h), tw, next(tw));
                    if joins {
                        faces.face[u] = seed as u32;
                        faces.members.push(u as u32);
                    }
                }
            }
            faces.start[seed] = first as u32;
            faces.size[seed] = (faces.members.len() - first) as u8;
        }
        faces
    }
}

/// Per half-edge of the triangles (vertex `3 t + k`, from corner `k` to
/// the next), its twin: the one other half-edge over the same two points
/// (`u32::MAX` on an edge of one or of more than two triangles). Half-edges
/// are bucketed by their lower point (a counting sort, in half-edge order
/// within a bucket, so the pairing does not depend on anything but the
/// mesh) and matched by their higher point inside a bucket.
fn twins(both: &Geometry) -> Vec<u32> {
    let vp = both.vertex_points();
    let ends = |h: usize| {
        let (a, b) = (vp[h], vp[h - h % 3 + (h + 1) % 3]);
        (a.min(b), a.max(b))
    };
    let mut start = vec![0u32; both.num_points() + 1];
    for h in 0..vp.len() {
        start[ends(h).0 as usize + 1] += 1;
    }
    for k in 1..start.len() {
        start[k] += start[k - 1];
    }
    let mut fill = start.clone();
    let mut bucketed = vec![0u32; vp.len()];
    for h in 0..vp.len() {
        let slot = &mut fill[ends(h).0 as usize];
        bucketed[*slot as usize] = h as u32;
        *slot += 1;
    }
    let mut twin = vec![u32::MAX; vp.len()];
    for w in start.windows(2) {
        let bucket = &bucketed[w[0] as usize..w[1] as usize];
        for &x in bucket {
            if twin[x as usize] != u32::MAX {
                continue;
            }
            let hi = ends(x as usize).1;
            let mut same = bucket
                .iter()
                .filter(|&&y| y != x && ends(y as usize).1 == hi);
            if let (Some(&y), None) = (same.next(), same.next()) {
                twin[x as usize] = y;
                twin[y as usize] = x;
            }
        }
    }
    twin
}

/// A triangle's plane: a corner, the unit normal and the tolerance (a
/// millionth of its longest edge); `None` for a triangle with no area.
fn plane_of([a, b, c]: [DVec3; 3]) -> Option<(DVec3, DVec3, f64)> {
    let normal = (b - a).cross(c - a).try_normalize()?;
    let longest = (b - a).length().max((c - b).length()).max((a - c).length());
    Some((a, normal, PLANAR * longest))
}

/// Whether two triangles may share a face: the same primitive attribute
/// values and groups, and the same vertex attribute values on both sides
/// of their shared edge (no uv seam along it).
struct Alike<'a> {
    prim_attribs: Vec<&'a AttribData>,
    prim_groups: Vec<&'a Group>,
    vertex_attribs: Vec<&'a AttribData>,
}

impl<'a> Alike<'a> {
    fn new(g: &'a Geometry) -> Alike<'a> {
        Alike {
            prim_attribs: g
                .attribs(AttribClass::Primitive)
                .iter()
                .map(|(_, a)| a.data())
                .collect(),
            prim_groups: g.prim_groups().values().collect(),
            vertex_attribs: g
                .attribs(AttribClass::Vertex)
                .iter()
                .map(|(_, a)| a.data())
                .collect(),
        }
    }

    fn prims(&self, a: usize, b: usize) -> bool {
        self.prim_attribs.iter().all(|d| d.get(a) == d.get(b))
            && self
                .prim_groups
                .iter()
                .all(|g| g.contains(a) == g.contains(b))
    }

    /// Half-edge (vertex) `h` (then `h_next`) against its twin (then
    /// `t_next`): `h` starts where `t_next` does, `h_next` where `twin` does.
    fn across(&self, h: usize, h_next: usize, twin: usize, t_next: usize) -> bool {
        let same = |x: usize, y: usize| self.vertex_attribs.iter().all(|d| d.get(x) == d.get(y));
        same(h, t_next) && same(h_next, twin)
    }
}

/// Why a side is not a closed manifold: its open and over-shared edges.
pub(super) fn boundary_report(both: &Geometry, side: Side, s: &Sources) -> String {
    let prims = match side {
        Side::A => 0..s.a_triangles,
        Side::B => s.a_triangles..both.num_prims(),
    };
    let tris: Vec<[u32; 3]> = prims
        .map(|t| {
            let p = both.prim_points(t);
            [p[0], p[1], p[2]]
        })
        .collect();
    // Only on the error path: the topology's report counts the edges.
    let report = Geometry::from_triangles(both.positions().to_vec(), &tris)
        .map(|g| g.topology().manifold_report(&g))
        .unwrap_or_default();
    format!(
        "{} open edges, {} edges shared by more than two faces",
        report.boundary_edges, report.non_manifold_edges
    )
}

/// Barycentric weights of `p` (projected into the plane of `abc`); a
/// degenerate triangle gives its first corner.
fn barycentric(p: DVec3, [a, b, c]: [DVec3; 3]) -> [f64; 3] {
    let (v0, v1, v2) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (v0.dot(v0), v0.dot(v1), v1.dot(v1));
    let (d20, d21) = (v2.dot(v0), v2.dot(v1));
    let den = d00 * d11 - d01 * d01;
    if den.abs() <= f64::EPSILON * d00 * d11 {
        return [1.0, 0.0, 0.0];
    }
    let v = (d11 * d20 - d01 * d21) / den;
    let w = (d00 * d21 - d01 * d20) / den;
    [1.0 - v - w, v, w]
}

/// Weights clamped into the triangle (a point of a cut lies on it up to
/// rounding) and summing to one.
fn clamped(w: [f64; 3]) -> [f32; 3] {
    let mut x = w.map(|t| t.max(0.0));
    let sum: f64 = x.iter().sum();
    if sum <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    x.iter_mut().for_each(|t| *t /= sum);
    x.map(|t| t as f32)
}
