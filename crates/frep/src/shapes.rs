//! Primitive solids and the operations of seed 000 as field builders:
//! R-function set operations with alpha, Pasko blends, offsets,
//! metamorphosis, and space mappings (affine, taper, bend, twist).
//!
//! Primitives are negated signed distances where a closed form exists
//! (sphere, box, torus, cylinder, plane), so offsets and blend parameters
//! have metric meaning; the others follow HyperFun.

use crate::capsules::CapsuleSet;
use crate::field::{Field, Node};

fn xyz() -> (Field, Field, Field) {
    (Field::x(), Field::y(), Field::z())
}

fn length3(x: &Field, y: &Field, z: &Field) -> Field {
    (x.square() + y.square() + z.square()).sqrt()
}

/// A ball of radius `r` at `c`.
pub fn sphere(c: [f64; 3], r: f64) -> Field {
    let (x, y, z) = xyz();
    r - length3(&(x - c[0]), &(y - c[1]), &(z - c[2]))
}

/// An axis-aligned box centred at `c` with half-extents `h` (exact distance).
pub fn block(c: [f64; 3], h: [f64; 3]) -> Field {
    let (x, y, z) = xyz();
    let q = [
        (x - c[0]).abs() - h[0],
        (y - c[1]).abs() - h[1],
        (z - c[2]).abs() - h[2],
    ];
    let outside = length3(&q[0].max(0.0), &q[1].max(0.0), &q[2].max(0.0));
    let inside = q[0].max(&q[1]).max(&q[2]).min(0.0);
    -(outside + inside)
}

/// A torus around the Y axis through `c`: ring radius `major`, tube `minor`.
pub fn torus(c: [f64; 3], major: f64, minor: f64) -> Field {
    let (x, y, z) = xyz();
    let (x, y, z) = (x - c[0], y - c[1], z - c[2]);
    let ring = (x.square() + z.square()).sqrt() - major;
    minor - (ring.square() + y.square()).sqrt()
}

/// A capped cylinder along Y centred at `c` (exact distance).
pub fn cylinder(c: [f64; 3], radius: f64, half_height: f64) -> Field {
    let (x, y, z) = xyz();
    let d0 = ((x - c[0]).square() + (z - c[2]).square()).sqrt() - radius;
    let d1 = (y - c[1]).abs() - half_height;
    let outside = (d0.max(0.0).square() + d1.max(0.0).square()).sqrt();
    let inside = d0.max(&d1).min(0.0);
    -(outside + inside)
}

/// A cone along Y with its apex at `apex`, opening downwards to `radius` at
/// `height` below the apex, capped there (HyperFun's cone cut by two planes).
pub fn cone(apex: [f64; 3], radius: f64, height: f64) -> Field {
    let (x, y, z) = xyz();
    let k = radius / height;
    let (x, y, z) = (x - apex[0], y - apex[1], z - apex[2]);
    let lateral = (-(&y) * k) - (x.square() + z.square()).sqrt();
    // Scaled to unit slope so it is a distance along the normal.
    let lateral = lateral / (1.0 + k * k).sqrt();
    let below_apex = -(&y);
    let above_base = y + height;
    lateral.min(below_apex).min(above_base)
}

/// An ellipsoid centred at `c` with semi-axes `r` (scaled-sphere bound).
pub fn ellipsoid(c: [f64; 3], r: [f64; 3]) -> Field {
    let (x, y, z) = xyz();
    let s = r[0].min(r[1]).min(r[2]);
    (1.0 - length3(
        &((x - c[0]) / r[0]),
        &((y - c[1]) / r[1]),
        &((z - c[2]) / r[2]),
    )) * s
}

/// `|a|^p` for p > 0, through exp and ln (zero where `a` is zero).
fn pow_abs(a: &Field, p: f64) -> Field {
    (a.abs().max(1e-300).ln() * p).exp()
}

/// Barr's superellipsoid at `c` with semi-axes `r` and exponents `e1`
/// (north-south) and `e2` (east-west): 1 is an ellipsoid, towards 0 a box.
pub fn superellipsoid(c: [f64; 3], r: [f64; 3], e1: f64, e2: f64) -> Field {
    let (x, y, z) = xyz();
    let (x, y, z) = ((x - c[0]) / r[0], (y - c[1]) / r[1], (z - c[2]) / r[2]);
    let xz = pow_abs(&(pow_abs(&x, 2.0 / e2) + pow_abs(&z, 2.0 / e2)), e2 / e1);
    1.0 - (xz + pow_abs(&y, 2.0 / e1))
}

/// The half-space behind a plane: inside where `n . p <= d` (`n` unit).
pub fn half_space(n: [f64; 3], d: f64) -> Field {
    let (x, y, z) = xyz();
    d - (x * n[0] + y * n[1] + z * n[2])
}

/// R-function union: `(f1 + f2 + sqrt(f1^2 + f2^2 - 2 a f1 f2)) / (1 + a)`;
/// `alpha = 1` is exactly `max` (and prunes in interval evaluation).
pub fn union(f1: &Field, f2: &Field, alpha: f64) -> Field {
    if alpha == 1.0 {
        return f1.max(f2);
    }
    (f1 + f2 + (f1.square() + f2.square() - f1 * f2 * (2.0 * alpha)).sqrt()) / (1.0 + alpha)
}

/// R-function intersection; `alpha = 1` is exactly `min`.
pub fn intersection(f1: &Field, f2: &Field, alpha: f64) -> Field {
    if alpha == 1.0 {
        return f1.min(f2);
    }
    (f1 + f2 - (f1.square() + f2.square() - f1 * f2 * (2.0 * alpha)).sqrt()) / (1.0 + alpha)
}

/// `f1` minus `f2`.
pub fn subtraction(f1: &Field, f2: &Field, alpha: f64) -> Field {
    intersection(f1, &-f2, alpha)
}

/// Pasko's blending displacement `a0 / (1 + (f1/a1)^2 + (f2/a2)^2)`.
fn displacement(f1: &Field, f2: &Field, a: [f64; 3]) -> Field {
    a[0] / (1.0 + (f1 / a[1]).square() + (f2 / a[2]).square())
}

/// Blended union (HyperFun `blendUni`, alpha 0): `a = [a0, a1, a2]`, a0 the
/// amount of added material, a1 and a2 its reach along each solid.
pub fn blend_union(f1: &Field, f2: &Field, a: [f64; 3]) -> Field {
    union(f1, f2, 0.0) + displacement(f1, f2, a)
}

/// Blended intersection (HyperFun `blendInt`).
pub fn blend_intersection(f1: &Field, f2: &Field, a: [f64; 3]) -> Field {
    intersection(f1, f2, 0.0) + displacement(f1, f2, a)
}

/// Blended subtraction: `f1` minus `f2` with a blend along the cut.
pub fn blend_subtraction(f1: &Field, f2: &Field, a: [f64; 3]) -> Field {
    blend_intersection(f1, &-f2, a)
}

/// Bounded blending (after Pasko, Pasko and Kunii 2005): a blended union or
/// intersection whose added material is confined to the bounding solid `f3`.
/// With `r1 = (f1/a1)^2 + (f2/a2)^2` and `r2 = (max(f3, 0)/a3)^2`, the
/// displacement `a0 (1 - r)^2 / (1 + r)` with `r = r1 / (r1 + r2)` vanishes
/// outside `f3` (where the result is exactly the plain R-function operation)
/// and fades continuously to zero at its surface.
pub fn bounded_blend(f1: &Field, f2: &Field, f3: &Field, a: [f64; 4], union_op: bool) -> Field {
    let r1 = (f1 / a[1]).square() + (f2 / a[2]).square();
    let r2 = (f3.max(0.0) / a[3]).square();
    let r = 1.0 - &r2 / (&r1 + &r2 + 1e-300);
    let disp = a[0] * (1.0 - &r).max(0.0).square() / (1.0 + &r);
    let base = if union_op {
        union(f1, f2, 0.0)
    } else {
        intersection(f1, f2, 0.0)
    };
    base + disp
}

/// The union (exact max) of any number of solids; None when there are none.
pub fn union_all(solids: impl IntoIterator<Item = Field>) -> Option<Field> {
    // A balanced tree, not a chain: interval pruning decides a subtree at
    // once, and the tape's depth stays logarithmic.
    let mut level: Vec<Field> = solids.into_iter().collect();
    while level.len() > 1 {
        level = level
            .chunks(2)
            .map(|pair| match pair {
                [a, b] => a.max(b),
                [a] => a.clone(),
                _ => unreachable!("chunks of two"),
            })
            .collect();
    }
    level.pop()
}

/// Grows (d > 0) or shrinks (d < 0) a solid by `d` (exact for distance fields).
pub fn offset(f: &Field, d: f64) -> Field {
    f + d
}

/// Metamorphosis: `(1 - t) f1 + t f2`, any topologies.
pub fn morph(f1: &Field, f2: &Field, t: f64) -> Field {
    f1 * (1.0 - t) + f2 * t
}

impl Field {
    /// The field with x, y and z replaced by other fields (space mapping):
    /// `f.remap(gx, gy, gz)(p) = f(gx(p), gy(p), gz(p))`.
    pub fn remap(&self, x: &Field, y: &Field, z: &Field) -> Field {
        self.fold(
            |_| true,
            |f, get: &dyn Fn(&Field) -> Field| match f.node() {
                Node::X => x.clone(),
                Node::Y => y.clone(),
                Node::Z => z.clone(),
                Node::Const(_) => f.clone(),
                Node::Unary(op, a) => get(a).unary(*op),
                Node::Binary(op, a, b) => get(a).binary(*op, get(b)),
                Node::Dataset(set, args) => Field::dataset_at(set, args.each_ref().map(get)),
            },
        )
    }

    /// The solid moved by the affine map `p -> M p + t` (given as the inverse
    /// map's rows `inv` and offset: a point p samples the original at `inv * p + o`).
    pub fn affine_inverse(&self, inv: [[f64; 3]; 3], o: [f64; 3]) -> Field {
        let (x, y, z) = xyz();
        let row = |r: [f64; 3], o: f64| &x * r[0] + &y * r[1] + &z * r[2] + o;
        self.remap(&row(inv[0], o[0]), &row(inv[1], o[1]), &row(inv[2], o[2]))
    }

    /// The solid moved by the affine map `m` (None when `m` is not invertible).
    pub fn transformed(&self, m: &geode_geo::glam::DMat4) -> Option<Field> {
        let inv = m.inverse();
        if !inv.is_finite() {
            return None;
        }
        // A point p of the result samples the original at m^-1 p.
        let rows = [inv.row(0), inv.row(1), inv.row(2)];
        Some(self.affine_inverse(rows.map(|r| [r.x, r.y, r.z]), rows.map(|r| r.w)))
    }

    pub fn translate(&self, t: [f64; 3]) -> Field {
        self.affine_inverse(
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            [-t[0], -t[1], -t[2]],
        )
    }

    /// Scales x and z by a factor varying linearly with y from `s0` at
    /// `y0` to `s1` at `y1` (seed 000's taper along an axis).
    pub fn taper_y(&self, y0: f64, y1: f64, s0: f64, s1: f64) -> Field {
        let (x, y, z) = xyz();
        let t = ((&y - y0) / (y1 - y0)).max(0.0).min(1.0);
        let s = s0 + t * (s1 - s0);
        self.remap(&(&x / &s), &y, &(&z / &s))
    }

    /// Twists about the Y axis by `rate` radians per unit of y.
    pub fn twist_y(&self, rate: f64) -> Field {
        let (x, y, z) = xyz();
        let a = &y * -rate;
        let (c, s) = (a.cos(), a.sin());
        self.remap(&(&x * &c - &z * &s), &y, &(&x * &s + &z * &c))
    }

    /// Deform point (seed 000): pushes space near `center` by `offset`, with a
    /// smooth falloff `(1 - (d/radius)^2)^2` that is 1 at the centre and 0 from
    /// `radius` on (the inverse map is approximated by sampling backwards).
    pub fn deform_point(&self, center: [f64; 3], offset: [f64; 3], radius: f64) -> Field {
        let (x, y, z) = xyz();
        let d2 = (&x - center[0]).square() + (&y - center[1]).square() + (&z - center[2]).square();
        let w = (1.0 - d2 / (radius * radius)).max(0.0).square();
        self.remap(
            &(&x - &w * offset[0]),
            &(&y - &w * offset[1]),
            &(&z - &w * offset[2]),
        )
    }

    /// Bends the solid around the Z axis: the X axis becomes an arc of
    /// radius `radius` (the bend of HyperFun, angle grows with x).
    pub fn bend_x(&self, radius: f64) -> Field {
        let (x, y, z) = xyz();
        // Polar coordinates about the bend centre (0, radius): the angle maps
        // back to x along the arc, the distance to y.
        let dy = &y - radius;
        let theta = x.atan2(-&dy);
        let r = (x.square() + dy.square()).sqrt();
        self.remap(&(theta * radius), &(radius - r), &z)
    }
}

/// A sphere swept along a polyline: the union of capsules, each segment's
/// radius interpolated linearly between its end points' radii.
pub fn sphere_sweep(points: &[[f64; 3]], radii: &[f64]) -> Option<Field> {
    CapsuleSet::new(&CapsuleSet::polyline_segments(points, radii)).map(Field::capsules)
}

/// The exact solid a tagged mesh primitive approximates, in its local frame
/// (see `geode_geo::analytic`).
pub fn analytic(shape: &geode_geo::analytic::AnalyticShape) -> Field {
    use geode_geo::analytic::AnalyticShape as S;
    match *shape {
        S::Box { size } => block([0.0; 3], size.map(|s| 0.5 * s as f64)),
        S::Sphere { radius } => sphere([0.0; 3], radius as f64),
        S::Torus { major, minor } => torus([0.0; 3], major as f64, minor as f64),
        S::Tube { radius, y0, y1 } => cylinder(
            [0.0, 0.5 * (y0 as f64 + y1 as f64), 0.0],
            radius as f64,
            0.5 * (y1 as f64 - y0 as f64).abs(),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(f: &Field, p: [f64; 3]) -> f64 {
        f.eval_tree(p)
    }

    #[test]
    fn primitives_are_distances() {
        let s = sphere([1.0, 0.0, 0.0], 2.0);
        assert!((at(&s, [1.0, 0.0, 0.0]) - 2.0).abs() < 1e-12);
        assert!((at(&s, [4.0, 0.0, 0.0]) + 1.0).abs() < 1e-12);
        let b = block([0.0; 3], [1.0, 2.0, 3.0]);
        assert!(
            (at(&b, [0.0; 3]) - 1.0).abs() < 1e-12,
            "inside: distance to the nearest face"
        );
        assert!(
            (at(&b, [2.0, 3.0, 0.0]) + 2f64.sqrt()).abs() < 1e-12,
            "outside a corner edge"
        );
        let t = torus([0.0; 3], 2.0, 0.5);
        assert!((at(&t, [2.0, 0.0, 0.0]) - 0.5).abs() < 1e-12);
        assert!((at(&t, [0.0, 0.0, 0.0]) + 1.5).abs() < 1e-12);
        let c = cylinder([0.0; 3], 1.0, 2.0);
        assert!((at(&c, [0.0, 1.5, 0.0]) - 0.5).abs() < 1e-12);
        let cone = cone([0.0, 1.0, 0.0], 1.0, 2.0);
        assert!(at(&cone, [0.0, 0.5, 0.0]) > 0.0 && at(&cone, [0.9, 0.5, 0.0]) < 0.0);
        let e = ellipsoid([0.0; 3], [2.0, 1.0, 1.0]);
        assert!(at(&e, [1.9, 0.0, 0.0]) > 0.0 && at(&e, [0.0, 1.1, 0.0]) < 0.0);
        let se = superellipsoid([0.0; 3], [1.0; 3], 0.1, 0.1);
        assert!(
            at(&se, [0.9, 0.9, 0.9]) > 0.0,
            "a rounded box holds its corners"
        );
        let round = superellipsoid([0.0; 3], [1.0; 3], 1.0, 1.0);
        assert!(
            (at(&round, [0.5, 0.0, 0.0]) - 0.75).abs() < 1e-9,
            "e = 1 is the quadric 1 - r^2"
        );
        let h = half_space([0.0, 1.0, 0.0], 1.0);
        assert_eq!(at(&h, [5.0, 0.0, 0.0]), 1.0);
    }

    #[test]
    fn r_functions_keep_the_set_and_alpha_one_is_min_max() {
        let a = sphere([0.0; 3], 1.0);
        let b = sphere([1.2, 0.0, 0.0], 1.0);
        let mut s: u64 = 7;
        for _ in 0..2000 {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let p = [
                (s >> 11) as f64 / (1u64 << 53) as f64 * 5.0 - 2.0,
                ((s >> 20) % 1000) as f64 / 250.0 - 2.0,
                0.1,
            ];
            let (fa, fb) = (at(&a, p), at(&b, p));
            for alpha in [0.0, 0.5] {
                assert_eq!(
                    at(&union(&a, &b, alpha), p) >= 0.0,
                    fa.max(fb) >= 0.0 || fa.max(fb).abs() < 1e-12
                );
                assert_eq!(
                    at(&intersection(&a, &b, alpha), p) >= 0.0,
                    fa.min(fb) >= 0.0 || fa.min(fb).abs() < 1e-12
                );
                assert_eq!(
                    at(&subtraction(&a, &b, alpha), p) >= 0.0,
                    fa.min(-fb) >= 0.0 || fa.min(-fb).abs() < 1e-12
                );
            }
            assert_eq!(at(&union(&a, &b, 1.0), p), fa.max(fb));
            assert_eq!(at(&intersection(&a, &b, 1.0), p), fa.min(fb));
        }
    }

    #[test]
    fn blends_add_material_near_both_surfaces_only() {
        let a = sphere([0.0; 3], 1.0);
        let b = sphere([2.5, 0.0, 0.0], 1.0);
        let u = union(&a, &b, 0.0);
        let bl = blend_union(&a, &b, [1.0, 1.0, 1.0]);
        let mid = [1.25, 0.0, 0.0];
        assert!(
            at(&u, mid) < 0.0 && at(&bl, mid) > 0.0,
            "the bridge fills the gap"
        );
        let far = [0.0, -5.0, 0.0];
        assert!(
            (at(&bl, far) - at(&u, far)).abs() < 0.05,
            "little effect far away"
        );
        let cut = blend_subtraction(&a, &b, [0.5, 1.0, 1.0]);
        assert!(at(&cut, [0.0; 3]) > 0.0);
    }

    #[test]
    fn bounded_blend_stays_inside_its_bounding_solid() {
        let a = sphere([-0.6, 0.0, 0.0], 0.5);
        let b = sphere([0.6, 0.0, 0.0], 0.5);
        let bound = sphere([0.0, 0.0, 0.0], 0.4);
        let bb = bounded_blend(&a, &b, &bound, [1.0, 0.5, 0.5, 0.5], true);
        let plain = union(&a, &b, 0.0);
        // Outside the bounding solid: exactly the plain union.
        for p in [[0.0, 0.6, 0.0], [-1.0, 0.3, 0.2], [0.9, -0.5, 0.0]] {
            assert_eq!(at(&bb, p), at(&plain, p), "{p:?}");
        }
        // Inside it: material is added (the gap between the spheres fills).
        assert!(at(&plain, [0.0; 3]) < 0.0 && at(&bb, [0.0; 3]) > 0.0);
        // Continuous across the bounding surface.
        let (inside, outside) = (at(&bb, [0.0, 0.399999, 0.0]), at(&bb, [0.0, 0.400001, 0.0]));
        assert!((inside - outside).abs() < 1e-4);
    }

    #[test]
    fn sweeps_and_point_deformation() {
        let s = sphere_sweep(
            &[[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
            &[0.1, 0.3, 0.2],
        )
        .unwrap();
        assert!(
            (at(&s, [0.5, 0.0, 0.0]) - 0.2).abs() < 1e-12,
            "radius interpolated mid-segment"
        );
        assert!((at(&s, [1.0, 0.5, 0.6]) - (0.25 - 0.6)).abs() < 1e-12);
        assert!(at(&s, [0.5, 0.5, 0.0]) < 0.0);
        let b = sphere([0.0; 3], 0.5);
        let pushed = b.deform_point([0.5, 0.0, 0.0], [0.3, 0.0, 0.0], 0.4);
        assert!(
            at(&b, [0.6, 0.0, 0.0]) < 0.0 && at(&pushed, [0.6, 0.0, 0.0]) > 0.0,
            "the bump reaches out"
        );
        assert_eq!(
            at(&pushed, [-0.5, 0.0, 0.0]),
            at(&b, [-0.5, 0.0, 0.0]),
            "untouched far away"
        );
    }

    #[test]
    fn offset_and_morph() {
        let s = sphere([0.0; 3], 1.0);
        assert!((at(&offset(&s, 0.5), [1.4, 0.0, 0.0]) - 0.1).abs() < 1e-12);
        let t = torus([0.0; 3], 1.0, 0.25);
        let m = morph(&s, &t, 0.5);
        assert!((at(&m, [0.0; 3]) - 0.5 * (1.0 + (-0.75))).abs() < 1e-12);
    }

    #[test]
    fn space_mappings() {
        let b = block([0.0; 3], [0.5, 1.0, 0.5]);
        let moved = b.translate([3.0, 0.0, 0.0]);
        assert!((at(&moved, [3.0, 0.0, 0.0]) - at(&b, [0.0; 3])).abs() < 1e-12);
        // Taper halves the section at the top.
        let tp = b.taper_y(-1.0, 1.0, 1.0, 0.5);
        assert!(at(&tp, [0.45, -0.99, 0.0]) > 0.0 && at(&tp, [0.45, 0.99, 0.0]) < 0.0);
        // Twist by 90 degrees per unit: at y = 1 a point on the box's +X face
        // comes from the +Z side, and the distance to the axis is unchanged.
        let long = block([0.0; 3], [0.2, 2.0, 0.6]);
        let tw = long.twist_y(std::f64::consts::FRAC_PI_2);
        assert!(at(&tw, [0.55, 1.0, 0.0]) > 0.0 && at(&long, [0.55, 1.0, 0.0]) < 0.0);
        // Bend: a straight bar along X follows a circle of the bend radius.
        let bar = block([0.0; 3], [3.0, 0.1, 0.1]);
        let bent = bar.bend_x(2.0);
        let a = 1.0f64; // one radian along the arc
        let p = [2.0 * a.sin(), 2.0 - 2.0 * a.cos(), 0.0];
        assert!(at(&bent, p) > 0.05, "the arc stays inside");
        assert!(
            at(&bent, [2.0, 0.0, 0.0]) < 0.0,
            "the straight line does not"
        );
    }
}
