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

mod apply;
pub mod ast;
mod bind;
mod budget;
mod builtins;
mod calls;
mod exec;
mod expr;
mod expression;
mod ir;
pub mod kdtree;
mod lex;
mod library;
mod lower;
pub mod noise;
mod parse;
mod run;
mod signatures;
pub mod ty;
mod world;

pub use bind::{BindSpec, Channel};
pub use expression::{parse_expression, Expression, Globals, Value, GLOBALS};
pub use ir::LANES;
pub use lex::Pos;
pub use run::{run, RunOptions, RunReport};
pub use signatures::{signatures, Signature};

use geode_geo::AttribClass;

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

/// Register counts per file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    pub f: u32,
    pub i: u32,
    pub s: u32,
    pub af: u32,
    pub ai: u32,
    pub as_: u32,
}

/// A compiled snippet, ready to run on the geometry it was compiled for.
pub struct Program {
    ops: Vec<ir::Op>,
    /// Each instruction's statement, for errors at run time.
    op_pos: Vec<Pos>,
    calls: Vec<ir::CallSite>,
    strings: Vec<String>,
    counts: Counts,
    bindings: Vec<bind::Binding>,
    written: Vec<bool>,
    run_over: AttribClass,
}

impl Program {
    /// Instructions, for tests and the curious.
    pub fn len(&self) -> usize {
        self.ops.len()
    }

    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// The attributes the snippet writes (created if missing).
    pub fn written(&self) -> Vec<&str> {
        self.bindings
            .iter()
            .zip(&self.written)
            .filter(|(_, w)| **w)
            .map(|(b, _)| b.name.as_str())
            .collect()
    }
}

/// Compiles `src` for a run over `spec.run_over` elements.
pub fn compile(src: &str, spec: &BindSpec) -> Result<Program, CompileError> {
    let tokens = lex::fold_prefixes(lex::lex(src)?)?;
    let snippet = parse::Parser::new(tokens).snippet()?;
    compile_snippet(&snippet, spec)
}

/// Compiles a parsed snippet.
fn compile_snippet(snippet: &ast::Snippet, spec: &BindSpec) -> Result<Program, CompileError> {
    let mut counts = Counts::default();
    let bindings = bind::bindings(snippet, spec, &mut counts)?;
    let mut lower = lower::Lower::new(snippet, &bindings, spec, counts);
    lower.snippet_body(&snippet.body)?;
    let written = std::mem::take(&mut lower.written);
    let (ops, op_pos, calls, strings, counts) = lower.finish();
    Ok(Program {
        ops,
        op_pos,
        calls,
        strings,
        counts,
        bindings,
        written,
        run_over: spec.run_over,
    })
}

/// ` (did you mean 'x'?)` for the known name closest to `name`, if close.
pub fn suggest<'n>(name: &str, known: impl Iterator<Item = &'n str>) -> String {
    let best = known
        .map(|k| (edit_distance(name, k), k))
        .filter(|(d, k)| *d <= (name.len().max(k.len()) / 3).max(1))
        .min();
    best.map_or(String::new(), |(_, k)| format!(" (did you mean '{k}'?)"))
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            cur[j + 1] = (prev[j] + usize::from(ca != *cb))
                .min(prev[j + 1] + 1)
                .min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

impl std::fmt::Debug for Program {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (i, op) in self.ops.iter().enumerate() {
            writeln!(f, "{i:4} {op:?}")?;
        }
        Ok(())
    }
}
