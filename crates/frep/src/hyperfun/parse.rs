//! HyperFun's grammar, read by recursive descent into objects of
//! statements and expressions. Precedence, lowest first: `or`, `and`,
//! `not`, relations, the set operations `| & \` (below arithmetic, as the
//! language defines), `+ -`, `* /`, `^` (right to left), unary `- ~`. Nesting
//! deeper than `MAX_DEPTH` is refused with the position where it goes over.

use super::lex::{Tok, Token};
use super::HfError;

/// Where a construct starts, for errors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Pos {
    pub line: usize,
    pub column: usize,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Op {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Union,
    Intersect,
    Subtract,
    Less,
    Greater,
    LessEq,
    GreaterEq,
    Equal,
    NotEqual,
    And,
    Or,
}

#[derive(Clone, Debug)]
pub(crate) enum Expr {
    Num(f64),
    Var(String, Pos),
    Elem(String, Box<Expr>, Pos),
    Call(String, Vec<Expr>, Pos),
    List(Vec<Expr>, Pos),
    Neg(Box<Expr>),
    Complement(Box<Expr>),
    Not(Box<Expr>),
    Binary(Op, Box<Expr>, Box<Expr>, Pos),
}

#[derive(Clone, Debug)]
pub(crate) enum Stmt {
    Arrays(Vec<(String, usize, Pos)>),
    Assign(String, Option<Expr>, Expr, Pos),
    Call(Expr),
    If(Expr, Vec<Stmt>, Vec<Stmt>, Pos),
    While(Expr, Vec<Stmt>, Pos),
}

/// `name(coords[3], params[n]) { body }`.
#[derive(Clone, Debug)]
pub(crate) struct Object {
    pub name: String,
    pub coords: (String, usize),
    pub params: Option<(String, usize)>,
    pub body: Vec<Stmt>,
    pub pos: Pos,
}

struct Parser {
    toks: Vec<Token>,
    at: usize,
    /// How deep the tree being built is: nested statements, operands and
    /// chains of operators all count, so neither this parser, nor the
    /// compiler walking its tree, nor dropping it recurses past `MAX_DEPTH`.
    depth: usize,
}

/// The deepest nesting a program may have (VEX's limit: programs written by
/// hand stay far below; a generated or hostile one is refused before it can
/// overflow the stack).
pub(crate) const MAX_DEPTH: usize = 200;

pub(crate) fn objects(toks: Vec<Token>) -> Result<Vec<Object>, HfError> {
    let mut p = Parser {
        toks,
        at: 0,
        depth: 0,
    };
    let mut out = Vec::new();
    while p.peek() != &Tok::End {
        out.push(p.object()?);
    }
    if out.is_empty() {
        return Err(p.error("expected an object: name(x[3], a[1]) { ... }"));
    }
    Ok(out)
}

impl Parser {
    /// Runs `f` `1 + extra` levels deeper, refusing to go past `MAX_DEPTH`.
    fn nested<T>(
        &mut self,
        extra: usize,
        f: impl FnOnce(&mut Parser) -> Result<T, HfError>,
    ) -> Result<T, HfError> {
        let levels = 1 + extra;
        if self.depth + levels > MAX_DEPTH {
            return Err(self.error(format!("nested too deeply (more than {MAX_DEPTH} levels)")));
        }
        self.depth += levels;
        let r = f(self);
        self.depth -= levels;
        r
    }

    fn peek(&self) -> &Tok {
        &self.toks[self.at].tok
    }

    fn pos(&self) -> Pos {
        let t = &self.toks[self.at];
        Pos {
            line: t.line,
            column: t.column,
        }
    }

    fn error(&self, message: impl Into<String>) -> HfError {
        let p = self.pos();
        HfError::at(p.line, p.column, message.into())
    }

    fn next(&mut self) -> Tok {
        let t = self.toks[self.at].tok.clone();
        if t != Tok::End {
            self.at += 1;
        }
        t
    }

    fn is_sym(&self, s: &str) -> bool {
        matches!(self.peek(), Tok::Sym(x) if *x == s)
    }

    fn is_word(&self, w: &str) -> bool {
        matches!(self.peek(), Tok::Name(x) if x == w)
    }

    fn expect(&mut self, s: &str) -> Result<(), HfError> {
        if self.is_sym(s) {
            self.next();
            Ok(())
        } else {
            Err(self.error(format!("expected '{s}', found {}", describe(self.peek()))))
        }
    }

    fn expect_word(&mut self, w: &str) -> Result<(), HfError> {
        if self.is_word(w) {
            self.next();
            Ok(())
        } else {
            Err(self.error(format!("expected '{w}', found {}", describe(self.peek()))))
        }
    }

    fn name(&mut self) -> Result<String, HfError> {
        match self.peek().clone() {
            Tok::Name(n) if !is_keyword(&n) => {
                self.next();
                Ok(n)
            }
            t => Err(self.error(format!("expected a name, found {}", describe(&t)))),
        }
    }

    fn size(&mut self) -> Result<usize, HfError> {
        self.expect("[")?;
        let n = match self.next() {
            Tok::Num(v) if v >= 1.0 && v.fract() == 0.0 && v <= 1e6 => v as usize,
            t => {
                self.at -= 1;
                return Err(self.error(format!(
                    "expected an array size (a whole number from 1), found {}",
                    describe(&t)
                )));
            }
        };
        self.expect("]")?;
        Ok(n)
    }

    fn object(&mut self) -> Result<Object, HfError> {
        let pos = self.pos();
        let name = self.name()?;
        self.expect("(")?;
        let coords = (self.name()?, self.size()?);
        let params = if self.is_sym(",") {
            self.next();
            Some((self.name()?, self.size()?))
        } else {
            None
        };
        self.expect(")")?;
        self.expect("{")?;
        let body = self.statements(&["}"])?;
        self.expect("}")?;
        Ok(Object {
            name,
            coords,
            params,
            body,
            pos,
        })
    }

    /// Statements up to (not including) one of the closing words or symbols.
    fn statements(&mut self, until: &[&str]) -> Result<Vec<Stmt>, HfError> {
        let mut out = Vec::new();
        loop {
            if until.iter().any(|u| self.is_sym(u) || self.is_word(u)) {
                return Ok(out);
            }
            if self.peek() == &Tok::End {
                return Err(self.error(format!(
                    "expected '{}' before the end of the file",
                    until[0]
                )));
            }
            out.push(self.statement()?);
        }
    }

    fn statement(&mut self) -> Result<Stmt, HfError> {
        self.nested(0, Parser::statement_here)
    }

    fn statement_here(&mut self) -> Result<Stmt, HfError> {
        let pos = self.pos();
        let stmt = if self.is_word("array") {
            self.next();
            let mut arrays = Vec::new();
            loop {
                let at = self.pos();
                let n = self.name()?;
                arrays.push((n, self.size()?, at));
                if !self.is_sym(",") {
                    break;
                }
                self.next();
            }
            Stmt::Arrays(arrays)
        } else if self.is_word("if") {
            self.next();
            let cond = self.expr()?;
            self.expect_word("then")?;
            let then = self.statements(&["else", "endif"])?;
            let otherwise = if self.is_word("else") {
                self.next();
                self.statements(&["endif"])?
            } else {
                Vec::new()
            };
            self.expect_word("endif")?;
            Stmt::If(cond, then, otherwise, pos)
        } else if self.is_word("while") {
            self.next();
            let cond = self.expr()?;
            self.expect_word("loop")?;
            let body = self.statements(&["endloop"])?;
            self.expect_word("endloop")?;
            Stmt::While(cond, body, pos)
        } else {
            let name = self.name()?;
            if self.is_sym("(") {
                self.at -= 1;
                Stmt::Call(self.primary()?)
            } else {
                let index = if self.is_sym("[") {
                    self.next();
                    let i = self.expr()?;
                    self.expect("]")?;
                    Some(i)
                } else {
                    None
                };
                self.expect("=")?;
                Stmt::Assign(name, index, self.expr()?, pos)
            }
        };
        self.expect(";")?;
        Ok(stmt)
    }

    fn expr(&mut self) -> Result<Expr, HfError> {
        self.binary_level(0)
    }

    /// One precedence level of left-associative binary operators.
    fn binary_level(&mut self, level: usize) -> Result<Expr, HfError> {
        const LEVELS: [&[(&str, Op)]; 5] = [
            &[("or", Op::Or)],
            &[("and", Op::And)],
            &[],
            &[("|", Op::Union), ("&", Op::Intersect), ("\\", Op::Subtract)],
            &[("+", Op::Add), ("-", Op::Sub)],
        ];
        if level == LEVELS.len() {
            return self.product();
        }
        if level == 2 && self.is_word("not") {
            self.next();
            let e = self.nested(0, |p| p.binary_level(level))?;
            return Ok(Expr::Not(Box::new(e)));
        }
        if level == 2 {
            return self.relations();
        }
        let mut left = self.binary_level(level + 1)?;
        let mut chain = 0;
        loop {
            let pos = self.pos();
            let Some(&(_, op)) = LEVELS[level]
                .iter()
                .find(|(s, _)| self.is_sym(s) || self.is_word(s))
            else {
                return Ok(left);
            };
            self.next();
            // `a + b + c...` nests to the left: each operator is a level.
            chain += 1;
            let right = self.nested(chain, |p| p.binary_level(level + 1))?;
            left = Expr::Binary(op, Box::new(left), Box::new(right), pos);
        }
    }

    /// `a < b`, and chains such as `2 <= y < 5.5`, read as `2 <= y and y < 5.5`.
    fn relations(&mut self) -> Result<Expr, HfError> {
        const RELATIONS: [(&str, Op); 6] = [
            ("<=", Op::LessEq),
            (">=", Op::GreaterEq),
            ("/=", Op::NotEqual),
            ("<", Op::Less),
            (">", Op::Greater),
            ("=", Op::Equal),
        ];
        let mut operand = self.binary_level(3)?;
        let mut chain: Option<Expr> = None;
        let mut links = 0;
        loop {
            let pos = self.pos();
            let Some(&(_, op)) = RELATIONS.iter().find(|(s, _)| self.is_sym(s)) else {
                return Ok(chain.unwrap_or(operand));
            };
            self.next();
            // Each link of a chain nests the `and` one level deeper.
            links += 1;
            let right = self.nested(links, |p| p.binary_level(3))?;
            let relation = Expr::Binary(op, Box::new(operand), Box::new(right.clone()), pos);
            chain = Some(match chain {
                None => relation,
                Some(c) => Expr::Binary(Op::And, Box::new(c), Box::new(relation), pos),
            });
            operand = right;
        }
    }

    fn product(&mut self) -> Result<Expr, HfError> {
        let mut left = self.power()?;
        let mut chain = 0;
        loop {
            let pos = self.pos();
            let op = if self.is_sym("*") {
                Op::Mul
            } else if self.is_sym("/") {
                Op::Div
            } else {
                return Ok(left);
            };
            self.next();
            chain += 1;
            let right = self.nested(chain, Parser::power)?;
            left = Expr::Binary(op, Box::new(left), Box::new(right), pos);
        }
    }

    fn power(&mut self) -> Result<Expr, HfError> {
        let base = self.unary()?;
        if self.is_sym("^") {
            let pos = self.pos();
            self.next();
            let exponent = self.nested(0, Parser::power)?;
            return Ok(Expr::Binary(
                Op::Pow,
                Box::new(base),
                Box::new(exponent),
                pos,
            ));
        }
        Ok(base)
    }

    fn unary(&mut self) -> Result<Expr, HfError> {
        self.nested(0, Parser::unary_here)
    }

    fn unary_here(&mut self) -> Result<Expr, HfError> {
        if self.is_sym("-") {
            self.next();
            return Ok(Expr::Neg(Box::new(self.unary()?)));
        }
        if self.is_sym("+") {
            self.next();
            return self.unary();
        }
        if self.is_sym("~") {
            self.next();
            return Ok(Expr::Complement(Box::new(self.unary()?)));
        }
        self.primary()
    }

    fn primary(&mut self) -> Result<Expr, HfError> {
        let pos = self.pos();
        match self.peek().clone() {
            Tok::Num(v) => {
                self.next();
                Ok(Expr::Num(v))
            }
            Tok::Sym("(") => {
                self.next();
                let e = self.expr()?;
                self.expect(")")?;
                Ok(e)
            }
            Tok::Sym("[") => {
                self.next();
                let mut items = vec![self.expr()?];
                while self.is_sym(",") {
                    self.next();
                    items.push(self.expr()?);
                }
                self.expect("]")?;
                Ok(Expr::List(items, pos))
            }
            Tok::Name(_) => {
                let name = self.name()?;
                if self.is_sym("(") {
                    self.next();
                    let mut args = Vec::new();
                    if !self.is_sym(")") {
                        args.push(self.expr()?);
                        while self.is_sym(",") {
                            self.next();
                            args.push(self.expr()?);
                        }
                    }
                    self.expect(")")?;
                    Ok(Expr::Call(name, args, pos))
                } else if self.is_sym("[") {
                    self.next();
                    let i = self.expr()?;
                    self.expect("]")?;
                    Ok(Expr::Elem(name, Box::new(i), pos))
                } else {
                    Ok(Expr::Var(name, pos))
                }
            }
            t => Err(self.error(format!("expected a value, found {}", describe(&t)))),
        }
    }
}

const KEYWORDS: [&str; 11] = [
    "array", "if", "then", "else", "endif", "while", "loop", "endloop", "and", "or", "not",
];

fn is_keyword(n: &str) -> bool {
    KEYWORDS.contains(&n)
}

fn describe(t: &Tok) -> String {
    match t {
        Tok::Num(v) => format!("the number {v}"),
        Tok::Name(n) => format!("'{n}'"),
        Tok::Sym(s) => format!("'{s}'"),
        Tok::End => "the end of the file".to_string(),
    }
}
