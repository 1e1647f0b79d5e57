//! The grammar of Houdini's group patterns: a pattern read into terms, each
//! error with the column (counted in characters from 1) where it starts.

use super::{Compare, PatternError, Selector, Term, TermOp};

/// The most terms one pattern may hold: a pattern is typed by a person, and
/// each term costs a pass over the elements.
pub const MAX_TERMS: usize = 4096;

/// Splits `text` into terms: space-separated tokens, a double-quoted string
/// (in `@name="a b"`) kept whole.
pub(super) fn terms(text: &str) -> Result<Vec<Term>, PatternError> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        if chars[i].is_whitespace() {
            i += 1;
            continue;
        }
        let start = i;
        let mut open_quote: Option<usize> = None;
        while i < chars.len() && (open_quote.is_some() || !chars[i].is_whitespace()) {
            if chars[i] == '"' {
                open_quote = if open_quote.is_some() { None } else { Some(i) };
            }
            i += 1;
        }
        if let Some(at) = open_quote {
            return Err(PatternError::at(
                at,
                "a quoted string is not closed (expected `\"`)",
            ));
        }
        if out.len() == MAX_TERMS {
            return Err(PatternError::at(
                start,
                format!("more than {MAX_TERMS} terms in one pattern"),
            ));
        }
        let token: String = chars[start..i].iter().collect();
        out.push(term(&token, start)?);
    }
    Ok(out)
}

/// One token: an optional `!` or `^`, then what it selects.
fn term(token: &str, column: usize) -> Result<Term, PatternError> {
    let (op, body, at) = match token.chars().next() {
        Some('!') => (TermOp::AllBut, &token[1..], column + 1),
        Some('^') => (TermOp::Remove, &token[1..], column + 1),
        _ => (TermOp::Add, token, column),
    };
    if body.is_empty() {
        return Err(PatternError::at(
            at,
            "expected a number, range, group name or @attribute test after the sign",
        ));
    }
    let selector = if body == "*" {
        Selector::All
    } else if let Some(test) = body.strip_prefix('@') {
        attribute_test(test, at + 1)?
    } else if body.starts_with(|c: char| c.is_ascii_digit()) {
        range(body, at)?
    } else {
        names(body, at)?
    };
    Ok(Term {
        op,
        selector,
        column: at,
    })
}

/// A group name, or a glob over group names (`*`, `?`, `[chars]`).
fn names(body: &str, at: usize) -> Result<Selector, PatternError> {
    for (k, c) in body.chars().enumerate() {
        if !(c.is_alphanumeric() || matches!(c, '_' | '*' | '?' | '[' | ']' | '.' | ':')) {
            return Err(PatternError::at(
                at + k,
                format!("`{c}` cannot be in a group name (expected letters, digits, `_` or the wildcards `*`, `?`, `[...]`)"),
            ));
        }
    }
    if body.matches('[').count() != body.matches(']').count() {
        return Err(PatternError::at(at, "a `[` in a group name is not closed"));
    }
    Ok(Selector::Names(body.to_owned()))
}

/// `n`, `n-m`, `n-m:step` or `n-m:keep,step`.
fn range(body: &str, at: usize) -> Result<Selector, PatternError> {
    let (span, filter) = match body.split_once(':') {
        Some((s, f)) => (s, Some(f)),
        None => (body, None),
    };
    let number = |s: &str, col: usize, what: &str| -> Result<usize, PatternError> {
        s.parse::<usize>().map_err(|_| {
            PatternError::at(
                col,
                format!("expected {what} (a whole number), found `{s}`"),
            )
        })
    };
    let (first, last) = match span.split_once('-') {
        Some((a, b)) => (
            number(a, at, "the first number of the range")?,
            number(
                b,
                at + a.chars().count() + 1,
                "the last number of the range",
            )?,
        ),
        None => {
            let n = number(span, at, "a number")?;
            (n, n)
        }
    };
    let (keep, step) = match filter {
        None => (1, 1),
        Some(f) => {
            let col = at + span.chars().count() + 1;
            let (keep, step, step_col) = match f.split_once(',') {
                Some((k, s)) => {
                    let step_col = col + k.chars().count() + 1;
                    (
                        number(k, col, "how many to keep")?,
                        number(s, step_col, "the step")?,
                        step_col,
                    )
                }
                None => (1, number(f, col, "the step")?, col),
            };
            if keep == 0 {
                return Err(PatternError::at(col, "the count kept must be at least 1"));
            }
            if step == 0 {
                return Err(PatternError::at(step_col, "the step must be at least 1"));
            }
            (keep.min(step), step)
        }
    };
    Ok(Selector::Range {
        first,
        last,
        keep,
        step,
    })
}

/// `name op value`: the name with an optional component (`.x`..`.w`,
/// `[k]`); `=`/`==`, `!=`, `<`, `<=`, `>`, `>=`; the value a number, or a
/// string (quoted when it holds spaces) with wildcards.
fn attribute_test(test: &str, at: usize) -> Result<Selector, PatternError> {
    let Some(op_at) = test.find(['=', '!', '<', '>']) else {
        return Err(PatternError::at(
            at + test.chars().count(),
            "expected a comparison after the attribute name (`=`, `==`, `!=`, `<`, `<=`, `>`, `>=`)",
        ));
    };
    let (lhs, rest) = test.split_at(op_at);
    let op_col = at + lhs.chars().count();
    let (op, value) = if let Some(v) = rest.strip_prefix("==") {
        (Compare::Eq, v)
    } else if let Some(v) = rest.strip_prefix("!=") {
        (Compare::Ne, v)
    } else if let Some(v) = rest.strip_prefix("<=") {
        (Compare::Le, v)
    } else if let Some(v) = rest.strip_prefix(">=") {
        (Compare::Ge, v)
    } else if let Some(v) = rest.strip_prefix('=') {
        (Compare::Eq, v)
    } else if let Some(v) = rest.strip_prefix('<') {
        (Compare::Lt, v)
    } else if let Some(v) = rest.strip_prefix('>') {
        (Compare::Gt, v)
    } else {
        return Err(PatternError::at(
            op_col,
            "expected `!=` (a lone `!` is no comparison)",
        ));
    };
    let (name, component) = attribute_name(lhs, at)?;
    let value_col = op_col + (rest.len() - value.len());
    if value.is_empty() {
        return Err(PatternError::at(
            value_col,
            "expected a value after the comparison",
        ));
    }
    let value = match value.strip_prefix('"') {
        Some(v) => v
            .strip_suffix('"')
            .ok_or_else(|| PatternError::at(value_col, "a quoted value must end with `\"`"))?
            .to_owned(),
        None => value.to_owned(),
    };
    Ok(Selector::Attribute {
        name,
        component,
        op,
        value,
        value_column: value_col,
    })
}

/// `name`, `name.y` or `name[2]` as the name and component.
fn attribute_name(lhs: &str, at: usize) -> Result<(String, usize), PatternError> {
    let (name, component) = if let Some((name, c)) = lhs.split_once('.') {
        let k = match c {
            "x" | "r" | "u" => 0,
            "y" | "g" | "v" => 1,
            "z" | "b" => 2,
            "w" | "a" => 3,
            _ => {
                return Err(PatternError::at(
                    at + name.chars().count() + 1,
                    format!("expected a component `x`, `y`, `z` or `w` after `.`, found `{c}`"),
                ))
            }
        };
        (name, k)
    } else if let Some((name, k)) = lhs.strip_suffix(']').and_then(|l| l.split_once('[')) {
        let k = k.parse::<usize>().map_err(|_| {
            PatternError::at(
                at + name.chars().count() + 1,
                format!("expected a component number in `[...]`, found `{k}`"),
            )
        })?;
        (name, k)
    } else {
        (lhs, 0)
    };
    if name.is_empty() || !name.chars().all(|c| c.is_alphanumeric() || c == '_') {
        return Err(PatternError::at(
            at,
            format!("expected an attribute name after `@`, found `{name}`"),
        ));
    }
    Ok((name.to_owned(), component))
}
