//! Curve shapes sampled with their exact unit tangents: line, arc or circle,
//! helix, (p, q) torus knot (the trefoil is (2, 3)), and curves through
//! given points by centripetal Catmull-Rom or cubic B-spline.

use crate::polyline::glam_d::DVec3;

/// Points of a curve with the exact unit tangent at each (for frames of
/// fourth order); `closed` curves do not repeat their first point.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sampled {
    pub points: Vec<DVec3>,
    pub tangents: Vec<DVec3>,
    pub closed: bool,
}

impl Sampled {
    fn from_fn(n: usize, closed: bool, f: impl Fn(f64) -> (DVec3, DVec3)) -> Sampled {
        let n = n.max(2);
        // A closed curve's last sample would repeat its first.
        let denom = if closed { n } else { n - 1 } as f64;
        let (points, tangents) = (0..n)
            .map(|i| {
                let (p, d) = f(i as f64 / denom);
                (p, d.normalize_or_zero())
            })
            .unzip();
        Sampled {
            points,
            tangents,
            closed,
        }
    }
}

/// A straight line from `a` to `b` with `n` points.
pub fn line(a: DVec3, b: DVec3, n: usize) -> Sampled {
    Sampled::from_fn(n, false, |t| (a.lerp(b, t), b - a))
}

/// An arc in the XZ plane about the centre, from `start` to `end` radians
/// (counter-clockwise seen from +Y); a full turn is a closed circle.
pub fn arc(radius: f64, start: f64, end: f64, n: usize) -> Sampled {
    let full = ((end - start).abs() - std::f64::consts::TAU).abs() < 1e-9;
    Sampled::from_fn(n, full, |t| {
        let a = start + (end - start) * t;
        (
            DVec3::new(radius * a.cos(), 0.0, -radius * a.sin()),
            DVec3::new(-a.sin(), 0.0, -a.cos()) * (end - start).signum(),
        )
    })
}

/// A helix about +Y: `turns` turns rising `pitch` per turn.
pub fn helix(radius: f64, pitch: f64, turns: f64, n: usize) -> Sampled {
    let tau = std::f64::consts::TAU;
    Sampled::from_fn(n, false, |t| {
        let a = tau * turns * t;
        (
            DVec3::new(radius * a.cos(), pitch * turns * t, radius * a.sin()),
            DVec3::new(-radius * a.sin() * tau, pitch, radius * a.cos() * tau),
        )
    })
}

/// A (p, q) torus knot on a torus of radii `major` and `minor` about +Y:
/// winds `p` times around the axis and `q` times through the hole.
pub fn torus_knot(p: u32, q: u32, major: f64, minor: f64, n: usize) -> Sampled {
    let (p, q) = (p as f64, q as f64);
    Sampled::from_fn(n, true, |t| {
        let a = std::f64::consts::TAU * t;
        let r = major + minor * (q * a).cos();
        let dr = -minor * q * (q * a).sin();
        let (s, c) = (p * a).sin_cos();
        (
            DVec3::new(r * c, minor * (q * a).sin(), r * s),
            DVec3::new(
                dr * c - r * p * s,
                minor * q * (q * a).cos(),
                dr * s + r * p * c,
            ),
        )
    })
}

/// Index of the control point `i` (may run off either end): wraps when
/// closed, clamps when open.
fn at(points: &[DVec3], i: isize, closed: bool) -> DVec3 {
    let n = points.len() as isize;
    if closed {
        points[i.rem_euclid(n) as usize]
    } else if i < 0 {
        // Reflected phantom point: the end tangent follows the first chord.
        2.0 * points[0] - points[1.min(n - 1) as usize]
    } else if i >= n {
        2.0 * points[(n - 1) as usize] - points[(n - 2).max(0) as usize]
    } else {
        points[i as usize]
    }
}

/// Centripetal (alpha 0.5; 0 uniform, 1 chordal) Catmull-Rom through
/// `points`, `per_segment` samples per span; passes through every point.
pub fn catmull_rom(points: &[DVec3], closed: bool, per_segment: usize, alpha: f64) -> Sampled {
    let mut out = Sampled {
        closed,
        ..Sampled::default()
    };
    if points.len() < 2 {
        out.points = points.to_vec();
        out.tangents = vec![DVec3::ZERO; points.len()];
        return out;
    }
    let per = per_segment.max(1);
    let spans = if closed {
        points.len()
    } else {
        points.len() - 1
    };
    for s in 0..spans as isize {
        let p = [
            at(points, s - 1, closed),
            at(points, s, closed),
            at(points, s + 1, closed),
            at(points, s + 2, closed),
        ];
        // Knot spacing |P_i+1 - P_i|^alpha, guarded against repeated points.
        let d = |a: DVec3, b: DVec3| a.distance(b).powf(alpha).max(1e-12);
        let (d0, d1, d2) = (d(p[0], p[1]), d(p[1], p[2]), d(p[2], p[3]));
        // Tangents of the equivalent cubic Hermite span on [0, 1].
        let m1 = d1 * ((p[1] - p[0]) / d0 - (p[2] - p[0]) / (d0 + d1) + (p[2] - p[1]) / d1);
        let m2 = d1 * ((p[2] - p[1]) / d1 - (p[3] - p[1]) / (d1 + d2) + (p[3] - p[2]) / d2);
        let last = !closed && s as usize == spans - 1;
        let count = if last { per + 1 } else { per };
        for k in 0..count {
            let u = k as f64 / per as f64;
            let (u2, u3) = (u * u, u * u * u);
            let pos = (2.0 * u3 - 3.0 * u2 + 1.0) * p[1]
                + (u3 - 2.0 * u2 + u) * m1
                + (-2.0 * u3 + 3.0 * u2) * p[2]
                + (u3 - u2) * m2;
            let der = (6.0 * u2 - 6.0 * u) * p[1]
                + (3.0 * u2 - 4.0 * u + 1.0) * m1
                + (-6.0 * u2 + 6.0 * u) * p[2]
                + (3.0 * u2 - 2.0 * u) * m2;
            out.points.push(pos);
            out.tangents.push(der.normalize_or_zero());
        }
    }
    out
}

/// A uniform cubic B-spline with `points` as control points, clamped to
/// its end points when open, periodic when closed; `per_segment` samples
/// per knot span. Smooth (C2) but passes through the ends only.
pub fn bspline(points: &[DVec3], closed: bool, per_segment: usize) -> Sampled {
    let mut out = Sampled {
        closed,
        ..Sampled::default()
    };
    let n = points.len();
    if n < 2 {
        out.points = points.to_vec();
        out.tangents = vec![DVec3::ZERO; n];
        return out;
    }
    let per = per_segment.max(1);
    let degree = 3.min(n - 1);
    // Knots: periodic uniform when closed; clamped uniform when open.
    let (ctrl, knots): (Vec<DVec3>, Vec<f64>) = if closed {
        let ctrl: Vec<DVec3> = (0..n + degree).map(|i| points[i % n]).collect();
        let knots = (0..ctrl.len() + degree + 1).map(|i| i as f64).collect();
        (ctrl, knots)
    } else {
        let inner = n - degree;
        let mut k = vec![0.0; degree + 1];
        k.extend((1..inner).map(|i| i as f64));
        k.extend(std::iter::repeat_n(inner as f64, degree + 1));
        (points.to_vec(), k)
    };
    let (lo, hi) = (knots[degree], knots[ctrl.len()]);
    let spans = (hi - lo).round() as usize;
    let total = if closed { spans * per } else { spans * per + 1 };
    for i in 0..total {
        let u = lo + (hi - lo) * i as f64 / (spans * per) as f64;
        let (p, d) = de_boor(&ctrl, &knots, degree, u.min(hi - 1e-12 * (hi - lo)));
        out.points.push(p);
        out.tangents.push(d.normalize_or_zero());
    }
    out
}

/// Point and first derivative of a B-spline at `u` (de Boor's algorithm on
/// the curve and on its derivative's control points).
pub fn de_boor(ctrl: &[DVec3], knots: &[f64], degree: usize, u: f64) -> (DVec3, DVec3) {
    let n = ctrl.len();
    // The span k with knots[k] <= u < knots[k + 1], degree <= k < n.
    let mut k = degree;
    while k + 1 < n && knots[k + 1] <= u {
        k += 1;
    }
    let eval = |pts: &[DVec3], kn: &[f64], p: usize, k: usize| -> DVec3 {
        let mut d: Vec<DVec3> = (0..=p).map(|j| pts[j + k - p]).collect();
        for r in 1..=p {
            for j in (r..=p).rev() {
                let i = j + k - p;
                let den = kn[i + p + 1 - r] - kn[i];
                let a = if den > 0.0 { (u - kn[i]) / den } else { 0.0 };
                d[j] = d[j - 1].lerp(d[j], a);
            }
        }
        d[p]
    };
    let point = eval(ctrl, knots, degree, k);
    if degree == 0 {
        return (point, DVec3::ZERO);
    }
    let q: Vec<DVec3> = (0..n - 1)
        .map(|i| {
            let den = knots[i + degree + 1] - knots[i + 1];
            if den > 0.0 {
                (ctrl[i + 1] - ctrl[i]) * (degree as f64 / den)
            } else {
                DVec3::ZERO
            }
        })
        .collect();
    let deriv = eval(&q, &knots[1..knots.len() - 1], degree - 1, k - 1);
    (point, deriv)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tangents_are_the_derivatives() {
        // Finite differences of the sampled positions agree with the tangents.
        for s in [
            helix(1.0, 0.5, 2.0, 400),
            torus_knot(2, 3, 1.0, 0.4, 800),
            arc(2.0, 0.0, 1.5, 200),
            catmull_rom(
                &[
                    DVec3::ZERO,
                    DVec3::X,
                    DVec3::new(1.0, 1.0, 0.0),
                    DVec3::new(2.0, 1.0, 1.0),
                ],
                false,
                100,
                0.5,
            ),
            bspline(
                &[
                    DVec3::ZERO,
                    DVec3::X,
                    DVec3::new(1.0, 1.0, 0.0),
                    DVec3::new(2.0, 1.0, 1.0),
                    DVec3::new(3.0, 0.0, 0.0),
                ],
                false,
                100,
            ),
            bspline(
                &[
                    DVec3::ZERO,
                    DVec3::X,
                    DVec3::new(1.0, 1.0, 0.0),
                    DVec3::new(0.0, 1.0, 0.5),
                ],
                true,
                100,
            ),
        ] {
            let n = s.points.len();
            for i in 1..n - 1 {
                let fd = (s.points[i + 1] - s.points[i - 1]).normalize();
                assert!(
                    fd.dot(s.tangents[i]) > 0.999,
                    "{i}: {fd} vs {}",
                    s.tangents[i]
                );
            }
        }
    }

    #[test]
    fn interpolating_curves_pass_through_their_points_and_splines_clamp_to_ends() {
        let pts = [
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(3.0, 1.0, 1.0),
        ];
        let c = catmull_rom(&pts, false, 7, 0.5);
        assert_eq!(c.points.len(), 3 * 7 + 1);
        for (k, p) in pts.iter().enumerate() {
            assert!(c.points[k * 7].distance(*p) < 1e-12);
        }
        let b = bspline(&pts, false, 5);
        assert!(b.points[0].distance(pts[0]) < 1e-12);
        assert!(b.points.last().unwrap().distance(pts[3]) < 1e-9);
        // A closed uniform cubic B-spline on a square is symmetric: every
        // sample is the same distance band from the centre.
        let sq = [DVec3::X, DVec3::Z, -DVec3::X, -DVec3::Z];
        let c = bspline(&sq, true, 8);
        assert_eq!(c.points.len(), 32);
        let r0 = c.points[0].length();
        assert!((r0 - 2.0 / 3.0).abs() < 1e-12, "{r0}");
    }
}
