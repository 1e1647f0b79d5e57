//! File errors that name the file, the position (line or byte offset) and what was expected.

use std::fmt;
use std::path::PathBuf;

/// Where in a file a problem was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Position {
    /// 1-based line of a text file.
    Line(u64),
    /// Byte offset in a binary file.
    Byte(u64),
}

impl fmt::Display for Position {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Position::Line(l) => write!(f, "line {l}"),
            Position::Byte(b) => write!(f, "byte {b}"),
        }
    }
}

/// A failure reading or writing a geometry file.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// The content is malformed.
    #[error("{}: {}{message}", path.display(), pos.map(|p| format!("{p}: ")).unwrap_or_default())]
    Parse {
        path: PathBuf,
        pos: Option<Position>,
        message: String,
    },
    /// The operating system refused.
    #[error("{}: {error}", path.display())]
    Os {
        path: PathBuf,
        #[source]
        error: std::io::Error,
    },
    /// The extension names no format geode knows.
    #[error("{}: unknown file format (expected one of: {expected})", path.display())]
    UnknownFormat { path: PathBuf, expected: String },
    /// The format cannot hold this geometry.
    #[error("{}: {message}", path.display())]
    Unsupported { path: PathBuf, message: String },
    /// The write was cancelled; nothing was written.
    #[error("{}: cancelled, nothing was written", path.display())]
    Cancelled { path: PathBuf },
    /// Reading or writing would need more memory than the budget allows.
    #[error("{}: {message}", path.display())]
    TooLarge { path: PathBuf, message: String },
}

impl IoError {
    pub fn os(path: impl Into<PathBuf>, source: std::io::Error) -> IoError {
        IoError::Os {
            path: path.into(),
            error: source,
        }
    }

    pub fn position(&self) -> Option<Position> {
        match self {
            IoError::Parse { pos, .. } => *pos,
            _ => None,
        }
    }
}

/// Formats without instancing refuse packed primitives (`write` unpacks first).
pub(crate) fn refuse_packed(
    g: &geode_geo::Geometry,
    path: &std::path::Path,
    format: &str,
) -> Result<(), IoError> {
    if g.has_packed() {
        return Err(IoError::Unsupported {
            path: path.to_owned(),
            message: format!("{format} cannot hold packed primitives; unpack them first"),
        });
    }
    Ok(())
}

/// A parse error at a position, before the file name is known to the parser.
#[derive(Debug, Clone, PartialEq)]
pub struct ParseError {
    pub pos: Option<Position>,
    pub message: String,
    /// The file is well formed but its counts need more memory than the
    /// budget: an `IoError::TooLarge`, not a malformed file.
    pub over_budget: bool,
}

impl ParseError {
    pub fn line(line: u64, message: impl Into<String>) -> ParseError {
        ParseError {
            pos: Some(Position::Line(line)),
            message: message.into(),
            over_budget: false,
        }
    }

    pub fn byte(offset: u64, message: impl Into<String>) -> ParseError {
        ParseError {
            pos: Some(Position::Byte(offset)),
            message: message.into(),
            over_budget: false,
        }
    }

    pub fn whole(message: impl Into<String>) -> ParseError {
        ParseError {
            pos: None,
            message: message.into(),
            over_budget: false,
        }
    }

    /// Counts that would need more memory than the budget.
    pub fn over_budget(message: impl Into<String>) -> ParseError {
        ParseError {
            over_budget: true,
            ..ParseError::whole(message)
        }
    }

    /// The same error, its message prefixed with where in the document it is.
    pub fn within(self, what: impl std::fmt::Display) -> ParseError {
        ParseError {
            message: format!("{what}: {}", self.message),
            pos: None,
            ..self
        }
    }

    pub fn in_file(self, path: impl Into<PathBuf>) -> IoError {
        if self.over_budget {
            return IoError::TooLarge {
                path: path.into(),
                message: self.message,
            };
        }
        IoError::Parse {
            path: path.into(),
            pos: self.pos,
            message: self.message,
        }
    }
}

pub type ParseResult<T> = Result<T, ParseError>;
