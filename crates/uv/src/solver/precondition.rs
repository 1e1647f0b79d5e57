//! Preconditioners for conjugate gradients: `z = M^-1 r` with `M`
//! Hermitian positive definite.

use super::Complex;

/// An approximate inverse of the system matrix.
pub trait Preconditioner: Sync {
    /// `z = M^-1 r`.
    fn apply(&self, r: &[Complex], z: &mut [Complex]);
}
