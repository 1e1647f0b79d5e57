//! The sparse linear algebra LSCM needs: complex Hermitian positive
//! definite systems `A x = b`, solved by a sparse Cholesky factorisation
//! (faer's, `direct.rs`) or by conjugate gradients (`cg.rs`)
//! preconditioned with smoothed-aggregation multigrid (`amg/`).
//!
//! Why a direct solver from a crate, measured on this project's 2-core
//! machine (release build) for LSCM of a 200k-triangle hemisphere
//! (100k complex unknowns, two pins, relative residual 1e-9):
//!
//! | solver | iterations | time |
//! | --- | --- | --- |
//! | CG, Jacobi preconditioner | 9,347 | 18 s |
//! | CG, multigrid (`amg/`) | 438 | 3.5 - 4.3 s |
//! | faer sparse Cholesky, sequential | - | 0.3 s |
//!
//! CG stalls because the conformal energy has a large near-kernel:
//! every smooth holomorphic map is nearly free of energy, and those
//! modes oscillate along the boundary, where neither smoothing nor
//! aggregation reaches them; the iterations grow with the boundary's
//! length whatever the preconditioner (multigrid still cuts them twenty
//! times), so a 1M-triangle mesh would take most of a minute. A sparse
//! Cholesky factorisation does not care. faer's is the well-kept pure
//! Rust one; it is built without its rayon feature and called with
//! `Par::Seq`, so its results cannot depend on the thread count.
//!
//! Conjugate gradients stay: they polish a direct solution that misses
//! the tolerance, take over when the factorisation fails (a system that is
//! only semi-definite: a part of an island linked through zero-area
//! triangles has no pins of its own; or no memory for the factor), and
//! are there for meshes too large to factor ([`solve_hermitian`] with
//! `direct: false`).
//!
//! Everything parallel here is deterministic: rows are split into chunks
//! of a fixed size ([`CHUNK`], independent of the thread count), each
//! chunk's partial sums are computed in one sequential order, and the
//! partials are added in chunk order. The same input gives bit-identical
//! results on any number of threads.

mod amg;
mod cg;
mod complex;
mod dense;
mod direct;
mod precondition;
mod sparse;

pub use amg::Multigrid;
pub use cg::CgSettings;
pub use complex::Complex;
pub use direct::cholesky_iterate;
pub use precondition::Preconditioner;
pub use sparse::Csr;

use crate::error::UvError;

/// Rows per parallel chunk (and so per partial sum of a reduction).
pub const CHUNK: usize = 2048;

/// How a solve went.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolveReport {
    /// Conjugate gradient iterations (0 when the factorisation sufficed).
    pub iterations: usize,
    /// `|b - A x| / |b|` at the end.
    pub relative_residual: f64,
    /// Whether the tolerance was met.
    pub converged: bool,
}

/// `A x = b` for a Hermitian positive (semi-)definite `A`: by Cholesky
/// factorisation when `direct` (falling back on CG when it fails), then
/// CG from that solution until the relative residual is within
/// `settings.tolerance`.
pub fn solve_hermitian(
    a: &Csr,
    b: &[Complex],
    direct: bool,
    settings: &CgSettings,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<(Vec<Complex>, SolveReport), UvError> {
    let factored = if direct {
        direct::cholesky_solve(a, b, cancel)?
    } else {
        None
    };
    let mut x = factored.unwrap_or_else(|| vec![Complex::ZERO; a.rows()]);
    let outcome = if direct && relative_residual(a, b, &x) <= settings.tolerance {
        cg::CgOutcome {
            iterations: 0,
            relative_residual: relative_residual(a, b, &x),
            converged: true,
        }
    } else {
        UvError::unless_cancelled(cancel)?;
        let multigrid = Multigrid::new(a);
        cg::solve(a, b, &mut x, &multigrid, settings, cancel)?
    };
    Ok((
        x,
        SolveReport {
            iterations: outcome.iterations,
            relative_residual: outcome.relative_residual,
            converged: outcome.converged,
        },
    ))
}

/// `|b - A x| / |b|` (0 when `b` is zero).
fn relative_residual(a: &Csr, b: &[Complex], x: &[Complex]) -> f64 {
    let mut ax = vec![Complex::ZERO; b.len()];
    a.multiply(x, &mut ax);
    let r: Vec<Complex> = ax.iter().zip(b).map(|(&ax, &b)| b - ax).collect();
    let b_norm = cg::norm(b);
    if b_norm > 0.0 {
        cg::norm(&r) / b_norm
    } else {
        cg::norm(&r)
    }
}
