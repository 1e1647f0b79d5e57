//! The contract for parameter expressions: a language parses an expression
//! once (syntax, the channels it references, whether it reads the time) and
//! evaluates it per frame in a scope the engine fills. The node library plugs
//! the wrangle's language in, so parameters and snippets share one language
//! while the engine knows none.

use std::fmt::Debug;
use std::sync::Arc;

use crate::context::TextPosition;

/// What an expression gives: numbers (a scalar is one) or text.
#[derive(Clone, Debug, PartialEq)]
pub enum ExprValue {
    Num(Vec<f64>),
    Str(String),
}

/// A parse or evaluation error at a position of the expression's text.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}{message}", position.map(|p| format!("column {}: ", p.column)).unwrap_or_default())]
pub struct ExprError {
    pub position: Option<TextPosition>,
    pub message: String,
}

impl ExprError {
    pub fn new(message: impl Into<String>) -> ExprError {
        ExprError {
            position: None,
            message: message.into(),
        }
    }
}

/// What an expression may read while it is evaluated.
pub struct ExprScope<'a> {
    /// `$F` is this rounded, `$FF` this.
    pub frame: f64,
    /// `$FPS`; `$T` is `(frame - 1) / fps`.
    pub fps: f64,
    /// `$HIP`.
    pub hip: &'a str,
    /// `$OS`: the node's name.
    pub node: &'a str,
    /// A referenced parameter's value at this frame (`ch("../a/b")`), or
    /// None when there is no such parameter.
    pub channel: &'a dyn Fn(&str) -> Option<ExprValue>,
}

/// A parsed expression.
pub trait Expression: Send + Sync + Debug {
    /// The literal paths its `ch()` calls read, in order of appearance.
    fn references(&self) -> &[String];
    /// Whether it reads the frame or the time (`$F`, `$T`...).
    fn reads_time(&self) -> bool;
    fn eval(&self, scope: &ExprScope) -> Result<ExprValue, ExprError>;
}

/// An expression language.
pub trait ExprLanguage: Send + Sync {
    fn parse(&self, text: &str) -> Result<Arc<dyn Expression>, ExprError>;
}
