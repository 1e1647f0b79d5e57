//! The attribute kernels' errors: what was wrong with the request.

use thiserror::Error;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum AttribError {
    /// A request the kernel cannot carry out on this data, said in words.
    #[error("{0}")]
    Invalid(String),
    #[error("cancelled")]
    Cancelled,
}

/// `Err(Cancelled)` once `cancel` says stop.
pub(crate) fn unless_cancelled(cancel: &(dyn Fn() -> bool + Sync)) -> Result<(), AttribError> {
    if cancel() {
        Err(AttribError::Cancelled)
    } else {
        Ok(())
    }
}
