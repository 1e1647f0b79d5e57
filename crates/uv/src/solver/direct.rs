//! The direct solve: faer's sparse Cholesky factorisation (AMD ordering,
//! supernodal), run sequentially so its rounding cannot depend on the
//! number of threads, each of its long calls on a thread of its own so a
//! cancel is answered within milliseconds.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, LltRef};
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
    // Ordering and symbolic factorisation are one call into faer each (a
    // tenth of a second, then a quarter, for 160,000 unknowns): they run
    // on a thread of their own while this one answers a cancel.
    let ordering = move || {
        let factor = factorize_symbolic_cholesky(
            symbolic.as_ref(),
            Side::Lower,
            Default::default(),
            Default::default(),
        );
        (symbolic, factor)
    };
    let (symbolic, factor) = uninterruptible(cancel, ordering)?;
    let Ok(factor) = factor else {
        return Ok(None);
    };
    let par = Par::Seq;
    let Ok(mut buffer) = MemBuffer::try_new(
        factor
            .factorize_numeric_llt_scratch::<c64>(par, Default::default())
            .or(factor.solve_in_place_scratch::<c64>(1, par)),
    ) else {
        return Ok(None);
    };
    let numeric = move || {
        let mut l_values = vec![c64::new(0.0, 0.0); factor.len_val()];
        let matrix = SparseColMatRef::new(symbolic.as_ref(), &values);
        let factored = factor
            .factorize_numeric_llt::<c64>(
                &mut l_values,
                matrix,
                Side::Lower,
                Default::default(),
                par,
                MemStack::new(&mut buffer),
                Default::default(),
            )
            .is_ok();
        (factor, l_values, buffer, factored)
    };
    let (factor, l_values, mut buffer, factored) = uninterruptible(cancel, numeric)?;
    if !factored {
        return Ok(None);
    }
    let llt = LltRef::new(&factor, &l_values);
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

/// `work`'s result, computed on a thread of its own while this one polls
/// `cancel` every few milliseconds; `Cancelled` as soon as it answers true
/// (the thread then finishes on its own and its result is dropped). For a
/// call into a library that cannot be interrupted.
fn uninterruptible<T: Send + 'static>(
    cancel: &(dyn Fn() -> bool + Sync),
    work: impl FnOnce() -> T + Send + 'static,
) -> Result<T, UvError> {
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::Builder::new()
        .name("geode-uv-factor".into())
        .spawn(move || {
            // The receiver is gone when the cook was cancelled.
            let _ = send.send(work());
        })
        .map_err(|e| UvError::Invalid(format!("could not start the factorisation: {e}")))?;
    loop {
        match receive.recv_timeout(std::time::Duration::from_millis(5)) {
            Ok(result) => return Ok(result),
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
                UvError::unless_cancelled(cancel)?;
            }
            Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                return Err(UvError::Invalid(
                    "the factorisation stopped without a result".into(),
                ));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::time::{Duration, Instant};

    /// The 5-point Laplacian of an `n` by `n` grid plus the identity:
    /// Hermitian positive definite, its factor dense enough to take a
    /// while (n = 700: 490,000 unknowns, about half a second to factor).
    fn grid_system(n: usize) -> Csr {
        let mut offsets = vec![0];
        let (mut cols, mut values) = (Vec::new(), Vec::new());
        for j in 0..n {
            for i in 0..n {
                let mut row = vec![(j * n + i, 5.0)];
                if i > 0 {
                    row.push((j * n + i - 1, -1.0));
                }
                if i + 1 < n {
                    row.push((j * n + i + 1, -1.0));
                }
                if j > 0 {
                    row.push(((j - 1) * n + i, -1.0));
                }
                if j + 1 < n {
                    row.push(((j + 1) * n + i, -1.0));
                }
                row.sort_by_key(|e| e.0);
                cols.extend(row.iter().map(|e| e.0 as u32));
                values.extend(row.iter().map(|e| Complex::new(e.1, 0.0)));
                offsets.push(cols.len());
            }
        }
        Csr {
            ncols: n * n,
            offsets,
            cols,
            values,
        }
    }

    /// A small system solves exactly; a large one cancelled 20 ms in (in
    /// its ordering or factorisation, single calls into faer) answers
    /// within 100 ms: a few here alone, the margin is for a loaded test
    /// run. (Before the calls ran on a thread of their own, it answered
    /// once the call returned: 217 ms here.)
    #[test]
    fn a_factorisation_answers_a_cancel_promptly() {
        let small = grid_system(3);
        let b = vec![Complex::new(1.0, 0.0); 9];
        let x = cholesky_solve(&small, &b, &|| false).unwrap().unwrap();
        let mut ax = vec![Complex::ZERO; 9];
        small.multiply(&x, &mut ax);
        assert!(ax
            .iter()
            .all(|v| (v.re - 1.0).abs() < 1e-12 && v.im.abs() < 1e-12));

        let large = grid_system(700);
        let b = vec![Complex::new(1.0, 0.0); 700 * 700];
        let stop = AtomicBool::new(false);
        std::thread::scope(|s| {
            let solve = s.spawn(|| {
                let r = cholesky_solve(&large, &b, &|| stop.load(Ordering::Relaxed));
                (r, Instant::now())
            });
            std::thread::sleep(Duration::from_millis(20));
            let cancelled_at = Instant::now();
            stop.store(true, Ordering::Relaxed);
            let (r, returned_at) = solve.join().unwrap();
            assert!(matches!(r, Err(UvError::Cancelled)), "{r:?}");
            let latency = returned_at - cancelled_at;
            assert!(latency < Duration::from_millis(100), "{latency:?}");
        });
    }
}
