//! Area-weighted plane quadrics (Garland and Heckbert): the summed squared
//! distance of a point to a set of planes, divided by their total area, so a
//! vertex's error reads as the mean squared distance to the surface it stands
//! for (in model units squared). Planes come from triangles (by area) or
//! are given with a weight of the caller's (a reducer's border and seam
//! constraints), and the point minimising the error can be solved for.

use glam::{DVec3, Vec3};

/// The quadric of a set of planes and their total area.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Quadric {
    /// Upper triangle of n nᵀ (xx, xy, xz, yy, yz, zz), summed with weights.
    a: [f64; 6],
    /// n d, summed with weights.
    b: [f64; 3],
    /// d², summed with weights.
    c: f64,
    /// The weights' sum (the planes' area).
    weight: f64,
}

impl Quadric {
    /// The plane with unit normal `n` through `at`, weighted `w`.
    pub fn plane(n: DVec3, at: DVec3, w: f64) -> Quadric {
        let d = -n.dot(at);
        Quadric {
            a: [
                w * n.x * n.x,
                w * n.x * n.y,
                w * n.x * n.z,
                w * n.y * n.y,
                w * n.y * n.z,
                w * n.z * n.z,
            ],
            b: [w * n.x * d, w * n.y * d, w * n.z * d],
            c: w * d * d,
            weight: w,
        }
    }

    /// The plane through a triangle, weighted by its area (zero for a
    /// degenerate triangle, which then adds nothing).
    pub fn triangle(p: [DVec3; 3]) -> Quadric {
        let cross = (p[1] - p[0]).cross(p[2] - p[0]);
        let len = cross.length();
        if !(len > 0.0 && len.is_finite()) {
            return Quadric::default();
        }
        Quadric::plane(cross / len, p[0], 0.5 * len)
    }

    /// [`Quadric::triangle`] of single-precision corners.
    pub fn of_triangle(p: [Vec3; 3]) -> Quadric {
        Quadric::triangle(p.map(|v| v.as_dvec3()))
    }

    /// The same planes, their weight left out of the mean (constraints
    /// that steer a placement without standing for surface).
    pub fn uncounted(mut self) -> Quadric {
        self.weight = 0.0;
        self
    }

    /// The planes' total weight (area).
    pub fn weight(&self) -> f64 {
        self.weight
    }

    pub fn sum(mut self, o: &Quadric) -> Quadric {
        self.add(o);
        self
    }

    pub fn add(&mut self, o: &Quadric) {
        for k in 0..6 {
            self.a[k] += o.a[k];
        }
        for k in 0..3 {
            self.b[k] += o.b[k];
        }
        self.c += o.c;
        self.weight += o.weight;
    }

    /// The weighted sum of squared distances from `p` to the planes.
    pub fn sum_at(&self, p: Vec3) -> f64 {
        self.eval(p.as_dvec3())
    }

    /// [`Quadric::sum_at`] in double precision.
    pub fn eval(&self, p: DVec3) -> f64 {
        let [xx, xy, xz, yy, yz, zz] = self.a;
        let ap = DVec3::new(
            xx * p.x + xy * p.y + xz * p.z,
            xy * p.x + yy * p.y + yz * p.z,
            xz * p.x + yz * p.y + zz * p.z,
        );
        (p.dot(ap) + 2.0 * DVec3::from_array(self.b).dot(p) + self.c).max(0.0)
    }

    /// The point minimising [`Quadric::eval`], or None when A is singular
    /// for practical purposes (planes all parallel, or all through one
    /// line): the determinant is compared with the cube of A's scale, so
    /// the test does not depend on the model's units.
    pub fn minimizer(&self) -> Option<DVec3> {
        let [xx, xy, xz, yy, yz, zz] = self.a;
        // Cofactors of the symmetric A.
        let c00 = yy * zz - yz * yz;
        let c01 = xz * yz - xy * zz;
        let c02 = xy * yz - xz * yy;
        let det = xx * c00 + xy * c01 + xz * c02;
        let scale = xx + yy + zz;
        if det.is_nan() || det.abs() <= 1e-9 * scale * scale * scale {
            return None;
        }
        let c11 = xx * zz - xz * xz;
        let c12 = xy * xz - xx * yz;
        let c22 = xx * yy - xy * xy;
        let [bx, by, bz] = self.b;
        let inv = -1.0 / det;
        let p = DVec3::new(
            (c00 * bx + c01 * by + c02 * bz) * inv,
            (c01 * bx + c11 * by + c12 * bz) * inv,
            (c02 * bx + c12 * by + c22 * bz) * inv,
        );
        p.is_finite().then_some(p)
    }

    /// Mean squared distance from `p` to the planes of `self` and `other`
    /// together (zero when neither holds any area).
    pub fn mean_with(&self, other: &Quadric, p: Vec3) -> f64 {
        self.mean_with_sum(other, p, other.sum_at(p))
    }

    /// [`Quadric::mean_with`] given `other.sum_at(p)`, which a caller
    /// trying many collapses onto one vertex keeps rather than recomputes.
    pub fn mean_with_sum(&self, other: &Quadric, p: Vec3, other_sum: f64) -> f64 {
        let weight = self.weight + other.weight;
        if weight <= 0.0 {
            return 0.0;
        }
        (self.sum_at(p) + other_sum) / weight
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_to_one_plane_is_exact() {
        let q = Quadric::of_triangle([Vec3::ZERO, Vec3::X * 2.0, Vec3::Y * 2.0]);
        let none = Quadric::default();
        assert!((q.mean_with(&none, Vec3::new(5.0, -3.0, 0.25)) - 0.0625).abs() < 1e-9);
        assert!(q.mean_with(&none, Vec3::new(0.3, 0.3, 0.0)) < 1e-12);
    }

    #[test]
    fn the_mean_weighs_planes_by_area() {
        // Two planes, z = 0 (area 2) and x = 0 (area 0.5), at (1, 0, 1):
        // (2 * 1 + 0.5 * 1) / 2.5 = 1; at (0, 0, 1): 2 / 2.5.
        let floor = Quadric::of_triangle([Vec3::ZERO, Vec3::X * 2.0, Vec3::Y * 2.0]);
        let wall = Quadric::of_triangle([Vec3::ZERO, Vec3::Y, Vec3::Z]);
        assert!((floor.mean_with(&wall, Vec3::new(1.0, 0.0, 1.0)) - 1.0).abs() < 1e-9);
        assert!((floor.mean_with(&wall, Vec3::new(0.0, 0.0, 1.0)) - 0.8).abs() < 1e-9);
    }

    #[test]
    fn three_planes_meet_at_their_corner() {
        let mut q = Quadric::plane(DVec3::X, DVec3::new(1.0, 0.0, 0.0), 1.0);
        q.add(&Quadric::plane(DVec3::Y, DVec3::new(0.0, 2.0, 0.0), 2.0));
        q.add(&Quadric::plane(DVec3::Z, DVec3::new(0.0, 0.0, -3.0), 0.5));
        let p = q.minimizer().unwrap();
        assert!((p - DVec3::new(1.0, 2.0, -3.0)).length() < 1e-12);
        assert!(q.eval(p) < 1e-12);
        assert!((q.eval(DVec3::new(1.0, 2.0, -2.0)) - 0.5).abs() < 1e-12);
        assert_eq!(q.weight(), 3.5);
        assert_eq!(q.uncounted().weight(), 0.0);
    }

    #[test]
    fn parallel_planes_have_no_single_minimiser() {
        let mut q = Quadric::plane(DVec3::Z, DVec3::ZERO, 1.0);
        q.add(&Quadric::plane(DVec3::Z, DVec3::Z, 1.0));
        assert!(q.minimizer().is_none());
    }

    #[test]
    fn degenerate_triangles_add_nothing() {
        let q = Quadric::of_triangle([Vec3::ZERO, Vec3::X, Vec3::X * 2.0]);
        assert_eq!(q, Quadric::default());
    }
}
