//! A dense Hermitian Cholesky factorisation, for multigrid's coarsest
//! level (a few hundred unknowns).

use super::{Complex, Csr};

/// `A = L L^H` with `L` lower triangular (row-major, n x n). Pivots that
/// vanish (a semi-definite direction) are dropped: their unknowns solve
/// to zero.
#[derive(Clone, Debug, Default)]
pub struct DenseCholesky {
    n: usize,
    lower: Vec<Complex>,
}

/// A pivot below this fraction of its original diagonal is dropped.
const PIVOT_DROP: f64 = 1e-13;

impl DenseCholesky {
    pub fn factor(a: &Csr) -> DenseCholesky {
        let n = a.rows();
        let mut l = vec![Complex::ZERO; n * n];
        for i in 0..n {
            let (cols, values) = a.row(i);
            for (&j, &v) in cols.iter().zip(values) {
                if (j as usize) <= i {
                    l[i * n + j as usize] = v;
                }
            }
        }
        for j in 0..n {
            let original = l[j * n + j].re;
            let mut d = original;
            for k in 0..j {
                d -= l[j * n + k].norm_sqr();
            }
            if !d.is_finite() || d <= PIVOT_DROP * original.abs() {
                for i in j..n {
                    l[i * n + j] = Complex::ZERO;
                }
                continue;
            }
            let pivot = d.sqrt();
            l[j * n + j] = Complex::new(pivot, 0.0);
            for i in j + 1..n {
                let mut s = l[i * n + j];
                for k in 0..j {
                    s -= l[i * n + k] * l[j * n + k].conj();
                }
                l[i * n + j] = s.scale(1.0 / pivot);
            }
        }
        DenseCholesky { n, lower: l }
    }

    /// `x = A^-1 b` (zero along dropped pivots).
    pub fn solve(&self, b: &[Complex], x: &mut [Complex]) {
        let (n, l) = (self.n, &self.lower);
        for i in 0..n {
            let pivot = l[i * n + i].re;
            if pivot == 0.0 {
                x[i] = Complex::ZERO;
                continue;
            }
            let mut s = b[i];
            for k in 0..i {
                s -= l[i * n + k] * x[k];
            }
            x[i] = s.scale(1.0 / pivot);
        }
        for i in (0..n).rev() {
            let pivot = l[i * n + i].re;
            if pivot == 0.0 {
                x[i] = Complex::ZERO;
                continue;
            }
            let mut s = x[i];
            for k in i + 1..n {
                s -= l[k * n + i].conj() * x[k];
            }
            x[i] = s.scale(1.0 / pivot);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_hermitian_system() {
        // [[4, 1+i, 0], [1-i, 3, i], [0, -i, 2]]
        let a = Csr {
            ncols: 3,
            offsets: vec![0, 2, 5, 7],
            cols: vec![0, 1, 0, 1, 2, 1, 2],
            values: vec![
                Complex::new(4.0, 0.0),
                Complex::new(1.0, 1.0),
                Complex::new(1.0, -1.0),
                Complex::new(3.0, 0.0),
                Complex::new(0.0, 1.0),
                Complex::new(0.0, -1.0),
                Complex::new(2.0, 0.0),
            ],
        };
        let exact = [
            Complex::new(1.0, 2.0),
            Complex::new(-1.0, 0.5),
            Complex::new(0.0, 3.0),
        ];
        let mut b = [Complex::ZERO; 3];
        a.multiply(&exact, &mut b);
        let mut x = [Complex::ZERO; 3];
        DenseCholesky::factor(&a).solve(&b, &mut x);
        for (x, e) in x.iter().zip(&exact) {
            assert!((*x - *e).norm_sqr() < 1e-24, "{x:?} vs {e:?}");
        }
    }
}
