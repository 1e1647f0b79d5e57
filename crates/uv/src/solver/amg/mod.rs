//! Smoothed-aggregation algebraic multigrid (Vaněk, Mandel, Brezina 1996)
//! as the conjugate gradient preconditioner for LSCM.
//!
//! Why: LSCM with two pinned vertices is a Laplacian-like system whose
//! condition number grows with the mesh size, and Jacobi-preconditioned
//! CG needed about 9,300 iterations (18 s on two cores) for a
//! 200k-triangle hemisphere. One multigrid V-cycle per iteration brings
//! that to a few dozen iterations, about independent of the size.
//!
//! Setup: unknowns are aggregated with their strong neighbours
//! (`aggregate.rs`); the tentative prolongator (constants per aggregate)
//! is smoothed by one damped Jacobi step, `P = (I - w D^-1 A) P0` with
//! `w = 4 / (3 rho)` and `rho` bounded by Gershgorin's circles; the coarse
//! matrix is `P^H A P`. Levels are added until a few hundred unknowns
//! remain, which a dense Cholesky factorisation solves. The cycle smooths
//! with l1-Jacobi (each row scaled by the sum of its magnitudes: always
//! convergent), the same sweeps before and after, so the preconditioner
//! is Hermitian positive definite as CG requires. Everything is
//! sequential in one order or parallel by rows: deterministic.

mod aggregate;

use rayon::prelude::*;

use super::dense::DenseCholesky;
use super::{Complex, Csr, Preconditioner, CHUNK};
use aggregate::{aggregate, tentative_prolongator};

/// A level this small is solved directly.
const COARSEST: usize = 300;
/// A coarsest level larger than this (coarsening stalled) is smoothed
/// instead of factored.
const DENSE_LIMIT: usize = 3000;
const MAX_LEVELS: usize = 25;
/// Strength of connection threshold.
const THETA: f64 = 0.08;
/// Jacobi sweeps before and after the coarse correction.
const SWEEPS: usize = 2;

/// The hierarchy: level 0 is the system matrix itself.
pub struct Multigrid<'a> {
    fine: &'a Csr,
    /// Matrices of levels 1, 2, ...
    coarse: Vec<Csr>,
    /// Prolongator from level k + 1 to k, and its adjoint.
    prolongators: Vec<(Csr, Csr)>,
    /// l1-Jacobi inverse diagonal of every level.
    smoothers: Vec<Vec<f64>>,
    /// The coarsest level factored (None: smoothed instead).
    direct: Option<DenseCholesky>,
}

impl<'a> Multigrid<'a> {
    pub fn new(a: &'a Csr) -> Multigrid<'a> {
        let mut mg = Multigrid {
            fine: a,
            coarse: Vec::new(),
            prolongators: Vec::new(),
            smoothers: vec![l1_inverse(a)],
            direct: None,
        };
        while mg.coarse.len() + 1 < MAX_LEVELS {
            let current = mg.matrix(mg.coarse.len());
            let n = current.rows();
            if n <= COARSEST {
                break;
            }
            let (of, aggregates) = aggregate(current, THETA);
            if aggregates == 0 || aggregates * 10 > n * 9 {
                break;
            }
            let p = smoothed_prolongator(current, &tentative_prolongator(&of, aggregates));
            let r = p.adjoint();
            let next = r.times(&current.times(&p));
            mg.smoothers.push(l1_inverse(&next));
            mg.prolongators.push((p, r));
            mg.coarse.push(next);
        }
        let last = mg.matrix(mg.coarse.len());
        if last.rows() <= DENSE_LIMIT {
            mg.direct = Some(DenseCholesky::factor(last));
        }
        mg
    }

    fn matrix(&self, level: usize) -> &Csr {
        if level == 0 {
            self.fine
        } else {
            &self.coarse[level - 1]
        }
    }

    /// Levels below the finest.
    pub fn depth(&self) -> usize {
        self.coarse.len()
    }

    /// One V-cycle for `A_level x = b` from `x = 0`.
    fn cycle(&self, level: usize, b: &[Complex], x: &mut [Complex]) {
        let a = self.matrix(level);
        let inverse = &self.smoothers[level];
        if level == self.depth() {
            match &self.direct {
                Some(direct) => direct.solve(b, x),
                None => smooth_from_zero(a, inverse, b, x, 4 * SWEEPS),
            }
            return;
        }
        smooth_from_zero(a, inverse, b, x, SWEEPS);
        let mut residual = vec![Complex::ZERO; b.len()];
        a.multiply(x, &mut residual);
        residual
            .par_iter_mut()
            .zip(b.par_iter())
            .with_min_len(CHUNK)
            .for_each(|(r, &b)| *r = b - *r);
        let (p, r) = &self.prolongators[level];
        let mut coarse_b = vec![Complex::ZERO; r.rows()];
        r.multiply(&residual, &mut coarse_b);
        let mut coarse_x = vec![Complex::ZERO; r.rows()];
        self.cycle(level + 1, &coarse_b, &mut coarse_x);
        p.multiply(&coarse_x, &mut residual);
        x.par_iter_mut()
            .zip(residual.par_iter())
            .with_min_len(CHUNK)
            .for_each(|(x, &c)| *x += c);
        let mut scratch = vec![Complex::ZERO; b.len()];
        for _ in 0..SWEEPS {
            sweep(a, inverse, b, x, &mut scratch);
        }
    }
}

impl Preconditioner for Multigrid<'_> {
    fn apply(&self, r: &[Complex], z: &mut [Complex]) {
        self.cycle(0, r, z);
    }
}

/// `1 / sum_j |a_ij|` per row (0 for an empty row).
fn l1_inverse(a: &Csr) -> Vec<f64> {
    (0..a.rows())
        .map(|i| {
            let sum: f64 = a.row(i).1.iter().map(|v| v.norm_sqr().sqrt()).sum();
            if sum > 0.0 && sum.is_finite() {
                1.0 / sum
            } else {
                0.0
            }
        })
        .collect()
}

/// `sweeps` l1-Jacobi sweeps from `x = 0`.
fn smooth_from_zero(a: &Csr, inverse: &[f64], b: &[Complex], x: &mut [Complex], sweeps: usize) {
    x.par_iter_mut()
        .zip(b.par_iter().zip(inverse.par_iter()))
        .with_min_len(CHUNK)
        .for_each(|(x, (&b, &m))| *x = b.scale(m));
    let mut scratch = vec![Complex::ZERO; b.len()];
    for _ in 1..sweeps {
        sweep(a, inverse, b, x, &mut scratch);
    }
}

/// One l1-Jacobi sweep: `x += M^-1 (b - A x)`.
fn sweep(a: &Csr, inverse: &[f64], b: &[Complex], x: &mut [Complex], ax: &mut [Complex]) {
    a.multiply(x, ax);
    x.par_iter_mut()
        .zip(ax.par_iter().zip(b.par_iter().zip(inverse.par_iter())))
        .with_min_len(CHUNK)
        .for_each(|(x, (&ax, (&b, &m)))| *x += (b - ax).scale(m));
}

/// `(I - w D^-1 A) P0` with `w = 4 / (3 rho(D^-1 A))`.
fn smoothed_prolongator(a: &Csr, tentative: &Csr) -> Csr {
    let diagonal = a.diagonal();
    let rho = (0..a.rows())
        .map(|i| {
            let sum: f64 = a.row(i).1.iter().map(|v| v.norm_sqr().sqrt()).sum();
            if diagonal[i] > 0.0 {
                sum / diagonal[i]
            } else {
                0.0
            }
        })
        .fold(0.0f64, f64::max);
    let omega = if rho > 0.0 { 4.0 / (3.0 * rho) } else { 0.0 };
    let mut smoother = a.clone();
    for (i, &d) in diagonal.iter().enumerate() {
        let span = smoother.offsets[i]..smoother.offsets[i + 1];
        let scale = if d > 0.0 { -omega / d } else { 0.0 };
        for k in span {
            let mut v = smoother.values[k].scale(scale);
            if smoother.cols[k] as usize == i {
                v.re += 1.0;
            }
            smoother.values[k] = v;
        }
    }
    smoother.times(tentative)
}
