//! Preconditioned conjugate gradients on a Hermitian positive
//! (semi-)definite system, as the real symmetric system of twice the size
//! (inner products are `Re(x^H y)`).

use rayon::prelude::*;

use super::{Complex, Csr, Preconditioner, CHUNK};
use crate::error::UvError;

/// When the iteration stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CgSettings {
    /// Stop once `|b - A x| <= tolerance * |b|`.
    pub tolerance: f64,
    /// Stop after this many iterations whatever the residual.
    pub max_iterations: usize,
}

/// How a solve ended.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CgOutcome {
    pub iterations: usize,
    /// `|b - A x| / |b|` at the end (0 for a zero right-hand side).
    pub relative_residual: f64,
    pub converged: bool,
}

/// Iterations between two polls of `cancel` (a multigrid-preconditioned
/// iteration costs about ten plain ones).
const CANCEL_POLL: usize = 16;

/// Solves `A x = b` from the guess in `x` with preconditioner `m`,
/// polling `cancel` every [`CANCEL_POLL`] iterations. Never fails but on
/// cancellation; a system it cannot bring under the tolerance returns its
/// last iterate with `converged: false`.
pub fn solve(
    a: &Csr,
    b: &[Complex],
    x: &mut [Complex],
    m: &dyn Preconditioner,
    settings: &CgSettings,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<CgOutcome, UvError> {
    let n = a.rows();
    let b_norm = norm(b);
    if b_norm == 0.0 || n == 0 {
        x.iter_mut().for_each(|v| *v = Complex::ZERO);
        return Ok(CgOutcome {
            converged: true,
            ..CgOutcome::default()
        });
    }
    let mut r = vec![Complex::ZERO; n];
    a.multiply(x, &mut r);
    r.par_iter_mut()
        .zip(b.par_iter())
        .with_min_len(CHUNK)
        .for_each(|(r, &b)| *r = b - *r);
    let mut z = vec![Complex::ZERO; n];
    m.apply(&r, &mut z);
    let mut p = z.clone();
    let mut q = vec![Complex::ZERO; n];
    let mut rz = dot(&r, &z);
    let mut residual = norm(&r);
    let target = settings.tolerance * b_norm;
    let mut iterations = 0;
    while residual > target && iterations < settings.max_iterations && rz > 0.0 {
        if iterations % CANCEL_POLL == 0 {
            UvError::unless_cancelled(cancel)?;
        }
        let pq = a.multiply_and_dot(&p, &mut q);
        if pq <= 0.0 || !pq.is_finite() {
            break; // p lies in the null space: nothing more to gain.
        }
        let alpha = rz / pq;
        residual = step(alpha, x, &mut r, &p, &q).sqrt();
        m.apply(&r, &mut z);
        let rz_next = dot(&r, &z);
        let beta = rz_next / rz;
        rz = rz_next;
        p.par_chunks_mut(CHUNK)
            .zip(z.par_chunks(CHUNK))
            .for_each(|(p, z)| {
                for (p, &z) in p.iter_mut().zip(z) {
                    *p = z + p.scale(beta);
                }
            });
        iterations += 1;
    }
    Ok(CgOutcome {
        iterations,
        relative_residual: residual / b_norm,
        converged: residual <= target,
    })
}

/// `x += alpha p`, `r -= alpha q`; returns `<r, r>` of the new residual.
fn step(alpha: f64, x: &mut [Complex], r: &mut [Complex], p: &[Complex], q: &[Complex]) -> f64 {
    let partials: Vec<f64> = x
        .par_chunks_mut(CHUNK)
        .zip(r.par_chunks_mut(CHUNK))
        .zip(p.par_chunks(CHUNK))
        .zip(q.par_chunks(CHUNK))
        .map(|(((x, r), p), q)| {
            let mut rr = 0.0;
            for i in 0..x.len() {
                x[i] += p[i].scale(alpha);
                r[i] -= q[i].scale(alpha);
                rr += r[i].norm_sqr();
            }
            rr
        })
        .collect();
    partials.iter().sum()
}

/// `|v|`, summed over fixed chunks in order.
pub fn norm(v: &[Complex]) -> f64 {
    dot(v, v).sqrt()
}

/// `Re(x^H y)` over fixed chunks, the partials added in order.
pub fn dot(x: &[Complex], y: &[Complex]) -> f64 {
    let partials: Vec<f64> = x
        .par_chunks(CHUNK)
        .zip(y.par_chunks(CHUNK))
        .map(|(x, y)| x.iter().zip(y).map(|(a, b)| a.dot(*b)).sum())
        .collect();
    partials.iter().sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// No preconditioning.
    struct Identity;

    impl Preconditioner for Identity {
        fn apply(&self, r: &[Complex], z: &mut [Complex]) {
            z.copy_from_slice(r);
        }
    }

    /// The 1D Laplacian with both ends fixed, times (1 + i) on the right.
    #[test]
    fn solves_a_tridiagonal_system() {
        let n: usize = 50;
        let mut offsets = vec![0usize];
        let (mut cols, mut values) = (Vec::new(), Vec::new());
        for i in 0..n {
            for j in i.saturating_sub(1)..(i + 2).min(n) {
                cols.push(j as u32);
                values.push(Complex::new(if i == j { 2.0 } else { -1.0 }, 0.0));
            }
            offsets.push(cols.len());
        }
        let a = Csr {
            ncols: n,
            offsets,
            cols,
            values,
        };
        let exact: Vec<Complex> = (0..n)
            .map(|i| Complex::new(i as f64, -(i as f64) * 0.5))
            .collect();
        let mut b = vec![Complex::ZERO; n];
        a.multiply(&exact, &mut b);
        let mut x = vec![Complex::ZERO; n];
        let settings = CgSettings {
            tolerance: 1e-12,
            max_iterations: 1000,
        };
        let m = Identity;
        let out = solve(&a, &b, &mut x, &m, &settings, &|| false).unwrap();
        assert!(out.converged, "{out:?}");
        for (x, e) in x.iter().zip(&exact) {
            assert!((*x - *e).norm_sqr().sqrt() < 1e-8, "{x:?} vs {e:?}");
        }
        let mut x = vec![Complex::ZERO; n];
        let cancelled = solve(&a, &b, &mut x, &m, &settings, &|| true);
        assert_eq!(cancelled, Err(UvError::Cancelled));
    }
}
