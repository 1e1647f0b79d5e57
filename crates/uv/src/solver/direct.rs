//! The direct solve: faer's sparse Cholesky factorisation (AMD ordering,
//! supernodal), run sequentially so its rounding cannot depend on the
//! number of threads.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::factorize_symbolic_cholesky;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{c64, Conj, MatMut, Par, Side};

use super::{Complex, Csr};
use crate::error::UvError;

/// `x = A^-1 b` for a Hermitian positive definite `A` (all entries
/// stored), or None when `A` is not definite (a pivot vanished: some
/// unknowns are free, as in a part of the mesh without pins) or memory
/// ran out. Polls `cancel` between the phases.
pub fn cholesky_solve(
    a: &Csr,
    b: &[Complex],
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Option<Vec<Complex>>, UvError> {
    cholesky_iterate(a, b, cancel, &mut |_| Ok(false))
}

/// Solves `A x = b` with one factorisation of `A`, then, while `next`
/// (given the solution, which it may overwrite with the next right-hand
/// side) answers true, solves again: inverse iteration's solves for the
/// price of one factorisation. The last solution comes back (None as in
/// [`cholesky_solve`], or when a solution is not finite).
pub fn cholesky_iterate(
    a: &Csr,
    b: &[Complex],
    cancel: &(dyn Fn() -> bool + Sync),
    next: &mut dyn FnMut(&mut [Complex]) -> Result<bool, UvError>,
) -> Result<Option<Vec<Complex>>, UvError> {
    let n = a.rows();
    // Column j of a Hermitian matrix is the conjugate of row j: the rows
    // as they are give the columns of the lower triangle.
    let symbolic = SymbolicSparseColMat::<usize>::new_checked(
        n,
        n,
        a.offsets.clone(),
        None,
        a.cols.iter().map(|&c| c as usize).collect(),
    );
    let values: Vec<c64> = a.values.iter().map(|v| c64::new(v.re, -v.im)).collect();
    let matrix = SparseColMatRef::new(symbolic.as_ref(), &values);
    let Ok(factor) = factorize_symbolic_cholesky(
        symbolic.as_ref(),
        Side::Lower,
        Default::default(),
        Default::default(),
    ) else {
        return Ok(None);
    };
    UvError::unless_cancelled(cancel)?;
    let par = Par::Seq;
    let Ok(mut buffer) = MemBuffer::try_new(
        factor
            .factorize_numeric_llt_scratch::<c64>(par, Default::default())
            .or(factor.solve_in_place_scratch::<c64>(1, par)),
    ) else {
        return Ok(None);
    };
    let mut l_values = vec![c64::new(0.0, 0.0); factor.len_val()];
    let Ok(llt) = factor.factorize_numeric_llt::<c64>(
        &mut l_values,
        matrix,
        Side::Lower,
        Default::default(),
        par,
        MemStack::new(&mut buffer),
        Default::default(),
    ) else {
        return Ok(None);
    };
    UvError::unless_cancelled(cancel)?;
    let mut x: Vec<c64> = b.iter().map(|v| c64::new(v.re, v.im)).collect();
    loop {
        llt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut x, n, 1),
            par,
            MemStack::new(&mut buffer),
        );
        let mut solution: Vec<Complex> = x.iter().map(|v| Complex::new(v.re, v.im)).collect();
        if !solution
            .iter()
            .all(|v| v.re.is_finite() && v.im.is_finite())
        {
            return Ok(None);
        }
        UvError::unless_cancelled(cancel)?;
        if !next(&mut solution)? {
            return Ok(Some(solution));
        }
        for (x, s) in x.iter_mut().zip(&solution) {
            *x = c64::new(s.re, s.im);
        }
    }
}
