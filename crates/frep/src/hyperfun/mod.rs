//! HyperFun programs (`.hf`, the modelling language of seed 000's FRep
//! library) compiled to fields. A program's objects, statements and library
//! calls are run once, at compile time, on symbolic values: what depends on
//! the point becomes part of the field's DAG, what does not is folded to a
//! number. So loops with constant conditions unroll, an `if` on a constant
//! picks its branch, and an `if` on the point becomes a select (both
//! branches, blended by a 0/1 mask). A `while` whose condition depends on
//! the point cannot become a finite field and is refused.
//!
//! Conventions kept from HyperFun: names are case-insensitive, arrays count
//! from 1, the set operations are the R-functions `f1 + f2 ± sqrt(f1² + f2²)`,
//! transformations (`hfScale3D`, `hfRotate3DX`, ...) rewrite the coordinate
//! array they are given (inverse mappings) and return 1.

mod compile;
mod lex;
mod library;
mod parse;

use crate::field::Field;

/// Why a program could not be compiled, with the line and column (from 1)
/// where the problem starts.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("line {line}, column {column}: {message}")]
pub struct HfError {
    pub line: usize,
    pub column: usize,
    pub message: String,
}

impl HfError {
    pub(crate) fn at(line: usize, column: usize, message: String) -> HfError {
        HfError {
            line,
            column,
            message,
        }
    }
}

/// Compiles the object `object` of a HyperFun program (the last one defined
/// when None) to a field of x, y and z; `params` fills the object's
/// parameter array (`a[...]`), missing entries being 0.
pub fn parse_hf(text: &str, object: Option<&str>, params: &[f64]) -> Result<Field, HfError> {
    let objects = parse::objects(lex::tokens(text)?)?;
    compile::compile(&objects, object, params)
}
