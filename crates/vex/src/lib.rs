//! geode's wrangle language: VEX snippets (SideFX's syntax and documented
//! semantics) compiled to a typed batch IR that runs over attribute
//! columns, `LANES` elements at a time and batches in parallel.
//!
//! `compile` parses, type-checks and lowers a snippet against the geometry
//! it will run on (attribute types decide untyped bindings and `point()`'s
//! result); `run` executes it on a copy of input 0. Every element reads the
//! input's snapshot; writes to other elements, new and removed geometry
//! apply after all elements ran, in element order, so results do not
//! depend on the thread count. The crate knows geometry through
//! `geode-geo` only.

//! The crate is laid out bottom-up: `error`, `ty`, `value`, `effect`,
//! `ir` and `program` at the bottom (data every layer shares); `run` (the
//! batch interpreter and the run's world) and `library` (the one table of
//! builtin functions: forms, lowering, lane functions, docs) on them;
//! `compile` on the library; `expression` on both. No module imports one
//! above it.

mod compile;
mod effect;
mod error;
mod expression;
mod ir;
pub mod kdtree;
mod library;
pub mod noise;
pub mod pattern;
mod program;
mod run;
pub mod ty;
mod value;

pub use compile::{ast, compile, suggest, BindSpec, Channel, Pos};
pub use error::{CompileError, RunError};
pub use expression::{parse_expression, Expression, Globals, Value, GLOBALS};
pub use ir::LANES;
pub use library::{docs_markdown, functions, signatures, Category, Function, Signature};
pub use program::Program;
pub use run::{run, RunOptions, RunReport};
