//! NURBS curves of any degree over any knot vector: control points with
//! weights kept homogeneous (w x, w y, w z, w), points and derivatives
//! (the quotient rule on homogeneous derivatives), knot insertion by
//! Boehm's algorithm and refinement to any finer knot vector by the Oslo
//! algorithm, both exact.

use geode_geo::glam::{DVec3, DVec4};

use super::basis::{KnotError, Knots};

#[derive(Clone, Debug, PartialEq)]
pub struct NurbsCurve {
    pub knots: Knots,
    /// Homogeneous control points (w x, w y, w z, w).
    pub points: Vec<DVec4>,
}

pub(crate) fn lift(p: DVec3, w: f64) -> DVec4 {
    (p * w).extend(w)
}

pub(crate) fn project(h: DVec4) -> DVec3 {
    h.truncate() / h.w
}

/// Derivatives of a rational function from its homogeneous derivatives
/// `h[k]` (The NURBS Book, A4.2): `C(k) = (A(k) - sum C(k,i) w(i) C(k-i)) / w`.
pub(crate) fn rational_derivatives(h: &[DVec4]) -> Vec<DVec3> {
    let mut out: Vec<DVec3> = Vec::with_capacity(h.len());
    for k in 0..h.len() {
        let mut v = h[k].truncate();
        let mut binom = 1.0;
        for i in 1..=k {
            binom = binom * (k - i + 1) as f64 / i as f64;
            v -= out[k - i] * (binom * h[i].w);
        }
        out.push(v / h[0].w);
    }
    out
}

impl NurbsCurve {
    /// A curve from points, weights (all 1 when `None`) and knots (clamped
    /// uniform when `None`).
    pub fn new(
        degree: usize,
        points: &[DVec3],
        weights: Option<&[f64]>,
        knots: Option<Vec<f64>>,
    ) -> Result<NurbsCurve, KnotError> {
        let knots = match knots {
            Some(k) => Knots::new(degree, k, points.len())?,
            None => {
                if points.len() < degree + 1 {
                    return Err(KnotError::TooFewPoints(degree, degree + 1));
                }
                Knots::clamped_uniform(degree, points.len())
            }
        };
        let points = points
            .iter()
            .enumerate()
            .map(|(i, p)| lift(*p, weights.map_or(1.0, |w| w[i])))
            .collect();
        Ok(NurbsCurve { knots, points })
    }

    pub fn domain(&self) -> (f64, f64) {
        self.knots.domain()
    }

    /// An exact circle in the XY plane from +X, counter-clockwise: the
    /// nine-point rational quadratic.
    pub fn circle(centre: DVec3, radius: f64) -> NurbsCurve {
        Self::arcs(centre, radius, 4)
    }

    /// `quarters` quarter circles in the XY plane from -Y (1 to 4; two make
    /// the right half, a sphere's profile).
    pub fn arcs(centre: DVec3, radius: f64, quarters: usize) -> NurbsCurve {
        let quarters = quarters.clamp(1, 4);
        let w = std::f64::consts::FRAC_1_SQRT_2;
        // Control points around the square, starting at -Y when not a full circle.
        let start = if quarters == 4 { 0 } else { 6 };
        let square = [
            (1.0, 0.0),
            (1.0, 1.0),
            (0.0, 1.0),
            (-1.0, 1.0),
            (-1.0, 0.0),
            (-1.0, -1.0),
            (0.0, -1.0),
            (1.0, -1.0),
        ];
        let pts: Vec<DVec3> = (0..=2 * quarters)
            .map(|k| {
                let (x, y) = square[(start + k) % 8];
                centre + DVec3::new(x, y, 0.0) * radius
            })
            .collect();
        let weights: Vec<f64> = (0..pts.len())
            .map(|i| if i % 2 == 1 { w } else { 1.0 })
            .collect();
        let mut knots = vec![0.0; 3];
        for q in 1..quarters {
            let t = q as f64 / quarters as f64;
            knots.extend([t, t]);
        }
        knots.extend([1.0; 3]);
        NurbsCurve::new(2, &pts, Some(&weights), Some(knots)).expect("circle knots are valid")
    }

    /// Homogeneous point and derivatives up to order `n` at `u`.
    fn homogeneous(&self, u: f64, n: usize) -> Vec<DVec4> {
        let p = self.knots.degree;
        let span = self.knots.span(u);
        let d = self.knots.derivatives(span, u, n);
        (0..=n)
            .map(|k| {
                if k > p {
                    return DVec4::ZERO;
                }
                (0..=p).map(|j| self.points[span - p + j] * d[k][j]).sum()
            })
            .collect()
    }

    pub fn point(&self, u: f64) -> DVec3 {
        project(self.homogeneous(u, 0)[0])
    }

    /// The point and its derivatives up to order `n` at `u`.
    pub fn derivatives(&self, u: f64, n: usize) -> Vec<DVec3> {
        rational_derivatives(&self.homogeneous(u, n))
    }

    /// Inserts the knot `u` `times` times (Boehm), keeping the curve.
    pub fn insert_knot(&self, u: f64, times: usize) -> NurbsCurve {
        let p = self.knots.degree;
        let k = self.knots.span(u);
        let s = self.knots.knots.iter().filter(|&&x| x == u).count();
        let r = times.min(p.saturating_sub(s));
        if r == 0 {
            return self.clone();
        }
        let (uk, pts) = (&self.knots.knots, &self.points);
        let np = pts.len();
        let mut knots = Vec::with_capacity(uk.len() + r);
        knots.extend_from_slice(&uk[..=k]);
        knots.extend(std::iter::repeat_n(u, r));
        knots.extend_from_slice(&uk[k + 1..]);
        let mut q = vec![DVec4::ZERO; np + r];
        q[..=k - p].copy_from_slice(&pts[..=k - p]);
        q[k - s + r..np + r].copy_from_slice(&pts[k - s..np]);
        let mut tmp: Vec<DVec4> = (0..=p - s).map(|i| pts[k - p + i]).collect();
        let mut l = 0;
        for j in 1..=r {
            l = k - p + j;
            for i in 0..=p - j - s {
                let alpha = (u - uk[l + i]) / (uk[i + k + 1] - uk[l + i]);
                tmp[i] = tmp[i + 1] * alpha + tmp[i] * (1.0 - alpha);
            }
            q[l] = tmp[0];
            q[k + r - j - s] = tmp[p - j - s];
        }
        if l + 1 < k - s {
            q[l + 1..k - s].copy_from_slice(&tmp[1..k - s - l]);
        }
        NurbsCurve {
            knots: Knots { degree: p, knots },
            points: q,
        }
    }

    /// The same curve over the finer knot vector `target` (which must
    /// contain every current knot, as often), by the Oslo algorithm: each
    /// new control point is the old ones weighted by discrete B-splines.
    pub fn refine(&self, target: &[f64]) -> Result<NurbsCurve, KnotError> {
        let p = self.knots.degree;
        let tau = &self.knots.knots;
        let m = target.len() - p - 1;
        let knots = Knots::new(p, target.to_vec(), m)?;
        let points = (0..m)
            .map(|j| {
                // The old span containing t_j (the last non-empty one at the end).
                let mu = self
                    .knots
                    .span(target[j].max(tau[p]).min(tau[self.points.len()]));
                // Blossomed basis: degree k uses the argument t_{j+k}.
                let mut b = vec![0.0f64; p + 1];
                b[p] = 1.0; // index i = mu - p + slot
                for k in 1..=p {
                    let x = target[j + k];
                    for slot in (p - k)..=p {
                        let i = mu - p + slot;
                        let w1 = {
                            let d = tau[i + k] - tau[i];
                            if d > 0.0 {
                                (x - tau[i]) / d
                            } else {
                                0.0
                            }
                        };
                        let w2 = {
                            let d = tau[i + k + 1] - tau[i + 1];
                            if d > 0.0 {
                                (tau[i + k + 1] - x) / d
                            } else {
                                0.0
                            }
                        };
                        let this = b[slot];
                        let next = if slot < p { b[slot + 1] } else { 0.0 };
                        b[slot] = w1 * this + w2 * next;
                    }
                }
                (0..=p)
                    .map(|slot| self.points[mu - p + slot] * b[slot])
                    .sum()
            })
            .collect();
        Ok(NurbsCurve { knots, points })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A quarter of the unit circle: degree 2, middle weight sqrt(2)/2.
    fn quarter() -> NurbsCurve {
        NurbsCurve::new(
            2,
            &[DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y],
            Some(&[1.0, std::f64::consts::FRAC_1_SQRT_2, 1.0]),
            None,
        )
        .unwrap()
    }

    #[test]
    fn a_rational_quadratic_is_exactly_a_circle() {
        let c = quarter();
        for i in 0..=100 {
            let u = i as f64 / 100.0;
            assert!((c.point(u).length() - 1.0).abs() < 1e-14);
            // The tangent is perpendicular to the radius.
            let d = c.derivatives(u, 1);
            assert!(d[1].dot(d[0]).abs() < 1e-12);
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let c = NurbsCurve::new(
            3,
            &[
                DVec3::ZERO,
                DVec3::X,
                DVec3::new(2.0, 1.0, 0.0),
                DVec3::new(3.0, 0.0, 1.0),
                DVec3::new(4.0, 2.0, 0.0),
            ],
            Some(&[1.0, 2.0, 0.5, 1.5, 1.0]),
            Some(vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0]),
        )
        .unwrap();
        let h = 1e-6;
        for i in 1..20 {
            let u = i as f64 / 20.0;
            let d = c.derivatives(u, 2);
            let fd1 = (c.point(u + h) - c.point(u - h)) / (2.0 * h);
            let fd2 = (c.point(u + h) - 2.0 * c.point(u) + c.point(u - h)) / (h * h);
            assert!((d[1] - fd1).length() < 1e-6 * (1.0 + fd1.length()), "{u}");
            assert!(
                (d[2] - fd2).length() < 1e-2 * (1.0 + fd2.length()),
                "{u}: {} vs {fd2}",
                d[2]
            );
        }
    }

    #[test]
    fn boehm_and_oslo_keep_the_curve_exactly() {
        let c = NurbsCurve::new(
            3,
            &[
                DVec3::ZERO,
                DVec3::X,
                DVec3::new(2.0, 1.0, 0.0),
                DVec3::new(3.0, 0.0, 1.0),
                DVec3::new(4.0, 2.0, 0.0),
            ],
            Some(&[1.0, 2.0, 0.5, 1.5, 1.0]),
            None,
        )
        .unwrap();
        let boehm = c.insert_knot(0.3, 2).insert_knot(0.5, 1);
        assert_eq!(boehm.points.len(), c.points.len() + 3);
        let mut target = c.knots.knots.clone();
        target.extend([0.1, 0.3, 0.3, 0.5, 0.8, 0.8, 0.8]);
        target.sort_by(f64::total_cmp);
        let oslo = c.refine(&target).unwrap();
        assert_eq!(oslo.points.len(), c.points.len() + 7);
        for i in 0..=1000 {
            let u = i as f64 / 1000.0;
            assert!(
                (boehm.point(u) - c.point(u)).length() < 1e-12,
                "Boehm at {u}"
            );
            assert!((oslo.point(u) - c.point(u)).length() < 1e-12, "Oslo at {u}");
        }
    }
}
