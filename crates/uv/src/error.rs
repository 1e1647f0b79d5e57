//! The UV kernel's errors: a cancelled run, or an input it cannot use.

use thiserror::Error;

/// What can stop a UV operation. Bad geometry (degenerate polygons,
/// non-manifold edges, isolated points) is never an error: it is handled.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum UvError {
    /// The caller's cancel callback said stop.
    #[error("cancelled")]
    Cancelled,
    /// A parameter or an input the operation cannot use (a singular
    /// projection frame, a pin out of range, a negative margin...).
    #[error("{0}")]
    Invalid(String),
}

impl UvError {
    /// `Err(Cancelled)` once `cancel` says stop: the poll between phases.
    pub(crate) fn unless_cancelled(cancel: &(dyn Fn() -> bool + Sync)) -> Result<(), UvError> {
        if cancel() {
            Err(UvError::Cancelled)
        } else {
            Ok(())
        }
    }
}
