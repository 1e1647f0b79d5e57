//! The convex hull of a point set in 3D by quickhull (Barber, Dobkin and
//! Huhdanpaa 1996), for the oriented box's candidate directions.
//!
//! Start from a tetrahedron of extreme points; every other point goes to
//! the outside set of the first face it lies above. Repeatedly take a face
//! with an outside set, its farthest point the eye: the faces the eye sees
//! (found by walking adjacency from that face) are removed, the horizon
//! (edges between seen and unseen faces) is joined to the eye by new
//! faces, and the removed faces' outside points go to the new faces they
//! lie above (or are inside now and dropped). "Above" means farther than
//! `eps` (1e-10 of the points' extent): points on a face's plane within
//! that tolerance, like the many coplanar points of a divided box, never
//! become vertices. Computed in f64, one thread, in point order: the same
//! hull on any machine.
//!
//! A near-degenerate input can give a horizon that is not one loop; the
//! hull then reports failure and the caller falls back to the points
//! themselves. Face slots of removed faces are reused.

use std::collections::HashMap;

use geode_geo::glam::DVec3;

const NONE: u32 = u32::MAX;

/// A closed triangle hull: outward faces over the input's point indices.
pub struct Hull {
    pub faces: Vec<[u32; 3]>,
    /// Unit outward normals.
    pub normals: Vec<DVec3>,
    /// Twice each face's area.
    pub double_areas: Vec<f64>,
    /// The hull's vertices (input point indices), ascending.
    pub vertices: Vec<u32>,
    /// Each undirected edge once: its two points and the faces beside it.
    pub edges: Vec<([u32; 2], [u32; 2])>,
}

/// Why there is no solid hull.
pub enum NoHull {
    /// All points within tolerance of one point or one line.
    Line,
    /// All points within tolerance of one plane (its unit normal).
    Flat(DVec3),
    /// The construction met a degenerate configuration.
    Failed,
    Cancelled,
}

struct Face {
    v: [u32; 3],
    normal: DVec3,
    offset: f64,
    /// Face across edge `k`, from `v[k]` to `v[(k + 1) % 3]`.
    adj: [u32; 3],
    outside: Vec<u32>,
    alive: bool,
}

impl Face {
    fn distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p) - self.offset
    }
}

struct Builder<'a> {
    points: &'a [DVec3],
    eps: f64,
    faces: Vec<Face>,
    free_slots: Vec<u32>,
    /// Per face: the eye number it was last classified for, and whether
    /// the eye sees it.
    seen_stamp: Vec<(u32, bool)>,
}

/// The convex hull of `points`; `cancel` is polled every 1024 eyes.
pub fn convex_hull(points: &[DVec3], cancel: &(dyn Fn() -> bool + Sync)) -> Result<Hull, NoHull> {
    let (lo, hi) = points.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let extent = (hi - lo)
        .max_element()
        .max(lo.abs().max(hi.abs()).max_element());
    let mut b = Builder {
        points,
        eps: 1e-10 * extent.max(f64::MIN_POSITIVE),
        faces: Vec::new(),
        free_slots: Vec::new(),
        seen_stamp: Vec::new(),
    };
    let simplex = b.initial_simplex()?;
    b.assign_initial(simplex);
    let mut stack: Vec<u32> = (0..4).collect();
    let mut eyes = 0u32;
    while let Some(f) = stack.pop() {
        let face = &b.faces[f as usize];
        if !face.alive || face.outside.is_empty() {
            continue;
        }
        eyes += 1;
        if eyes.is_multiple_of(1024) && cancel() {
            return Err(NoHull::Cancelled);
        }
        let created = b.add_eye(f, eyes)?;
        stack.extend(created);
    }
    Ok(b.finish())
}

impl Builder<'_> {
    /// Four extreme points spanning a tetrahedron, its faces made.
    fn initial_simplex(&mut self) -> Result<[u32; 4], NoHull> {
        let p = self.points;
        if p.is_empty() {
            return Err(NoHull::Line);
        }
        let mut extremes = [0u32; 6];
        for (i, q) in p.iter().enumerate() {
            for axis in 0..3 {
                if q[axis] < p[extremes[2 * axis] as usize][axis] {
                    extremes[2 * axis] = i as u32;
                }
                if q[axis] > p[extremes[2 * axis + 1] as usize][axis] {
                    extremes[2 * axis + 1] = i as u32;
                }
            }
        }
        let (mut a, mut b, mut best) = (0, 0, -1.0);
        for &i in &extremes {
            for &j in &extremes {
                let d = p[i as usize].distance_squared(p[j as usize]);
                if d > best {
                    (a, b, best) = (i, j, d);
                }
            }
        }
        let farthest = |score: &dyn Fn(DVec3) -> f64| {
            let mut best = (0u32, -1.0);
            for (i, &q) in p.iter().enumerate() {
                let s = score(q);
                if s > best.1 {
                    best = (i as u32, s);
                }
            }
            best
        };
        let (pa, pb) = (p[a as usize], p[b as usize]);
        let axis = (pb - pa).normalize_or_zero();
        let (c, line_distance) = farthest(&|q| (q - pa).reject_from_normalized(axis).length());
        if axis == DVec3::ZERO || line_distance <= self.eps {
            return Err(NoHull::Line);
        }
        let normal = (pb - pa).cross(p[c as usize] - pa).normalize();
        let (d, plane_distance) = farthest(&|q| normal.dot(q - pa).abs());
        if plane_distance <= self.eps {
            return Err(NoHull::Flat(normal));
        }
        let simplex = [a, b, c, d];
        let centre = simplex.iter().map(|&i| p[i as usize]).sum::<DVec3>() / 4.0;
        for tri in [[a, b, c], [a, d, b], [b, d, c], [c, d, a]] {
            let f = self.new_face(tri);
            if self.faces[f as usize].distance(centre) > 0.0 {
                let face = &mut self.faces[f as usize];
                face.v.swap(1, 2);
                let [x, y, z] = face.v;
                let (normal, offset) = plane(p, x, y, z);
                (face.normal, face.offset) = (normal, offset);
            }
        }
        self.link_all(&[0, 1, 2, 3]).map_err(|_| NoHull::Failed)?;
        Ok(simplex)
    }

    /// Every point but the simplex's into the first face it lies above.
    fn assign_initial(&mut self, simplex: [u32; 4]) {
        for (i, &q) in self.points.iter().enumerate() {
            if simplex.contains(&(i as u32)) {
                continue;
            }
            if let Some(f) = (0..4).find(|&f| self.faces[f].distance(q) > self.eps) {
                self.faces[f].outside.push(i as u32);
            }
        }
    }

    fn new_face(&mut self, v: [u32; 3]) -> u32 {
        let (normal, offset) = plane(self.points, v[0], v[1], v[2]);
        let face = Face {
            v,
            normal,
            offset,
            adj: [NONE; 3],
            outside: Vec::new(),
            alive: true,
        };
        if let Some(slot) = self.free_slots.pop() {
            self.faces[slot as usize] = face;
            self.seen_stamp[slot as usize] = (0, false);
            slot
        } else {
            self.faces.push(face);
            self.seen_stamp.push((0, false));
            (self.faces.len() - 1) as u32
        }
    }

    /// Adjacency among `faces` by their shared directed edges.
    fn link_all(&mut self, faces: &[u32]) -> Result<(), ()> {
        let mut by_edge = HashMap::new();
        for &f in faces {
            let v = self.faces[f as usize].v;
            for k in 0..3 {
                by_edge.insert((v[k], v[(k + 1) % 3]), f);
            }
        }
        for &f in faces {
            let v = self.faces[f as usize].v;
            for k in 0..3 {
                let twin = *by_edge.get(&(v[(k + 1) % 3], v[k])).ok_or(())?;
                self.faces[f as usize].adj[k] = twin;
            }
        }
        Ok(())
    }

    fn sees(&mut self, f: u32, eye: DVec3, stamp: u32) -> bool {
        let (s, seen) = self.seen_stamp[f as usize];
        if s == stamp {
            return seen;
        }
        let seen = self.faces[f as usize].distance(eye) > self.eps;
        self.seen_stamp[f as usize] = (stamp, seen);
        seen
    }

    /// Adds face `f`'s farthest outside point; returns the new faces.
    fn add_eye(&mut self, f: u32, stamp: u32) -> Result<Vec<u32>, NoHull> {
        let eye_index = self.farthest_outside(f);
        let eye = self.points[eye_index as usize];
        // The faces the eye sees, and the horizon: (seen face, edge).
        let mut visible = vec![f];
        self.seen_stamp[f as usize] = (stamp, true);
        let mut horizon = Vec::new();
        let mut k = 0;
        while k < visible.len() {
            let g = visible[k];
            k += 1;
            for e in 0..3 {
                let h = self.faces[g as usize].adj[e];
                let before = self.seen_stamp[h as usize].0 == stamp;
                if self.sees(h, eye, stamp) {
                    if !before {
                        visible.push(h);
                    }
                } else {
                    horizon.push((g, e));
                }
            }
        }
        let created = self.cone(eye_index, &horizon)?;
        self.reassign(&visible, eye_index, &created);
        for &g in &visible {
            let face = &mut self.faces[g as usize];
            face.alive = false;
            face.outside = Vec::new();
            self.free_slots.push(g);
        }
        Ok(created)
    }

    fn farthest_outside(&self, f: u32) -> u32 {
        let face = &self.faces[f as usize];
        let mut best = (face.outside[0], f64::NEG_INFINITY);
        for &i in &face.outside {
            let d = face.distance(self.points[i as usize]);
            if d > best.1 {
                best = (i, d);
            }
        }
        best.0
    }

    /// New faces from each horizon edge to the eye, linked to the unseen
    /// faces beyond the horizon and to each other.
    fn cone(&mut self, eye: u32, horizon: &[(u32, usize)]) -> Result<Vec<u32>, NoHull> {
        // Horizon edge `a -> b` per start point `a`: a simple loop has one.
        let mut by_start: HashMap<u32, u32> = HashMap::with_capacity(horizon.len());
        let mut created = Vec::with_capacity(horizon.len());
        let mut pending = Vec::with_capacity(horizon.len());
        for &(g, e) in horizon {
            let v = self.faces[g as usize].v;
            let (a, b) = (v[e], v[(e + 1) % 3]);
            let beyond = self.faces[g as usize].adj[e];
            pending.push((a, b, beyond, g));
        }
        for &(a, b, beyond, seen) in &pending {
            let f = self.new_face([a, b, eye]);
            self.faces[f as usize].adj[0] = beyond;
            let w = self.faces[beyond as usize].v;
            let back = (0..3)
                .find(|&k| {
                    w[k] == b && w[(k + 1) % 3] == a && self.faces[beyond as usize].adj[k] == seen
                })
                .ok_or(NoHull::Failed)?;
            self.faces[beyond as usize].adj[back] = f;
            if by_start.insert(a, f).is_some() {
                return Err(NoHull::Failed);
            }
            created.push(f);
        }
        // Face (a, b, eye): its edge b -> eye meets the face starting at b.
        for &f in &created {
            let b = self.faces[f as usize].v[1];
            let next = *by_start.get(&b).ok_or(NoHull::Failed)?;
            self.faces[f as usize].adj[1] = next;
            self.faces[next as usize].adj[2] = f;
        }
        Ok(created)
    }

    /// The seen faces' outside points (but the eye) to the new faces.
    fn reassign(&mut self, visible: &[u32], eye: u32, created: &[u32]) {
        for &g in visible {
            let outside = std::mem::take(&mut self.faces[g as usize].outside);
            for i in outside {
                if i == eye {
                    continue;
                }
                let q = self.points[i as usize];
                if let Some(&f) = created
                    .iter()
                    .find(|&&f| self.faces[f as usize].distance(q) > self.eps)
                {
                    self.faces[f as usize].outside.push(i);
                }
            }
        }
    }

    /// The live faces, compacted, with their edges and vertices.
    fn finish(self) -> Hull {
        let mut index = vec![NONE; self.faces.len()];
        let mut hull = Hull {
            faces: Vec::new(),
            normals: Vec::new(),
            double_areas: Vec::new(),
            vertices: Vec::new(),
            edges: Vec::new(),
        };
        for (f, face) in self.faces.iter().enumerate() {
            if face.alive {
                index[f] = hull.faces.len() as u32;
                hull.faces.push(face.v);
                hull.normals.push(face.normal);
                let [a, b, c] = face.v.map(|i| self.points[i as usize]);
                hull.double_areas.push((b - a).cross(c - a).length());
            }
        }
        for (f, face) in self.faces.iter().enumerate() {
            if face.alive {
                for (k, &g) in face.adj.iter().enumerate() {
                    if (f as u32) < g {
                        let ends = [face.v[k], face.v[(k + 1) % 3]];
                        hull.edges.push((ends, [index[f], index[g as usize]]));
                    }
                }
            }
        }
        hull.vertices = hull.faces.iter().flatten().copied().collect();
        hull.vertices.sort_unstable();
        hull.vertices.dedup();
        hull
    }
}

/// The unit normal and offset of the plane through `a`, `b`, `c`
/// (counter-clockwise seen from outside).
fn plane(p: &[DVec3], a: u32, b: u32, c: u32) -> (DVec3, f64) {
    let (pa, pb, pc) = (p[a as usize], p[b as usize], p[c as usize]);
    let normal = (pb - pa).cross(pc - pa).normalize_or_zero();
    (normal, normal.dot(pa))
}

#[cfg(test)]
mod tests {
    use super::*;
    use geode_geo::random;

    fn never() -> bool {
        false
    }

    /// A convex hull: closed (V - E + F = 2 with every edge in two faces),
    /// every input point on or below every face plane, every vertex an
    /// input point that lies on its faces.
    fn check_hull(points: &[DVec3], h: &Hull) {
        let (v, e, f) = (h.vertices.len(), h.edges.len(), h.faces.len());
        assert_eq!(2 * e, 3 * f, "every edge in two faces");
        assert_eq!(v as i64 - e as i64 + f as i64, 2, "Euler characteristic");
        let extent = points
            .iter()
            .map(|p| p.abs().max_element())
            .fold(0.0, f64::max);
        for (face, n) in h.faces.iter().zip(&h.normals) {
            let offset = n.dot(points[face[0] as usize]);
            for p in points {
                assert!(
                    n.dot(*p) - offset <= 1e-9 * extent,
                    "a point outside a face"
                );
            }
        }
    }

    #[test]
    fn a_cloud_points_on_a_sphere_and_a_divided_box() {
        let cloud: Vec<DVec3> = (0..3000u64)
            .map(|i| {
                DVec3::new(
                    random::unit_f64(1, i, 0),
                    random::unit_f64(1, i, 1),
                    random::unit_f64(1, i, 2),
                )
            })
            .collect();
        let h = convex_hull(&cloud, &never).ok().unwrap();
        check_hull(&cloud, &h);

        // Every point of a sphere is a vertex of its hull.
        let sphere: Vec<DVec3> = (0..2000u64)
            .map(|i| {
                let z = 2.0 * random::unit_f64(2, i, 0) - 1.0;
                let phi = std::f64::consts::TAU * random::unit_f64(2, i, 1);
                let r = (1.0 - z * z).sqrt();
                DVec3::new(r * phi.cos(), r * phi.sin(), z)
            })
            .collect();
        let h = convex_hull(&sphere, &never).ok().unwrap();
        check_hull(&sphere, &h);
        assert_eq!(h.vertices.len(), sphere.len());

        // A box's grid of points: only the eight corners are vertices.
        let mut grid = Vec::new();
        for x in 0..5 {
            for y in 0..4 {
                for z in 0..3 {
                    grid.push(DVec3::new(
                        f64::from(x),
                        f64::from(y) * 0.5,
                        f64::from(z) * 0.25,
                    ));
                }
            }
        }
        let h = convex_hull(&grid, &never).ok().unwrap();
        check_hull(&grid, &h);
        assert_eq!(h.vertices.len(), 8);
    }

    #[test]
    fn flat_and_straight_sets_have_no_solid_hull() {
        let flat: Vec<DVec3> = (0..50)
            .map(|i| DVec3::new(f64::from(i % 7), f64::from(i / 7), 2.0))
            .collect();
        assert!(matches!(convex_hull(&flat, &never), Err(NoHull::Flat(n)) if n.z.abs() > 0.999));
        let line: Vec<DVec3> = (0..10).map(|i| DVec3::splat(f64::from(i))).collect();
        assert!(matches!(convex_hull(&line, &never), Err(NoHull::Line)));
    }
}
