//! Plane quadrics for edge collapse (Garland and Heckbert), in f64, with
//! the optimal placement `geode_geo::ops::Quadric` lacks: that one answers
//! a distance bound for its caller's half-edge collapses; this one also
//! solves for the point that minimises the error. Planes are weighted by
//! area (a triangle's) or by a constraint's chosen weight, and the weights'
//! sum is kept so an error reads as a mean squared distance.

use geode_geo::glam::DVec3;

/// Σ w (n·p + d)², as `pᵀ A p + 2 bᵀ p + c`, and Σ w.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Quadric {
    /// Upper triangle of A: xx, xy, xz, yy, yz, zz.
    a: [f64; 6],
    b: [f64; 3],
    c: f64,
    pub weight: f64,
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

    /// The plane of triangle `p`, weighted by its area (nothing for a
    /// degenerate triangle).
    pub fn triangle(p: [DVec3; 3]) -> Quadric {
        let cross = (p[1] - p[0]).cross(p[2] - p[0]);
        let len = cross.length();
        if !(len > 0.0 && len.is_finite()) {
            return Quadric::default();
        }
        Quadric::plane(cross / len, p[0], 0.5 * len)
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

    pub fn sum(mut self, o: &Quadric) -> Quadric {
        self.add(o);
        self
    }

    /// The weighted sum of squared distances from `p` to the planes.
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn three_planes_meet_at_their_corner() {
        let mut q = Quadric::plane(DVec3::X, DVec3::new(1.0, 0.0, 0.0), 1.0);
        q.add(&Quadric::plane(DVec3::Y, DVec3::new(0.0, 2.0, 0.0), 2.0));
        q.add(&Quadric::plane(DVec3::Z, DVec3::new(0.0, 0.0, -3.0), 0.5));
        let p = q.minimizer().unwrap();
        assert!((p - DVec3::new(1.0, 2.0, -3.0)).length() < 1e-12);
        assert!(q.eval(p) < 1e-12);
        assert!((q.eval(DVec3::new(1.0, 2.0, -2.0)) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn parallel_planes_have_no_single_minimiser() {
        let mut q = Quadric::plane(DVec3::Z, DVec3::ZERO, 1.0);
        q.add(&Quadric::plane(DVec3::Z, DVec3::Z, 1.0));
        assert!(q.minimizer().is_none());
    }
}
