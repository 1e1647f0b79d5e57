//! The crate's errors: a compile error at a line and column of the
//! snippet, and the ways a run can fail.

use crate::compile::Pos;

/// A compile error at a line and column of the snippet.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("line {}, column {}: {msg}", pos.line, pos.col)]
pub struct CompileError {
    pub pos: Pos,
    pub msg: String,
}

impl CompileError {
    pub fn at(pos: Pos, msg: impl Into<String>) -> CompileError {
        CompileError {
            pos,
            msg: msg.into(),
        }
    }
}

#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RunError {
    #[error("cancelled")]
    Cancelled,
    #[error("the wrangle needs an input geometry")]
    NoInput,
    #[error("element {elem} (line {}, column {}): {msg}", pos.line, pos.col)]
    At { elem: u32, pos: Pos, msg: String },
    /// A request the run's memory budget cannot hold, refused before it
    /// was allocated.
    #[error("element {elem} (line {}, column {}): {msg}", pos.line, pos.col)]
    OverBudget { elem: u32, pos: Pos, msg: String },
    #[error("not supported yet: {0}")]
    Unsupported(String),
    #[error("{0}")]
    Geometry(String),
}
