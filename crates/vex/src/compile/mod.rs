//! The compiler: lexing, parsing, finding the snippet's bindings, and
//! lowering to the batch IR, with calls resolved against the library
//! table. Nothing here runs a snippet.

pub mod ast;
mod bind;
pub mod lex;
mod lower;
pub mod parse;

pub use bind::{BindSpec, Channel};
pub use lex::Pos;
pub(crate) use lower::type_of;

use crate::error::CompileError;
use crate::program::{Counts, Program};

/// Compiles `src` for a run over `spec.run_over` elements.
pub fn compile(src: &str, spec: &BindSpec) -> Result<Program, CompileError> {
    let tokens = lex::fold_prefixes(lex::lex(src)?)?;
    let snippet = parse::Parser::new(tokens).snippet()?;
    compile_snippet(&snippet, spec)
}

/// Compiles a parsed snippet.
pub(crate) fn compile_snippet(
    snippet: &ast::Snippet,
    spec: &BindSpec,
) -> Result<Program, CompileError> {
    let mut counts = Counts::default();
    let bindings = bind::bindings(snippet, spec, &mut counts)?;
    let mut lower = lower::Lower::new(snippet, &bindings, spec, counts);
    lower.snippet_body(&snippet.body)?;
    let written = std::mem::take(&mut lower.written);
    let ramps = std::mem::take(&mut lower.ramps);
    let l = lower.finish();
    Ok(Program {
        ops: l.ops,
        op_pos: l.op_pos,
        calls: l.calls,
        strings: l.strings,
        counts: l.counts,
        bindings,
        written,
        run_over: spec.run_over,
        ramps,
        constants: l.constants,
        uniform: l.uniform,
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

/// Edits between `a` and `b` (insertions, deletions, substitutions and
/// swaps of neighbours: `nosie` is one edit from `noise`).
fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    // Three rows: the one two back serves the swaps.
    let mut older: Vec<usize> = vec![0; b.len() + 1];
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for i in 0..a.len() {
        let mut cur = vec![i + 1; b.len() + 1];
        for j in 0..b.len() {
            let mut d = (prev[j] + usize::from(a[i] != b[j]))
                .min(prev[j + 1] + 1)
                .min(cur[j] + 1);
            if i > 0 && j > 0 && a[i] == b[j - 1] && a[i - 1] == b[j] {
                d = d.min(older[j - 1] + 1);
            }
            cur[j + 1] = d;
        }
        older = std::mem::replace(&mut prev, cur);
    }
    prev[b.len()]
}

/// The type the last statement of `src` (a call) lowers to with `hint`,
/// after the statements before it: the library table's tests check each
/// form's return type with it.
#[cfg(test)]
pub(crate) fn last_call_type(
    src: &str,
    hint: Option<crate::ty::Ty>,
    spec: &BindSpec,
) -> Result<crate::ty::Ty, CompileError> {
    let tokens = lex::fold_prefixes(lex::lex(src)?)?;
    let snippet = parse::Parser::new(tokens).snippet()?;
    let mut counts = Counts::default();
    let bindings = bind::bindings(&snippet, spec, &mut counts)?;
    let mut lowering = lower::Lower::new(&snippet, &bindings, spec, counts);
    let (last, before) = snippet.body.split_last().expect("the call");
    lowering.snippet_body(before)?;
    let ast::Stmt::Expr(e) = last else {
        panic!("the call is an expression statement")
    };
    Ok(lowering.expr(e, hint)?.ty)
}
