//! What a cook receives besides its inputs: frame, node path, cancellation, progress; and its error type.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

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
}

/// A failed cook: the node, the parameter if one is to blame, and why.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{path}{}: {message}", param.as_ref().map(|p| format!(" (parameter `{p}`)")).unwrap_or_default())]
pub struct CookError {
    pub path: String,
    pub param: Option<String>,
    pub message: String,
    pub cancelled: bool,
}

impl CookError {
    pub fn new(path: &str, message: impl Into<String>) -> CookError {
        CookError {
            path: path.to_owned(),
            param: None,
            message: message.into(),
            cancelled: false,
        }
    }

    pub fn param(path: &str, param: &str, message: impl Into<String>) -> CookError {
        CookError {
            path: path.to_owned(),
            param: Some(param.to_owned()),
            message: message.into(),
            cancelled: false,
        }
    }

    pub fn cancelled(path: &str) -> CookError {
        CookError {
            path: path.to_owned(),
            param: None,
            message: "cancelled".into(),
            cancelled: true,
        }
    }
}

/// Receives (node path, fraction done) as cooks progress.
pub type ProgressFn<'a> = dyn Fn(&str, f32) + Sync + 'a;

/// The cook's surroundings. Kernels' long loops call [`CookContext::check`]
/// and [`CookContext::progress`].
pub struct CookContext<'a> {
    pub path: &'a str,
    pub frame: f64,
    pub cancel: &'a CancelToken,
    pub on_progress: &'a ProgressFn<'a>,
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

    /// Reports the fraction done (0 to 1) of this node's cook.
    pub fn progress(&self, fraction: f32) {
        (self.on_progress)(self.path, fraction.clamp(0.0, 1.0));
    }

    pub fn error(&self, message: impl Into<String>) -> CookError {
        CookError::new(self.path, message)
    }

    pub fn param_error(&self, param: &str, message: impl Into<String>) -> CookError {
        CookError::param(self.path, param, message)
    }
}
