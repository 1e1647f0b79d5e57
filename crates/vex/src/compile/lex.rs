//! VEX's tokens: identifiers, numbers, strings, `@` bindings and operators,
//! each with its line and column for error messages.

use crate::error::CompileError;

#[derive(Clone, Debug, PartialEq)]
pub enum Tok {
    Ident(String),
    Int(i64),
    Float(f64),
    Str(String),
    /// `@name` with its type prefix (`f`, `i`, `v`, `s`, `u`, `p`, `3`, `4`
    /// or none) and whether `[]` made it an array.
    Binding {
        prefix: Option<char>,
        array: bool,
        name: String,
    },
    Punct(&'static str),
    /// `$F`, `$HIP`: a global of a parameter expression (not VEX: a
    /// snippet that uses one is told so).
    Global(String),
    Eof,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Pos {
    pub line: u32,
    pub col: u32,
}

#[derive(Clone, Debug)]
pub struct Token {
    pub tok: Tok,
    pub pos: Pos,
}

/// Longest first, so `<<=` wins over `<<` and `<`.
const PUNCTS: &[&str] = &[
    "<<=", ">>=", "+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", "==", "!=", "<=", ">=", "&&",
    "||", "++", "--", "<<", ">>", "+", "-", "*", "/", "%", "<", ">", "=", "!", "~", "&", "|", "^",
    "?", ":", ";", ",", ".", "(", ")", "{", "}", "[", "]",
];

/// Splits `src` into tokens; comments (`//`, `/* */`) and `#pragma`-style
/// directive lines are skipped.
pub fn lex(src: &str) -> Result<Vec<Token>, CompileError> {
    let chars: Vec<char> = src.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line, mut col) = (0usize, 1u32, 1u32);
    let advance = |i: &mut usize, line: &mut u32, col: &mut u32, n: usize| {
        for _ in 0..n {
            if chars[*i] == '\n' {
                *line += 1;
                *col = 1;
            } else {
                *col += 1;
            }
            *i += 1;
        }
    };
    while i < chars.len() {
        let c = chars[i];
        let pos = Pos { line, col };
        if c.is_whitespace() {
            advance(&mut i, &mut line, &mut col, 1);
            continue;
        }
        if c == '/' && chars.get(i + 1) == Some(&'/') {
            while i < chars.len() && chars[i] != '\n' {
                advance(&mut i, &mut line, &mut col, 1);
            }
            continue;
        }
        if c == '/' && chars.get(i + 1) == Some(&'*') {
            advance(&mut i, &mut line, &mut col, 2);
            while i < chars.len() && !(chars[i] == '*' && chars.get(i + 1) == Some(&'/')) {
                advance(&mut i, &mut line, &mut col, 1);
            }
            if i >= chars.len() {
                return Err(CompileError::at(pos, "unterminated comment"));
            }
            advance(&mut i, &mut line, &mut col, 2);
            continue;
        }
        if c == '#' && col == 1 {
            // Preprocessor lines (#include, #pragma) are not needed by
            // wrangles; they are skipped as VEX's cpp would leave nothing.
            while i < chars.len() && chars[i] != '\n' {
                advance(&mut i, &mut line, &mut col, 1);
            }
            continue;
        }
        if c.is_ascii_digit() || (c == '.' && chars.get(i + 1).is_some_and(|d| d.is_ascii_digit()))
        {
            let start = i;
            let mut is_float = false;
            while i < chars.len()
                && (chars[i].is_ascii_alphanumeric() || chars[i] == '_' || chars[i] == '.')
            {
                if chars[i] == '.' {
                    is_float = true;
                }
                if (chars[i] == 'e' || chars[i] == 'E')
                    && !chars[start..i].iter().any(|c| *c == 'x' || *c == 'X')
                {
                    is_float = true;
                    if matches!(chars.get(i + 1), Some('+') | Some('-')) {
                        advance(&mut i, &mut line, &mut col, 1);
                    }
                }
                advance(&mut i, &mut line, &mut col, 1);
            }
            let text: String = chars[start..i].iter().filter(|c| **c != '_').collect();
            let text = text.trim_end_matches(['f', 'F']);
            let tok = if let Some(hex) = text.strip_prefix("0x").or_else(|| text.strip_prefix("0X"))
            {
                i64::from_str_radix(hex, 16).ok().map(Tok::Int)
            } else if is_float {
                text.parse::<f64>().ok().map(Tok::Float)
            } else {
                text.parse::<i64>().ok().map(Tok::Int)
            };
            let tok =
                tok.ok_or_else(|| CompileError::at(pos, format!("malformed number '{text}'")))?;
            out.push(Token { tok, pos });
            continue;
        }
        if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                advance(&mut i, &mut line, &mut col, 1);
            }
            out.push(Token {
                tok: Tok::Ident(chars[start..i].iter().collect()),
                pos,
            });
            continue;
        }
        if c == '"' || c == '\'' {
            let quote = c;
            advance(&mut i, &mut line, &mut col, 1);
            let mut s = String::new();
            loop {
                match chars.get(i) {
                    None | Some('\n') => return Err(CompileError::at(pos, "unterminated string")),
                    Some(&q) if q == quote => {
                        advance(&mut i, &mut line, &mut col, 1);
                        break;
                    }
                    Some('\\') => {
                        let e = chars.get(i + 1).copied().unwrap_or('\\');
                        s.push(match e {
                            'n' => '\n',
                            't' => '\t',
                            'r' => '\r',
                            '0' => '\0',
                            other => other,
                        });
                        let step = 2.min(chars.len() - i);
                        advance(&mut i, &mut line, &mut col, step);
                    }
                    Some(&ch) => {
                        s.push(ch);
                        advance(&mut i, &mut line, &mut col, 1);
                    }
                }
            }
            out.push(Token {
                tok: Tok::Str(s),
                pos,
            });
            continue;
        }
        if c == '$' {
            let start = i + 1;
            let mut end = start;
            while end < chars.len() && (chars[end].is_ascii_alphanumeric() || chars[end] == '_') {
                end += 1;
            }
            if end == start {
                return Err(CompileError::at(pos, "expected a variable name after '$'"));
            }
            let name: String = chars[start..end].iter().collect();
            let n = end - i;
            advance(&mut i, &mut line, &mut col, n);
            out.push(Token {
                tok: Tok::Global(name),
                pos,
            });
            continue;
        }
        if c == '@' {
            out.push(Token {
                tok: binding(&chars, &mut i, &mut line, &mut col, pos, &advance)?,
                pos,
            });
            continue;
        }
        let rest: String = chars[i..(i + 3).min(chars.len())].iter().collect();
        let Some(p) = PUNCTS.iter().find(|p| rest.starts_with(**p)) else {
            return Err(CompileError::at(pos, format!("unexpected character '{c}'")));
        };
        advance(&mut i, &mut line, &mut col, p.len());
        out.push(Token {
            tok: Tok::Punct(p),
            pos,
        });
    }
    out.push(Token {
        tok: Tok::Eof,
        pos: Pos { line, col },
    });
    Ok(out)
}

/// Reads `@name`, `f@name`, `v[]@name`: the prefix is the identifier or
/// digit just before `@`, already pushed as a token, so it is taken back.
fn binding(
    chars: &[char],
    i: &mut usize,
    line: &mut u32,
    col: &mut u32,
    pos: Pos,
    advance: &dyn Fn(&mut usize, &mut u32, &mut u32, usize),
) -> Result<Tok, CompileError> {
    advance(i, line, col, 1);
    let start = *i;
    while *i < chars.len() && (chars[*i].is_alphanumeric() || chars[*i] == '_') {
        advance(i, line, col, 1);
    }
    if start == *i {
        return Err(CompileError::at(
            pos,
            "expected an attribute name after '@'",
        ));
    }
    Ok(Tok::Binding {
        prefix: None,
        array: false,
        name: chars[start..*i].iter().collect(),
    })
}

/// Folds a type prefix written before `@` (`f@`, `v[]@`, `3@`) into the
/// binding that follows it: the lexer sees the prefix as an identifier or
/// number (and `[` `]`) directly touching the `@`.
pub fn fold_prefixes(tokens: Vec<Token>) -> Result<Vec<Token>, CompileError> {
    let mut out: Vec<Token> = Vec::with_capacity(tokens.len());
    for t in tokens {
        if let Tok::Binding { name, .. } = &t.tok {
            let array = out.len() >= 2
                && out[out.len() - 1].tok == Tok::Punct("]")
                && out[out.len() - 2].tok == Tok::Punct("[")
                && touching(&out[out.len() - 1], &t, 1);
            let back = if array { 2 } else { 0 };
            let prefix_tok = out.len().checked_sub(back + 1).map(|k| &out[k]);
            let prefix = prefix_tok.and_then(|p| {
                let len = if array { 3 } else { 1 };
                let letter = match &p.tok {
                    Tok::Ident(s) if s.len() == 1 => s.chars().next(),
                    Tok::Int(n @ 2..=4) if touching(p, &t, len) => char::from_digit(*n as u32, 10),
                    _ => None,
                }?;
                (touching(p, &t, len) && "fivsup234".contains(letter)).then_some(letter)
            });
            if array && prefix.is_none() {
                return Err(CompileError::at(
                    t.pos,
                    "'[]@' needs a type prefix, as in 'f[]@name'",
                ));
            }
            let name = name.clone();
            let pos = if prefix.is_some() {
                out.truncate(out.len() - back - 1);
                Pos {
                    line: t.pos.line,
                    col: t.pos.col - 1 - back as u32,
                }
            } else {
                t.pos
            };
            out.push(Token {
                tok: Tok::Binding {
                    prefix,
                    array,
                    name,
                },
                pos,
            });
        } else {
            out.push(t);
        }
    }
    Ok(out)
}

/// Whether `a` ends `gap` columns before `b` starts on the same line, i.e.
/// they are written together (`f@x`, not `f @x`).
fn touching(a: &Token, b: &Token, gap: u32) -> bool {
    a.pos.line == b.pos.line && a.pos.col + gap == b.pos.col
}
