//! The closest point of a triangle hierarchy to a query point: depth-first
//! through the boxes nearest first, pruning boxes farther than the best
//! found, so a query on a million triangles visits a few dozen. Degenerate
//! triangles (segments, points) answer as their longest edge.

use glam::{DVec3, Vec3};

use super::raycast::TriangleBvh;

/// The closest point found: the triangle (its index in the list given to
/// [`TriangleBvh::new`]), the point, its barycentric weights of corners 1
/// and 2 (corner 0 has `1 - u - v`), and the squared distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closest {
    pub triangle: u32,
    pub point: Vec3,
    pub u: f32,
    pub v: f32,
    pub dist2: f32,
}

impl TriangleBvh {
    /// The closest point within `max_dist` of `q`; ties go to the lower
    /// triangle index, so the answer is the same however the tree was
    /// walked.
    pub fn closest(&self, q: Vec3, max_dist: f32) -> Option<Closest> {
        if self.corners.is_empty() {
            return None;
        }
        let mut best: Option<Closest> = None;
        let mut bound = if max_dist.is_finite() {
            max_dist * max_dist
        } else {
            f32::INFINITY
        };
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let n = stack[top];
            let node = &self.nodes[n as usize];
            if box_dist2(node.lo, node.hi, q) > bound {
                continue;
            }
            if node.end > node.start {
                for i in node.start as usize..node.end as usize {
                    let tri = self.order[i];
                    let (point, u, v) = closest_on_triangle(&self.corners[i], q);
                    let d2 = (point - q).length_squared();
                    let better = match best {
                        Some(b) => d2 < b.dist2 || (d2 == b.dist2 && tri < b.triangle),
                        None => d2 <= bound,
                    };
                    if better {
                        best = Some(Closest {
                            triangle: tri,
                            point,
                            u,
                            v,
                            dist2: d2,
                        });
                        bound = d2;
                    }
                }
            } else {
                // The nearer child is walked first (pushed last); when the
                // query is inside both boxes (thick boxes of a wavy
                // surface), the one whose centre is nearer, so the first
                // leaf reached is near and the bound tight at once.
                let (a, b) = (n + 1, node.second);
                let (na, nb) = (&self.nodes[a as usize], &self.nodes[b as usize]);
                let key = |m: &super::raycast::Node| {
                    let centre = (m.lo + m.hi) * 0.5;
                    (box_dist2(m.lo, m.hi, q), (centre - q).length_squared())
                };
                let (ka, kb) = (key(na), key(nb));
                let a_first = ka.0 < kb.0 || (ka.0 == kb.0 && ka.1 <= kb.1);
                let (first, second) = if a_first { (a, b) } else { (b, a) };
                stack[top] = second;
                stack[top + 1] = first;
                top += 2;
            }
        }
        best
    }

    /// [`TriangleBvh::closest`] in double precision (the corners are
    /// single, every step after them double): exact to rounding on long
    /// thin triangles. The walk is `closest`'s with double box distances;
    /// `closest` keeps single ones, since the remesher's result on the
    /// OpenSubdiv car (a sliver appears) turned out sensitive to the
    /// pruning order (to be made one walk once that is understood).
    pub fn closest_f64(&self, q: DVec3, max_dist: f64) -> Option<Closest64> {
        if self.corners.is_empty() {
            return None;
        }
        let mut best: Option<Closest64> = None;
        let mut bound = if max_dist.is_finite() {
            max_dist * max_dist
        } else {
            f64::INFINITY
        };
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let n = stack[top];
            let node = &self.nodes[n as usize];
            if box_dist2_f64(node.lo, node.hi, q) > bound {
                continue;
            }
            if node.end > node.start {
                for i in node.start as usize..node.end as usize {
                    let tri = self.order[i];
                    let (point, u, v) =
                        closest_on_triangle_f64(&self.corners[i].map(|c| c.as_dvec3()), q);
                    let d2 = (point - q).length_squared();
                    let better = match best {
                        Some(b) => d2 < b.dist2 || (d2 == b.dist2 && tri < b.triangle),
                        None => d2 <= bound,
                    };
                    if better {
                        best = Some(Closest64 {
                            triangle: tri,
                            point,
                            u,
                            v,
                            dist2: d2,
                        });
                        bound = d2;
                    }
                }
            } else {
                // The nearer child is walked first (pushed last); when the
                // query is inside both boxes (thick boxes of a wavy
                // surface), the one whose centre is nearer, so the first
                // leaf reached is near and the bound tight at once.
                let (a, b) = (n + 1, node.second);
                let (na, nb) = (&self.nodes[a as usize], &self.nodes[b as usize]);
                let key = |m: &super::raycast::Node| {
                    let centre = ((m.lo + m.hi) * 0.5).as_dvec3();
                    (box_dist2_f64(m.lo, m.hi, q), (centre - q).length_squared())
                };
                let (ka, kb) = (key(na), key(nb));
                let a_first = ka.0 < kb.0 || (ka.0 == kb.0 && ka.1 <= kb.1);
                let (first, second) = if a_first { (a, b) } else { (b, a) };
                stack[top] = second;
                stack[top + 1] = first;
                top += 2;
            }
        }
        best
    }
}

/// [`Closest`] in double precision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closest64 {
    pub triangle: u32,
    pub point: DVec3,
    pub u: f64,
    pub v: f64,
    pub dist2: f64,
}

fn box_dist2_f64(lo: Vec3, hi: Vec3, q: DVec3) -> f64 {
    let d = (lo.as_dvec3() - q).max(q - hi.as_dvec3()).max(DVec3::ZERO);
    d.length_squared()
}

fn box_dist2(lo: Vec3, hi: Vec3, q: Vec3) -> f32 {
    let d = (lo - q).max(q - hi).max(Vec3::ZERO);
    d.length_squared()
}

/// The closest point of a segment to `q` and its parameter along it.
fn closest_on_segment(a: DVec3, b: DVec3, q: DVec3) -> (DVec3, f64) {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((q - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t, t)
}

/// The closest point of triangle `c` to `q` with its barycentric (u, v),
/// computed in double precision (see [`closest_on_triangle_f64`]).
pub fn closest_on_triangle(c: &[Vec3; 3], q: Vec3) -> (Vec3, f32, f32) {
    let (p, u, v) = closest_on_triangle_f64(&c.map(|x| x.as_dvec3()), q.as_dvec3());
    (p.as_vec3(), u as f32, v as f32)
}

/// The closest point of triangle `c` to `q` with its barycentric (u, v)
/// (Ericson, Real-Time Collision Detection, 5.1.5: by Voronoi region).
pub fn closest_on_triangle_f64(c: &[DVec3; 3], q: DVec3) -> (DVec3, f64, f64) {
    let (a, b, cc) = (c[0], c[1], c[2]);
    let ab = b - a;
    let ac = cc - a;
    if ab.cross(ac).length_squared() <= f64::EPSILON * ab.length_squared() * ac.length_squared() {
        return closest_degenerate(c, q);
    }
    let ap = q - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, 0.0, 0.0);
    }
    let bp = q - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, 1.0, 0.0);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let t = d1 / (d1 - d3);
        return (a + ab * t, t, 0.0);
    }
    let cp = q - cc;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (cc, 0.0, 1.0);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let t = d2 / (d2 - d6);
        return (a + ac * t, 0.0, t);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + (cc - b) * t, 1.0 - t, t);
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    (a + ab * v + ac * w, v, w)
}

/// A triangle without area: the closest of its three edges.
fn closest_degenerate(c: &[DVec3; 3], q: DVec3) -> (DVec3, f64, f64) {
    let edges = [(0usize, 1usize), (1, 2), (2, 0)];
    let mut best = (c[0], 0.0, 0.0, f64::INFINITY);
    for (i, j) in edges {
        let (p, t) = closest_on_segment(c[i], c[j], q);
        let d = (p - q).length_squared();
        if d < best.3 {
            // Weights of corners 1 and 2 at parameter t from i to j.
            let mut w = [0.0; 3];
            w[i] += 1.0 - t;
            w[j] += t;
            best = (p, w[1], w[2], d);
        }
    }
    (best.0, best.1, best.2)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force over every triangle: what the hierarchy must agree with.
    fn brute(pos: &[Vec3], tris: &[[u32; 3]], q: Vec3) -> f32 {
        tris.iter()
            .map(|t| {
                let c = t.map(|i| pos[i as usize]);
                (closest_on_triangle(&c, q).0 - q).length_squared()
            })
            .fold(f32::INFINITY, f32::min)
    }

    #[test]
    fn matches_brute_force_on_a_bumpy_grid() {
        let n = 30u32;
        let mut pos = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = (i as f32 / n as f32, j as f32 / n as f32);
                pos.push(Vec3::new(x, y, 0.1 * (7.0 * x).sin() * (5.0 * y).cos()));
            }
        }
        let mut tris = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let a = j * (n + 1) + i;
                tris.push([a, a + 1, a + n + 2]);
                tris.push([a, a + n + 2, a + n + 1]);
            }
        }
        let bvh = TriangleBvh::new(&pos, &tris);
        let mut s = 1u32;
        for _ in 0..500 {
            let mut r = || {
                s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                (s >> 8) as f32 / (1u32 << 24) as f32 * 1.6 - 0.3
            };
            let q = Vec3::new(r(), r(), r());
            let got = bvh.closest(q, f32::INFINITY).unwrap();
            assert!((got.dist2 - brute(&pos, &tris, q)).abs() < 1e-6, "{q}");
            // The weights rebuild the point.
            let c = tris[got.triangle as usize].map(|i| pos[i as usize]);
            let p = c[0] * (1.0 - got.u - got.v) + c[1] * got.u + c[2] * got.v;
            assert!((p - got.point).length() < 1e-5);
        }
    }

    /// A long sliver in the plane y = 0 (from a machined part's STL): the
    /// point above its middle projects inside it, so its distance is its
    /// height; single-precision Ericson put it past an edge.
    #[test]
    fn a_sliver_is_measured_to_its_plane() {
        let c = [
            Vec3::new(2.46875, 0.0, 0.0),
            Vec3::new(0.450_072_35, 0.0, 0.187_006_83),
            Vec3::new(0.437_993_2, 0.0, 0.174_927_64),
        ];
        let q = Vec3::new(1.532_617_1, -0.000_528_097_15, 0.086_373_195);
        let (p, _, _) = closest_on_triangle(&c, q);
        assert!(((p - q).length() - 0.000_528_097_15).abs() < 1e-9, "{p}");
    }

    #[test]
    fn respects_the_maximum_distance_and_degenerate_triangles() {
        let pos = [Vec3::ZERO, Vec3::X, Vec3::X];
        let bvh = TriangleBvh::new(&pos, &[[0, 1, 2]]);
        let hit = bvh.closest(Vec3::new(0.25, 1.0, 0.0), 2.0).unwrap();
        assert!((hit.point - Vec3::new(0.25, 0.0, 0.0)).length() < 1e-6);
        assert!((hit.dist2 - 1.0).abs() < 1e-6);
        assert!(bvh.closest(Vec3::new(0.25, 1.0, 0.0), 0.5).is_none());
    }
}
