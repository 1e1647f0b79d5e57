//! HyperFun's tokens: numbers, names (case-insensitive, so lower-cased),
//! symbols; `--` comments to the end of the line. Each with its line and column.

use super::HfError;

#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Tok {
    Num(f64),
    Name(String),
    Sym(&'static str),
    End,
}

#[derive(Clone, Debug)]
pub(crate) struct Token {
    pub tok: Tok,
    pub line: usize,
    pub column: usize,
}

/// Longest first, so `<=` is not read as `<` then `=`.
const SYMBOLS: [&str; 22] = [
    "<=", ">=", "/=", "(", ")", "[", "]", "{", "}", ",", ";", "=", "+", "-", "*", "/", "^", "|",
    "&", "\\", "~", "<",
];

pub(crate) fn tokens(text: &str) -> Result<Vec<Token>, HfError> {
    let mut out = Vec::new();
    for (l, line) in text.lines().enumerate() {
        let chars: Vec<char> = line.chars().collect();
        let mut i = 0;
        while i < chars.len() {
            let c = chars[i];
            let at = |tok| Token {
                tok,
                line: l + 1,
                column: i + 1,
            };
            if c.is_whitespace() {
                i += 1;
            } else if c == '-' && chars.get(i + 1) == Some(&'-') {
                break;
            } else if c.is_ascii_digit()
                || (c == '.' && chars.get(i + 1).is_some_and(|d| d.is_ascii_digit()))
            {
                let start = i;
                while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                    i += 1;
                }
                if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                    let mut j = i + 1;
                    if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                        j += 1;
                    }
                    if j < chars.len() && chars[j].is_ascii_digit() {
                        i = j;
                        while i < chars.len() && chars[i].is_ascii_digit() {
                            i += 1;
                        }
                    }
                }
                let s: String = chars[start..i].iter().collect();
                let value = s
                    .parse::<f64>()
                    .map_err(|_| HfError::at(l + 1, start + 1, format!("'{s}' is not a number")))?;
                out.push(Token {
                    tok: Tok::Num(value),
                    line: l + 1,
                    column: start + 1,
                });
            } else if c.is_alphabetic() {
                let start = i;
                while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                    i += 1;
                }
                let s: String = chars[start..i].iter().collect::<String>().to_lowercase();
                out.push(Token {
                    tok: Tok::Name(s),
                    line: l + 1,
                    column: start + 1,
                });
            } else if c == '>' {
                let sym = if chars.get(i + 1) == Some(&'=') {
                    ">="
                } else {
                    ">"
                };
                out.push(at(Tok::Sym(sym)));
                i += sym.len();
            } else {
                let rest: String = chars[i..chars.len().min(i + 2)].iter().collect();
                let Some(sym) = SYMBOLS.iter().find(|s| rest.starts_with(**s)) else {
                    return Err(HfError::at(
                        l + 1,
                        i + 1,
                        format!("unexpected character '{c}'"),
                    ));
                };
                out.push(at(Tok::Sym(sym)));
                i += sym.len();
            }
        }
    }
    let line = text.lines().count().max(1);
    out.push(Token {
        tok: Tok::End,
        line,
        column: text.lines().last().map_or(1, |l| l.chars().count() + 1),
    });
    Ok(out)
}
