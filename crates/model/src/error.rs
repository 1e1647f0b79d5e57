//! The modelling kernel's errors: what was wrong with which input.

use thiserror::Error;

#[derive(Debug, Error)]
pub enum ModelError {
    /// An input the operation needs closed (a solid) is not.
    #[error("input {input} is not a closed manifold mesh: {why}")]
    NotClosed { input: &'static str, why: String },
    /// A closed input whose faces point inward (negative volume).
    #[error(
        "input {input} is inside out: its faces point inward (volume {volume}); reverse it first"
    )]
    InsideOut { input: &'static str, volume: f64 },
    /// A parameter's value the operation cannot use.
    #[error("{0}")]
    Invalid(String),
    /// The operation itself failed on these inputs.
    #[error("{op} failed: {why}")]
    Failed { op: &'static str, why: String },
    #[error("cancelled")]
    Cancelled,
}

impl ModelError {
    /// `Err(Cancelled)` once `cancel` says stop: the poll between phases.
    pub(crate) fn unless_cancelled(cancel: &(dyn Fn() -> bool + Sync)) -> Result<(), ModelError> {
        if cancel() {
            Err(ModelError::Cancelled)
        } else {
            Ok(())
        }
    }
}
