//! Import of fidget's `.vm` SSA text format (one `id opcode args...` per line;
//! its sign convention is negative inside, so the result is negated for ours).

use std::collections::HashMap;

use crate::field::{Binary, Field, Unary};

/// A `.vm` line that could not be understood.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("line {line}: {message}")]
pub struct VmError {
    pub line: usize,
    pub message: String,
}

/// Parses a `.vm` program into a field with geode's sign (f >= 0 inside).
pub fn parse_vm(text: &str) -> Result<Field, VmError> {
    let mut values: HashMap<&str, Field> = HashMap::new();
    let mut last: Option<Field> = None;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let err = |m: String| VmError { line, message: m };
        let toks: Vec<&str> = content.split_whitespace().collect();
        if toks.len() < 2 {
            return Err(err(format!(
                "expected `id opcode args...`, found `{content}`"
            )));
        }
        let arg = |k: usize| -> Result<Field, VmError> {
            let name = toks
                .get(k)
                .ok_or_else(|| err(format!("`{}` needs more arguments", toks[1])))?;
            values
                .get(name)
                .cloned()
                .ok_or_else(|| err(format!("`{name}` is used before it is defined")))
        };
        let unary = |op: Unary| arg(2).map(|a| a.unary(op));
        let binary = |op: Binary| Ok::<Field, VmError>(arg(2)?.binary(op, arg(3)?));
        let f = match toks[1] {
            "var-x" => Field::x(),
            "var-y" => Field::y(),
            "var-z" => Field::z(),
            "const" => {
                let v = toks
                    .get(2)
                    .and_then(|t| t.parse::<f64>().ok())
                    .ok_or_else(|| err("`const` needs a number".into()))?;
                Field::constant(v)
            }
            "abs" => unary(Unary::Abs)?,
            "neg" => unary(Unary::Neg)?,
            "sqrt" => unary(Unary::Sqrt)?,
            "square" => unary(Unary::Square)?,
            "floor" => unary(Unary::Floor)?,
            "ceil" => unary(Unary::Ceil)?,
            "round" => unary(Unary::Round)?,
            "sin" => unary(Unary::Sin)?,
            "cos" => unary(Unary::Cos)?,
            "tan" => unary(Unary::Tan)?,
            "asin" => unary(Unary::Asin)?,
            "acos" => unary(Unary::Acos)?,
            "atan" => unary(Unary::Atan)?,
            "ln" => unary(Unary::Ln)?,
            "exp" => unary(Unary::Exp)?,
            "not" => unary(Unary::Not)?,
            "add" => binary(Binary::Add)?,
            "sub" => binary(Binary::Sub)?,
            "mul" => binary(Binary::Mul)?,
            "div" => binary(Binary::Div)?,
            "min" => binary(Binary::Min)?,
            "max" => binary(Binary::Max)?,
            "atan2" => binary(Binary::Atan2)?,
            "compare" => binary(Binary::Compare)?,
            "mod" => binary(Binary::Mod)?,
            "and" => binary(Binary::And)?,
            "or" => binary(Binary::Or)?,
            other => return Err(err(format!("unknown opcode `{other}`"))),
        };
        values.insert(toks[0], f.clone());
        last = Some(f);
    }
    let out = last.ok_or(VmError {
        line: 0,
        message: "the program is empty".into(),
    })?;
    Ok(-out)
}
