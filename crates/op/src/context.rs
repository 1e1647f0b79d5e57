//! What a cook receives besides its inputs (frame, node path, cancellation, progress, environment, where to put warnings) and its typed error.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use crate::env::{human_bytes, CookEnv};
use crate::param::ParamSpec;

/// A shared flag that asks running cooks to stop.
#[derive(Clone, Debug, Default)]
pub struct CancelToken(Arc<AtomicBool>);

impl CancelToken {
    pub fn new() -> CancelToken {
        CancelToken::default()
    }

    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    /// The token as the `Fn() -> bool` kernels poll (kernels know no token type).
    pub fn as_fn(&self) -> impl Fn() -> bool + Sync + '_ {
        move || self.is_cancelled()
    }
}

/// What kind of failure a [`CookError`] is; callers branch on this, never on the text.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ErrorKind {
    /// The cook was asked to stop.
    Cancelled,
    /// A parameter's value cannot be used.
    Parameter,
    /// An input is missing or its content cannot be used.
    Input,
    /// The result would not fit the memory budget (`GEODE_MEMORY_MB`).
    Resource,
    /// A kernel refused or failed; the kernel's error is the source.
    Kernel,
    /// Reading or writing a file failed; the I/O error is the source.
    Io,
    /// The network itself is wrong at cook time (no output, unknown node).
    Network,
}

impl ErrorKind {
    /// The kind's name as the studio and logs show it (`parameter`, `io`).
    pub fn name(self) -> &'static str {
        match self {
            ErrorKind::Cancelled => "cancelled",
            ErrorKind::Parameter => "parameter",
            ErrorKind::Input => "input",
            ErrorKind::Resource => "resource",
            ErrorKind::Kernel => "kernel",
            ErrorKind::Io => "io",
            ErrorKind::Network => "network",
        }
    }
}

/// Where in a parameter's text (a snippet, an expression) an error is:
/// line and column, both from 1, the column counted in characters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TextPosition {
    pub line: u32,
    pub column: u32,
}

type Source = Arc<dyn std::error::Error + Send + Sync + 'static>;

/// A failed cook: the node, the parameter if one is to blame, the kind, why,
/// and (for kernel and file errors) the error it came from.
#[derive(Clone, Debug)]
pub struct CookError {
    pub path: String,
    pub param: Option<String>,
    pub kind: ErrorKind,
    pub message: String,
    /// Where in the blamed parameter's text the problem is, when it is text.
    pub position: Option<TextPosition>,
    source: Option<Source>,
}

impl std::fmt::Display for CookError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.path)?;
        if let Some(p) = &self.param {
            write!(f, " (parameter `{p}`)")?;
        }
        write!(f, ": {}", self.message)
    }
}

/// The source is the error itself, not the `Arc` that shares it, so a
/// caller can downcast it (the CLI tells a disk's refusal from a file's bad
/// content by it).
impl std::error::Error for CookError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        let source: &(dyn std::error::Error + Send + Sync + 'static) = self.source.as_deref()?;
        Some(source)
    }
}

/// Errors are equal when they say the same thing of the same node (sources
/// are not comparable); the engine uses this to report each error once.
impl PartialEq for CookError {
    fn eq(&self, o: &CookError) -> bool {
        self.path == o.path
            && self.param == o.param
            && self.kind == o.kind
            && self.message == o.message
            && self.position == o.position
    }
}

impl CookError {
    pub fn new(path: &str, kind: ErrorKind, message: impl Into<String>) -> CookError {
        CookError {
            path: path.to_owned(),
            param: None,
            kind,
            message: message.into(),
            position: None,
            source: None,
        }
    }

    pub fn param(path: &str, param: &str, message: impl Into<String>) -> CookError {
        CookError::new(path, ErrorKind::Parameter, message).at_param(param)
    }

    pub fn cancelled(path: &str) -> CookError {
        CookError::new(path, ErrorKind::Cancelled, "cancelled")
    }

    /// Blames a parameter.
    pub fn at_param(mut self, param: &str) -> CookError {
        self.param = Some(param.to_owned());
        self
    }

    /// Points at a line and column (from 1) of the blamed parameter's text.
    pub fn at_position(mut self, line: u32, column: u32) -> CookError {
        self.position = Some(TextPosition { line, column });
        self
    }

    /// Keeps the error this one came from (its text stays the message).
    pub fn with_source(
        mut self,
        source: impl std::error::Error + Send + Sync + 'static,
    ) -> CookError {
        self.source = Some(Arc::new(source));
        self
    }

    pub fn is_cancelled(&self) -> bool {
        self.kind == ErrorKind::Cancelled
    }
}

/// What a cook warns of (the result stands, but the user should know: a
/// feature lost, a value clamped), kept in the order given. A pure function
/// of the cook's key like its value, so the cache keeps them together.
#[derive(Debug, Default)]
pub struct Warnings(Mutex<Vec<String>>);

impl Warnings {
    pub fn new() -> Warnings {
        Warnings::default()
    }

    pub fn push(&self, message: String) {
        self.0
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(message);
    }

    pub fn take(&self) -> Vec<String> {
        std::mem::take(&mut *self.0.lock().unwrap_or_else(|e| e.into_inner()))
    }
}

/// What a node's extra cache-key content may read: the environment (where
/// files may be read) and the cook's cancellation.
pub struct KeyContext<'a> {
    /// The node's path (for errors).
    pub path: &'a str,
    /// The frame being cooked.
    pub frame: f64,
    pub env: &'a CookEnv,
    pub cancel: &'a CancelToken,
}

impl KeyContext<'_> {
    /// The content hash of a file the node reads, or `None` when it may
    /// not or cannot be read (the cook reports why).
    pub fn file_hash(&self, path: &str) -> Option<u128> {
        self.env
            .files
            .content_hash(std::path::Path::new(path), &self.cancel.as_fn())
    }
}

/// What a node is checked against without cooking ([`crate::Operator::check`],
/// `geode check`): its place, the frame its parameters were evaluated at,
/// and which inputs are wired (what they would carry is not known without
/// cooking them).
pub struct CheckContext<'a> {
    pub path: &'a str,
    pub frame: f64,
    pub env: &'a CookEnv,
    /// One per declared input: whether a wire feeds it.
    pub wired: &'a [bool],
}

impl CheckContext<'_> {
    /// A problem in a parameter's text at a line and column (from 1); the
    /// message says what, the position where.
    pub fn text_error(
        &self,
        param: &str,
        line: u32,
        column: u32,
        message: impl Into<String>,
    ) -> CookError {
        CookError::new(self.path, ErrorKind::Kernel, message)
            .at_param(param)
            .at_position(line, column)
    }
}

/// Receives (node path, fraction done) as cooks progress.
pub type ProgressFn<'a> = dyn Fn(&str, f32) + Sync + 'a;

/// The cook's surroundings. Kernels' long loops call [`CookContext::check`]
/// (or poll [`CookContext::cancel_fn`]) and [`CookContext::progress`].
pub struct CookContext<'a> {
    pub path: &'a str,
    pub frame: f64,
    pub cancel: &'a CancelToken,
    pub on_progress: &'a ProgressFn<'a>,
    /// Hidden inputs (`$HIP`) and limits; what of it a cook reads is in its key.
    pub env: &'a CookEnv,
    pub warnings: &'a Warnings,
}

impl CookContext<'_> {
    /// Err when the cook was cancelled: return it with `?`.
    pub fn check(&self) -> Result<(), CookError> {
        if self.cancel.is_cancelled() {
            Err(CookError::cancelled(self.path))
        } else {
            Ok(())
        }
    }

    /// What kernels poll for cancellation.
    pub fn cancel_fn(&self) -> impl Fn() -> bool + Sync + '_ {
        self.cancel.as_fn()
    }

    /// Warns of something the user should know about the result.
    pub fn warn(&self, message: impl Into<String>) {
        self.warnings.push(message.into());
    }

    /// Reports the fraction done (0 to 1) of this node's cook.
    pub fn progress(&self, fraction: f32) {
        (self.on_progress)(self.path, fraction.clamp(0.0, 1.0));
    }

    /// The input is missing or unusable.
    pub fn input_error(&self, message: impl Into<String>) -> CookError {
        CookError::new(self.path, ErrorKind::Input, message)
    }

    pub fn param_error(&self, param: &ParamSpec, message: impl Into<String>) -> CookError {
        CookError::param(self.path, param.name, message)
    }

    /// A field of one row of a list parameter is to blame (`row` from
    /// `Params::list`): the error names it in full, `skeleton[2].parent`.
    pub fn field_error(
        &self,
        row: &crate::Params,
        field: &ParamSpec,
        message: impl Into<String>,
    ) -> CookError {
        CookError::param(self.path, &row.name(field), message)
    }

    /// A kernel's error, kept as the source; a kernel that stopped because
    /// the cook was cancelled gives a `Cancelled` error.
    pub fn kernel(&self, e: impl std::error::Error + Send + Sync + 'static) -> CookError {
        if self.cancel.is_cancelled() {
            return CookError::cancelled(self.path);
        }
        CookError::new(self.path, ErrorKind::Kernel, e.to_string()).with_source(e)
    }

    /// A kernel's error blamed on a parameter.
    pub fn kernel_at(
        &self,
        param: &ParamSpec,
        e: impl std::error::Error + Send + Sync + 'static,
    ) -> CookError {
        self.kernel(e).at_param(param.name)
    }

    /// A file error for the file named by `param`.
    pub fn io(
        &self,
        param: &ParamSpec,
        e: impl std::error::Error + Send + Sync + 'static,
    ) -> CookError {
        if self.cancel.is_cancelled() {
            return CookError::cancelled(self.path);
        }
        CookError::new(self.path, ErrorKind::Io, e.to_string())
            .at_param(param.name)
            .with_source(e)
    }

    /// Reads the file `param` names, as the environment allows (confined
    /// folders, regular files, size within the memory budget), stopping
    /// when the cook is cancelled.
    pub fn read_file(&self, param: &ParamSpec, path: &str) -> Result<Vec<u8>, CookError> {
        self.env
            .files
            .read(
                std::path::Path::new(path),
                self.env.memory_budget,
                &self.cancel_fn(),
            )
            .map_err(|e| self.file_refusal(param, e))
    }

    /// The real path of the file `param` names, if the environment allows
    /// reading it (checked before anything else is said of the file).
    pub fn readable_file(
        &self,
        param: &ParamSpec,
        path: &str,
    ) -> Result<std::path::PathBuf, CookError> {
        self.env
            .files
            .readable(std::path::Path::new(path))
            .map_err(|e| self.file_refusal(param, e))
    }

    /// The real path to write the file `param` names, if the environment
    /// allows writing there.
    pub fn writable_file(
        &self,
        param: &ParamSpec,
        path: &str,
    ) -> Result<std::path::PathBuf, CookError> {
        self.env
            .files
            .writable(std::path::Path::new(path))
            .map_err(|e| self.file_refusal(param, e))
    }

    fn file_refusal(&self, param: &ParamSpec, e: crate::FileRefusal) -> CookError {
        match e {
            crate::FileRefusal::Cancelled => CookError::cancelled(self.path),
            crate::FileRefusal::TooLarge { .. } => {
                CookError::new(self.path, ErrorKind::Resource, e.to_string())
                    .at_param(param.name)
                    .with_source(e)
            }
            e => self.io(param, e),
        }
    }

    /// Refuses, before anything is allocated, a result estimated at `bytes`
    /// (`what` says what was counted) that the memory budget cannot hold.
    pub fn reserve(&self, param: &ParamSpec, bytes: f64, what: &str) -> Result<(), CookError> {
        let budget = self.env.memory_budget;
        if bytes <= budget as f64 {
            return Ok(());
        }
        Err(CookError::new(
            self.path,
            ErrorKind::Resource,
            format!(
                "{what} would need about {}, more than the memory budget of {} (GEODE_MEMORY_MB)",
                human_bytes(bytes),
                human_bytes(budget as f64)
            ),
        )
        .at_param(param.name))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::error::Error;

    /// The error a cook error came from is its source as itself: it
    /// downcasts, and its own chain follows.
    #[test]
    fn a_cook_errors_source_downcasts_to_what_it_came_from() {
        let e = CookError::new("/f", ErrorKind::Io, "disk full")
            .at_param("file")
            .with_source(std::io::Error::other("disk full"));
        let source = e.source().expect("a source");
        assert!(source.downcast_ref::<std::io::Error>().is_some());
        assert_eq!(e.to_string(), "/f (parameter `file`): disk full");
        assert!(CookError::new("/f", ErrorKind::Input, "no input")
            .source()
            .is_none());
    }
}
