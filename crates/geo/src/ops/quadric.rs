//! Area-weighted plane quadrics (Garland and Heckbert): the summed squared
//! distance of a point to a set of planes, divided by their total area, so a
//! vertex's error reads as the mean squared distance to the surface it stands
//! for (in model units squared).

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
    /// The plane through a triangle, weighted by its area (zero for a
    /// degenerate triangle, which then adds nothing).
    pub fn of_triangle(p: [Vec3; 3]) -> Quadric {
        let [a, b, c] = p.map(|v| v.as_dvec3());
        let cross = (b - a).cross(c - a);
        let len = cross.length();
        if !(len > 0.0 && len.is_finite()) {
            return Quadric::default();
        }
        let n = cross / len;
        let area = 0.5 * len;
        let d = -n.dot(a);
        Quadric {
            a: [
                area * n.x * n.x,
                area * n.x * n.y,
                area * n.x * n.z,
                area * n.y * n.y,
                area * n.y * n.z,
                area * n.z * n.z,
            ],
            b: [area * n.x * d, area * n.y * d, area * n.z * d],
            c: area * d * d,
            weight: area,
        }
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
        let p = p.as_dvec3();
        let [xx, xy, xz, yy, yz, zz] = self.a;
        let ap = DVec3::new(
            xx * p.x + xy * p.y + xz * p.z,
            xy * p.x + yy * p.y + yz * p.z,
            xz * p.x + yz * p.y + zz * p.z,
        );
        let b = DVec3::from_array(self.b);
        (p.dot(ap) + 2.0 * b.dot(p) + self.c).max(0.0)
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
    fn degenerate_triangles_add_nothing() {
        let q = Quadric::of_triangle([Vec3::ZERO, Vec3::X, Vec3::X * 2.0]);
        assert_eq!(q, Quadric::default());
    }
}
