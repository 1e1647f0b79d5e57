//! Exact orientation predicates for f32 coordinates: a floating-point
//! filter (Shewchuk's first-stage error bounds) and, when it cannot
//! decide, the determinant summed exactly.
//!
//! The exact stage uses that geode's coordinates are f32: a product of
//! two of them is exact in f64 (48 bits of 53), and a product of three is
//! exact as two f64s (the 48-bit product split in halves, each times the
//! third coordinate exactly). The determinant,
//! expanded over the raw coordinates into 24 (3D) or 6 (2D) such products,
//! is then summed without error as a floating-point expansion (Shewchuk's
//! Grow-Expansion, zeros eliminated); its largest component carries the
//! sign.

use std::cmp::Ordering;

use geode_geo::glam::{DVec3, Vec3};

/// Half an ulp of 1.0 in f64.
const EPS: f64 = 1.0 / (1u64 << 53) as f64;
const O3D_BOUND: f64 = (7.0 + 56.0 * EPS) * EPS;
const O2D_BOUND: f64 = (3.0 + 16.0 * EPS) * EPS;

/// The sign of `(b - a) x (c - a) · (d - a)`: positive when `d` lies on the
/// side of the plane `abc` that `(b - a) x (c - a)` points to.
pub fn orient3d(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> Ordering {
    // Differences in f64 (rounded when exponents differ widely; the bound
    // covers that, as in Shewchuk's orient3d).
    let (a64, b64, c64, d64) = (a.as_dvec3(), b.as_dvec3(), c.as_dvec3(), d.as_dvec3());
    let (ba, ca, da) = (b64 - a64, c64 - a64, d64 - a64);
    let (m1, m2) = (ca.y * da.z, ca.z * da.y);
    let (m3, m4) = (ca.z * da.x, ca.x * da.z);
    let (m5, m6) = (ca.x * da.y, ca.y * da.x);
    let det = ba.x * (m1 - m2) + ba.y * (m3 - m4) + ba.z * (m5 - m6);
    let permanent = ba.x.abs() * (m1.abs() + m2.abs())
        + ba.y.abs() * (m3.abs() + m4.abs())
        + ba.z.abs() * (m5.abs() + m6.abs());
    let bound = O3D_BOUND * permanent;
    if det > bound {
        return Ordering::Greater;
    }
    if -det > bound {
        return Ordering::Less;
    }
    orient3d_exact(a, b, c, d)
}

/// A triangle's plane prepared for many [`orient3d`] tests against it
/// (its edges' 2x2 minors computed once): `orient(d)` is
/// `orient3d(a, b, c, d)`, the determinant expanded along `d - a`'s row
/// (the same products, so the same error bound).
#[derive(Clone, Copy, Debug)]
pub struct Plane {
    v: [Vec3; 3],
    a: DVec3,
    /// `(b - a) x (c - a)`.
    normal: DVec3,
    /// Per component, the minor's two products' magnitudes summed.
    magnitude: DVec3,
}

impl Plane {
    pub fn new(a: Vec3, b: Vec3, c: Vec3) -> Plane {
        let a64 = a.as_dvec3();
        let (ba, ca) = (b.as_dvec3() - a64, c.as_dvec3() - a64);
        let products = [
            (ba.y * ca.z, ba.z * ca.y),
            (ba.z * ca.x, ba.x * ca.z),
            (ba.x * ca.y, ba.y * ca.x),
        ];
        Plane {
            v: [a, b, c],
            a: a64,
            normal: DVec3::from(products.map(|(p, q)| p - q)),
            magnitude: DVec3::from(products.map(|(p, q)| p.abs() + q.abs())),
        }
    }

    /// `(b - a) x (c - a)` in f64 (rounded).
    pub fn normal(&self) -> DVec3 {
        self.normal
    }

    pub fn orient(&self, d: Vec3) -> Ordering {
        let da = d.as_dvec3() - self.a;
        let det = da.dot(self.normal);
        let bound = O3D_BOUND * da.abs().dot(self.magnitude);
        if det > bound {
            Ordering::Greater
        } else if -det > bound {
            Ordering::Less
        } else {
            orient3d_exact(self.v[0], self.v[1], self.v[2], d)
        }
    }
}

/// [`orient3d`] by exact summation alone.
pub fn orient3d_exact(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> Ordering {
    // orient = -det4 | x y z 1 | over rows a, b, c, d; det4 expands along
    // its column of ones into the 3x3 determinants of the other rows.
    let rows = [a, b, c, d].map(|p| p.to_array().map(f64::from));
    let mut sum = Expansion::<48>::new();
    for skip in 0..4 {
        // Cofactor sign of the 1 in row `skip`, column 3; orient is -det4.
        let sign = if (skip + 3) % 2 == 0 { -1.0 } else { 1.0 };
        let r: Vec<[f64; 3]> = (0..4).filter(|&i| i != skip).map(|i| rows[i]).collect();
        for (p, s) in PERMUTATIONS3 {
            let xy = r[0][p[0]] * r[1][p[1]];
            let (hi, lo) = two_product(xy, r[2][p[2]]);
            sum.add(sign * s * hi);
            sum.add(sign * s * lo);
        }
    }
    sum.sign()
}

/// The permutations of three columns and their signs.
const PERMUTATIONS3: [([usize; 3], f64); 6] = [
    ([0, 1, 2], 1.0),
    ([1, 2, 0], 1.0),
    ([2, 0, 1], 1.0),
    ([0, 2, 1], -1.0),
    ([2, 1, 0], -1.0),
    ([1, 0, 2], -1.0),
];

/// The sign of `(b - a) x (c - a)` for 2D points of f32 coordinates.
pub fn orient2d(a: [f32; 2], b: [f32; 2], c: [f32; 2]) -> Ordering {
    let [a, b, c] = [a, b, c].map(|p| p.map(f64::from));
    let l = (b[0] - a[0]) * (c[1] - a[1]);
    let r = (b[1] - a[1]) * (c[0] - a[0]);
    let det = l - r;
    let bound = O2D_BOUND * (l.abs() + r.abs());
    if det > bound {
        return Ordering::Greater;
    }
    if -det > bound {
        return Ordering::Less;
    }
    // det = ax by - ax cy - bx ay + bx cy + cx ay - cx by, each product exact.
    let mut sum = Expansion::<6>::new();
    for t in [
        a[0] * b[1],
        -(a[0] * c[1]),
        -(b[0] * a[1]),
        b[0] * c[1],
        c[0] * a[1],
        -(c[0] * b[1]),
    ] {
        sum.add(t);
    }
    sum.sign()
}

fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let x = a + b;
    let bv = x - a;
    let av = x - bv;
    (x, (a - av) + (b - bv))
}

/// `a b` as two f64s summing to it exactly, for `a` of at most 48
/// significant bits and `b` an f32 (as the exact stage's products are):
/// Veltkamp's split cuts `a` into halves of 26 and 27 bits, whose
/// products with `b` are exact. (An FMA would do it in one step, but
/// without `target-cpu` it is a slow library call.)
fn two_product(a: f64, b: f64) -> (f64, f64) {
    const SPLITTER: f64 = (1u64 << 27) as f64 + 1.0;
    let c = SPLITTER * a;
    let hi = c - (c - a);
    let lo = a - hi;
    let (p, q) = (hi * b, lo * b);
    let (s, e) = two_sum(p, q);
    (s, e)
}

/// A nonoverlapping expansion of at most `N` components, increasing in
/// magnitude, zeros eliminated: an exact sum of up to `N` f64s, on the
/// stack (degenerate inputs take the exact path at every test).
struct Expansion<const N: usize> {
    e: [f64; N],
    len: usize,
}

impl<const N: usize> Expansion<N> {
    fn new() -> Self {
        Expansion {
            e: [0.0; N],
            len: 0,
        }
    }

    /// Adds `b` exactly (Shewchuk's Grow-Expansion).
    fn add(&mut self, b: f64) {
        let mut q = b;
        let mut k = 0;
        for i in 0..self.len {
            let (s, h) = two_sum(q, self.e[i]);
            q = s;
            if h != 0.0 {
                self.e[k] = h;
                k += 1;
            }
        }
        if q != 0.0 {
            self.e[k] = q;
            k += 1;
        }
        self.len = k;
    }

    /// The sum's sign: its largest component's.
    fn sign(&self) -> Ordering {
        match self.len {
            0 => Ordering::Equal,
            n => self.e[n - 1].total_cmp(&0.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geode_geo::random::unit;

    #[test]
    fn the_filter_and_the_exact_sum_agree() {
        for i in 0..20000u64 {
            let p = |k: u64| {
                Vec3::new(
                    unit(1, i, 3 * k),
                    unit(1, i, 3 * k + 1),
                    unit(1, i, 3 * k + 2),
                )
            };
            let (a, b, c, mut d) = (p(0), p(1), p(2), p(3));
            if i % 2 == 0 {
                // Nearly on the plane: the filter often defers.
                d = a + (b - a) * unit(2, i, 0) + (c - a) * unit(2, i, 1);
            }
            assert_eq!(orient3d(a, b, c, d), orient3d_exact(a, b, c, d), "{i}");
            assert_eq!(
                Plane::new(a, b, c).orient(d),
                orient3d_exact(a, b, c, d),
                "{i}"
            );
        }
        let (o, x, y, z) = (Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z);
        assert_eq!(orient3d(o, x, y, z), Ordering::Greater);
        assert_eq!(orient3d_exact(o, y, x, z), Ordering::Less);
        assert_eq!(orient3d_exact(o, x, y, x + y), Ordering::Equal);
    }

    #[test]
    fn coplanar_points_off_the_axes_are_exactly_coplanar() {
        // Points with exact f32 coordinates on the plane x + 2y - z = 0.
        let p = |x: f32, y: f32| Vec3::new(x, y, x + 2.0 * y);
        let (a, b, c) = (p(0.5, 0.75), p(-3.25, 0.5), p(1.0e3, -2.0));
        for i in 0..100 {
            let d = p(i as f32 * 0.375, 1.0 - i as f32 * 0.125);
            assert_eq!(orient3d(a, b, c, d), Ordering::Equal);
        }
        assert_eq!(
            orient2d([0.0, 0.0], [1.0, 1.0], [3.0, 3.0]),
            Ordering::Equal
        );
        assert_eq!(
            orient2d([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]),
            Ordering::Greater
        );
    }
}
