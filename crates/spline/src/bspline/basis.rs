//! B-spline basis functions over any knot vector (Cox-de Boor): the span
//! holding a parameter, the non-zero basis functions there, and their
//! derivatives (The NURBS Book, algorithms A2.1 to A2.3, in f64).

/// Why a knot vector cannot carry a spline.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum KnotError {
    #[error("degree {0} needs at least {1} control points")]
    TooFewPoints(usize, usize),
    #[error("{found} knots for {points} control points of degree {degree}: expected {expected}")]
    Count {
        found: usize,
        points: usize,
        degree: usize,
        expected: usize,
    },
    #[error("knot {0} decreases (knots must be non-decreasing)")]
    Decreasing(usize),
    #[error("knot {0} is not finite")]
    NotFinite(usize),
    #[error("the knot vector's domain is empty")]
    EmptyDomain,
}

/// A knot vector with its degree.
#[derive(Clone, Debug, PartialEq)]
pub struct Knots {
    pub degree: usize,
    pub knots: Vec<f64>,
}

impl Knots {
    /// Checks `knots` for `points` control points of `degree`.
    pub fn new(degree: usize, knots: Vec<f64>, points: usize) -> Result<Knots, KnotError> {
        if points < degree + 1 {
            return Err(KnotError::TooFewPoints(degree, degree + 1));
        }
        let expected = points + degree + 1;
        if knots.len() != expected {
            return Err(KnotError::Count {
                found: knots.len(),
                points,
                degree,
                expected,
            });
        }
        if let Some(i) = knots.iter().position(|k| !k.is_finite()) {
            return Err(KnotError::NotFinite(i));
        }
        if let Some(i) = (1..knots.len()).find(|&i| knots[i] < knots[i - 1]) {
            return Err(KnotError::Decreasing(i));
        }
        let k = Knots { degree, knots };
        let (a, b) = k.domain();
        if b <= a {
            return Err(KnotError::EmptyDomain);
        }
        Ok(k)
    }

    /// Clamped uniform knots on [0, 1]: the curve meets its end points.
    pub fn clamped_uniform(degree: usize, points: usize) -> Knots {
        let inner = points - degree;
        let mut knots = vec![0.0; degree + 1];
        knots.extend((1..inner).map(|i| i as f64 / inner as f64));
        knots.extend(std::iter::repeat_n(1.0, degree + 1));
        Knots { degree, knots }
    }

    /// Uniform knots 0, 1, 2, ...: with the first `degree` points repeated
    /// at the end, a closed (periodic) spline over [degree, points].
    pub fn uniform(degree: usize, points: usize) -> Knots {
        Knots {
            degree,
            knots: (0..points + degree + 1).map(|i| i as f64).collect(),
        }
    }

    /// Number of control points the knots carry.
    pub fn points(&self) -> usize {
        self.knots.len() - self.degree - 1
    }

    /// The parameter range where the basis sums to one.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.points()])
    }

    /// The span `k` with `knots[k] <= u < knots[k + 1]` (the last non-empty
    /// span at the domain's end), `degree <= k < points`.
    pub fn span(&self, u: f64) -> usize {
        let (p, n) = (self.degree, self.points());
        if u >= self.knots[n] {
            // The last span of positive length.
            let mut k = n - 1;
            while k > p && self.knots[k] == self.knots[k + 1] {
                k -= 1;
            }
            return k;
        }
        if u <= self.knots[p] {
            let mut k = p;
            while k + 1 < n && self.knots[k + 1] <= u {
                k += 1;
            }
            return k;
        }
        // Binary search in [p, n).
        let (mut lo, mut hi) = (p, n);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if u < self.knots[mid] {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        lo
    }

    /// The `degree + 1` basis functions non-zero on `span` at `u`.
    pub fn basis(&self, span: usize, u: f64) -> Vec<f64> {
        self.derivatives(span, u, 0).swap_remove(0)
    }

    /// Basis functions and their derivatives up to order `n` at `u`:
    /// `out[k][j]` is the k-th derivative of N_{span - degree + j}.
    pub fn derivatives(&self, span: usize, u: f64, n: usize) -> Vec<Vec<f64>> {
        let p = self.degree;
        let k = &self.knots;
        let mut ndu = vec![vec![0.0f64; p + 1]; p + 1];
        let (mut left, mut right) = (vec![0.0; p + 1], vec![0.0; p + 1]);
        ndu[0][0] = 1.0;
        for j in 1..=p {
            left[j] = u - k[span + 1 - j];
            right[j] = k[span + j] - u;
            let mut saved = 0.0;
            for r in 0..j {
                ndu[j][r] = right[r + 1] + left[j - r];
                let temp = if ndu[j][r] != 0.0 {
                    ndu[r][j - 1] / ndu[j][r]
                } else {
                    0.0
                };
                ndu[r][j] = saved + right[r + 1] * temp;
                saved = left[j - r] * temp;
            }
            ndu[j][j] = saved;
        }
        let mut ders = vec![vec![0.0f64; p + 1]; n + 1];
        for j in 0..=p {
            ders[0][j] = ndu[j][p];
        }
        let mut a = vec![vec![0.0f64; p + 1]; 2];
        for r in 0..=p {
            let (mut s1, mut s2) = (0usize, 1usize);
            a[0][0] = 1.0;
            for kk in 1..=n.min(p) {
                let mut d = 0.0;
                let rk = r as isize - kk as isize;
                let pk = p - kk;
                if r >= kk {
                    a[s2][0] = a[s1][0] / ndu[pk + 1][rk as usize];
                    d = a[s2][0] * ndu[rk as usize][pk];
                }
                let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
                let j2 = if (r as isize - 1) <= pk as isize {
                    kk - 1
                } else {
                    p - r
                };
                for j in j1..=j2 {
                    let idx = (rk + j as isize) as usize;
                    a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx];
                    d += a[s2][j] * ndu[idx][pk];
                }
                if r <= pk {
                    a[s2][kk] = -a[s1][kk - 1] / ndu[pk + 1][r];
                    d += a[s2][kk] * ndu[r][pk];
                }
                ders[kk][r] = d;
                std::mem::swap(&mut s1, &mut s2);
            }
        }
        let mut factor = p as f64;
        for (kk, row) in ders.iter_mut().enumerate().take(n.min(p) + 1).skip(1) {
            for v in row.iter_mut() {
                *v *= factor;
            }
            factor *= (p - kk) as f64;
        }
        ders
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_a_partition_of_unity_and_derivatives_sum_to_zero() {
        let k = Knots::new(
            3,
            vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.3, 0.7, 1.0, 1.0, 1.0, 1.0],
            7,
        )
        .unwrap();
        for i in 0..=200 {
            let u = i as f64 / 200.0;
            let s = k.span(u);
            let d = k.derivatives(s, u, 2);
            assert!((d[0].iter().sum::<f64>() - 1.0).abs() < 1e-12, "{u}");
            assert!(d[0].iter().all(|&b| b >= -1e-15));
            assert!(d[1].iter().sum::<f64>().abs() < 1e-9 && d[2].iter().sum::<f64>().abs() < 1e-7);
        }
    }

    #[test]
    fn bad_knots_are_named() {
        assert_eq!(
            Knots::new(3, vec![0.0; 7], 4),
            Err(KnotError::Count {
                found: 7,
                points: 4,
                degree: 3,
                expected: 8
            })
        );
        assert_eq!(
            Knots::new(1, vec![0.0, 1.0, 0.5, 1.0], 2),
            Err(KnotError::Decreasing(2))
        );
        assert_eq!(Knots::new(2, vec![0.0; 6], 3), Err(KnotError::EmptyDomain));
        assert_eq!(
            Knots::new(3, vec![0.0; 6], 2),
            Err(KnotError::TooFewPoints(3, 4))
        );
    }
}
