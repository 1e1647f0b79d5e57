//! A recursive-descent parser for VEX snippets: statements, declarations,
//! functions defined in the snippet, and expressions by precedence climbing.

use crate::compile::ast::*;
use crate::compile::lex::{Pos, Tok, Token};
use crate::error::CompileError;
use crate::ty::Ty;

pub struct Parser {
    toks: Vec<Token>,
    at: usize,
    /// How deep the tree being built is: nested statements, operands and
    /// chains of operators all count, so neither this parser nor the passes
    /// that walk its tree recurse past `MAX_DEPTH`.
    depth: usize,
}

/// The deepest nesting a snippet may have (VEX written by hand stays far
/// below; a generated or hostile one is refused before it can overflow the
/// stack).
pub const MAX_DEPTH: usize = 200;

/// Binary operators by precedence, loosest first (C's table).
const LEVELS: &[&[&str]] = &[
    &["||"],
    &["&&"],
    &["|"],
    &["^"],
    &["&"],
    &["==", "!="],
    &["<", ">", "<=", ">="],
    &["<<", ">>"],
    &["+", "-"],
    &["*", "/", "%"],
];

const ASSIGN_OPS: &[&str] = &[
    "=", "+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", "<<=", ">>=",
];

type PResult<T> = Result<T, CompileError>;

impl Parser {
    pub fn new(toks: Vec<Token>) -> Parser {
        Parser {
            toks,
            at: 0,
            depth: 0,
        }
    }

    /// Runs `f` `1 + extra` levels deeper, refusing to go past `MAX_DEPTH`.
    fn nested<T>(&mut self, extra: usize, f: impl FnOnce(&mut Parser) -> PResult<T>) -> PResult<T> {
        let levels = 1 + extra;
        if self.depth + levels > MAX_DEPTH {
            return Err(CompileError::at(
                self.pos(),
                format!("nested too deeply (more than {MAX_DEPTH} levels; each operator of a chain counts one: split a long one into statements)"),
            ));
        }
        self.depth += levels;
        let r = f(self);
        self.depth -= levels;
        r
    }

    fn peek(&self) -> &Tok {
        &self.toks[self.at].tok
    }

    fn peek_at(&self, k: usize) -> &Tok {
        &self.toks[(self.at + k).min(self.toks.len() - 1)].tok
    }

    fn pos(&self) -> Pos {
        self.toks[self.at].pos
    }

    fn bump(&mut self) -> Token {
        let t = self.toks[self.at].clone();
        if self.at + 1 < self.toks.len() {
            self.at += 1;
        }
        t
    }

    fn is(&self, p: &str) -> bool {
        matches!(self.peek(), Tok::Punct(q) if *q == p)
    }

    fn eat(&mut self, p: &str) -> bool {
        if self.is(p) {
            self.bump();
            true
        } else {
            false
        }
    }

    fn expect(&mut self, p: &str) -> PResult<()> {
        if self.eat(p) {
            Ok(())
        } else {
            Err(CompileError::at(
                self.pos(),
                format!("expected '{p}' but found {}", describe(self.peek())),
            ))
        }
    }

    fn ident(&mut self) -> PResult<String> {
        match self.peek().clone() {
            Tok::Ident(s) => {
                self.bump();
                Ok(s)
            }
            other => Err(CompileError::at(
                self.pos(),
                format!("expected a name but found {}", describe(&other)),
            )),
        }
    }

    /// The type keyword at the cursor (not consumed), skipping `const`.
    fn type_here(&mut self) -> Option<Ty> {
        while matches!(self.peek(), Tok::Ident(s) if s == "const" || s == "export") {
            self.bump();
        }
        match self.peek() {
            Tok::Ident(s) => Ty::from_keyword(s),
            _ => None,
        }
    }

    /// `type` or `type[]`.
    fn parse_type(&mut self) -> PResult<Ty> {
        let pos = self.pos();
        let t = self
            .type_here()
            .ok_or_else(|| CompileError::at(pos, "expected a type"))?;
        self.bump();
        if self.is("[") && matches!(self.peek_at(1), Tok::Punct("]")) {
            self.bump();
            self.bump();
            return t
                .array()
                .ok_or_else(|| CompileError::at(pos, format!("no arrays of {t}")));
        }
        Ok(t)
    }

    /// Fails unless every token was read.
    pub fn end(&mut self) -> PResult<()> {
        match self.peek() {
            Tok::Eof => Ok(()),
            other => Err(CompileError::at(
                self.pos(),
                format!("expected the end but found {}", describe(other)),
            )),
        }
    }

    pub fn snippet(&mut self) -> PResult<Snippet> {
        let mut s = Snippet::default();
        while *self.peek() != Tok::Eof {
            if let Some(f) = self.function()? {
                s.functions.push(f);
            } else {
                s.body.push(self.statement()?);
            }
        }
        Ok(s)
    }

    /// A function definition at the cursor: `[function] type name(params) {`.
    fn function(&mut self) -> PResult<Option<Function>> {
        let start = self.at;
        let pos = self.pos();
        if matches!(self.peek(), Tok::Ident(s) if s == "function") {
            self.bump();
        }
        if self.type_here().is_none() {
            self.at = start;
            return Ok(None);
        }
        let ret = self.parse_type()?;
        let is_def =
            matches!(self.peek(), Tok::Ident(_)) && matches!(self.peek_at(1), Tok::Punct("("));
        if !is_def {
            self.at = start;
            return Ok(None);
        }
        let name = self.ident()?;
        self.expect("(")?;
        let mut params = Vec::new();
        let mut ty = None;
        while !self.is(")") {
            if self.type_here().is_some() {
                ty = Some(self.parse_type()?);
            }
            let pty =
                ty.ok_or_else(|| CompileError::at(self.pos(), "expected a parameter type"))?;
            let pname = self.ident()?;
            let pty = if self.is("[") {
                self.bump();
                self.expect("]")?;
                pty.array()
                    .ok_or_else(|| CompileError::at(self.pos(), "no arrays of arrays"))?
            } else {
                pty
            };
            params.push(Param {
                name: pname,
                ty: pty,
            });
            if self.eat(";") {
                ty = None;
            } else if !self.eat(",") {
                break;
            }
        }
        self.expect(")")?;
        let body = match self.block()? {
            Stmt::Block(b) => b,
            other => vec![other],
        };
        Ok(Some(Function {
            name,
            ret,
            params,
            body,
            pos,
        }))
    }

    fn block(&mut self) -> PResult<Stmt> {
        self.expect("{")?;
        let mut out = Vec::new();
        while !self.is("}") {
            if *self.peek() == Tok::Eof {
                return Err(CompileError::at(
                    self.pos(),
                    "expected '}' before the end of the snippet",
                ));
            }
            out.push(self.statement()?);
        }
        self.bump();
        Ok(Stmt::Block(out))
    }

    fn statement(&mut self) -> PResult<Stmt> {
        self.nested(0, Parser::statement_here)
    }

    fn statement_here(&mut self) -> PResult<Stmt> {
        let pos = self.pos();
        if self.is("{") {
            return self.block();
        }
        if self.eat(";") {
            return Ok(Stmt::Empty);
        }
        let word = match self.peek() {
            Tok::Ident(s) => s.clone(),
            _ => String::new(),
        };
        match word.as_str() {
            "if" => {
                self.bump();
                self.expect("(")?;
                let c = self.expr()?;
                self.expect(")")?;
                let then = Box::new(self.statement()?);
                let other = if matches!(self.peek(), Tok::Ident(s) if s == "else") {
                    self.bump();
                    Some(Box::new(self.statement()?))
                } else {
                    None
                };
                return Ok(Stmt::If(c, then, other));
            }
            "while" => {
                self.bump();
                self.expect("(")?;
                let c = self.expr()?;
                self.expect(")")?;
                return Ok(Stmt::While(c, Box::new(self.statement()?)));
            }
            "do" => {
                self.bump();
                let body = Box::new(self.statement()?);
                match self.ident()?.as_str() {
                    "while" => {}
                    _ => {
                        return Err(CompileError::at(
                            self.pos(),
                            "expected 'while' after a do body",
                        ))
                    }
                }
                self.expect("(")?;
                let c = self.expr()?;
                self.expect(")")?;
                self.expect(";")?;
                return Ok(Stmt::DoWhile(body, c));
            }
            "for" => {
                self.bump();
                self.expect("(")?;
                let init = if self.is(";") {
                    None
                } else {
                    Some(Box::new(self.simple_statement()?))
                };
                self.expect(";")?;
                let cond = if self.is(";") {
                    None
                } else {
                    Some(self.expr()?)
                };
                self.expect(";")?;
                let step = if self.is(")") {
                    None
                } else {
                    Some(self.comma_expr()?)
                };
                self.expect(")")?;
                return Ok(Stmt::For(init, cond, step, Box::new(self.statement()?)));
            }
            "foreach" => {
                self.bump();
                return self.foreach();
            }
            "break" => {
                self.bump();
                self.expect(";")?;
                return Ok(Stmt::Break(pos));
            }
            "continue" => {
                self.bump();
                self.expect(";")?;
                return Ok(Stmt::Continue(pos));
            }
            "return" => {
                self.bump();
                let v = if self.is(";") {
                    None
                } else {
                    Some(self.expr()?)
                };
                self.expect(";")?;
                return Ok(Stmt::Return(v, pos));
            }
            _ => {}
        }
        let s = self.simple_statement()?;
        self.expect(";")?;
        Ok(s)
    }

    /// A declaration or an expression (no trailing `;`): for-loop heads too.
    fn simple_statement(&mut self) -> PResult<Stmt> {
        let start = self.at;
        if self.type_here().is_some() && !matches!(self.peek_at(1), Tok::Punct("(")) {
            return self.declarations();
        }
        self.at = start;
        Ok(Stmt::Expr(self.comma_expr()?))
    }

    /// `a, b` in expression statements and for-loop steps: evaluated in order.
    fn comma_expr(&mut self) -> PResult<Expr> {
        let first = self.expr()?;
        if !self.is(",") {
            return Ok(first);
        }
        let pos = first.pos;
        let mut all = vec![first];
        while self.eat(",") {
            all.push(self.expr()?);
        }
        Ok(Expr {
            kind: ExprKind::Call("__sequence".into(), all),
            pos,
        })
    }

    fn declarations(&mut self) -> PResult<Stmt> {
        let base = self.parse_type()?;
        let mut out = Vec::new();
        loop {
            let pos = self.pos();
            let name = self.ident()?;
            let mut ty = base;
            if self.is("[") {
                self.bump();
                // A size inside the brackets is allowed by VEX and ignored.
                if !self.is("]") {
                    self.expr()?;
                }
                self.expect("]")?;
                ty = base
                    .array()
                    .ok_or_else(|| CompileError::at(pos, format!("no arrays of {base}")))?;
            }
            let init = if self.eat("=") {
                Some(self.expr()?)
            } else {
                None
            };
            out.push(Decl {
                name,
                ty,
                init,
                pos,
            });
            if !self.eat(",") {
                break;
            }
        }
        Ok(Stmt::Decls(out))
    }

    fn foreach(&mut self) -> PResult<Stmt> {
        self.expect("(")?;
        let pos = self.pos();
        let first_ty = self.parse_type()?;
        let first = self.ident()?;
        self.expect(";")?;
        // Three parts when a declaration follows: `foreach (int i; type x; array)`.
        let save = self.at;
        let three = self.type_here().is_some()
            && matches!(self.peek_at(1), Tok::Ident(_))
            && matches!(self.peek_at(2), Tok::Punct(";"));
        self.at = save;
        let (index, elem) = if three {
            if first_ty != Ty::Int {
                return Err(CompileError::at(pos, "the index of foreach must be an int"));
            }
            let epos = self.pos();
            let ty = self.parse_type()?;
            let name = self.ident()?;
            self.expect(";")?;
            (
                Some(first),
                Decl {
                    name,
                    ty,
                    init: None,
                    pos: epos,
                },
            )
        } else {
            (
                None,
                Decl {
                    name: first,
                    ty: first_ty,
                    init: None,
                    pos,
                },
            )
        };
        let array = self.expr()?;
        self.expect(")")?;
        let body = Box::new(self.statement()?);
        Ok(Stmt::Foreach {
            index,
            elem,
            array,
            body,
        })
    }

    /// After `seq[`: an index `seq[i]` or a slice `seq[start:end:step]`.
    fn index_or_slice(&mut self, seq: Expr, pos: Pos) -> PResult<Expr> {
        let part = |me: &mut Self| -> PResult<Option<Box<Expr>>> {
            if me.is(":") || me.is("]") {
                Ok(None)
            } else {
                Ok(Some(Box::new(me.expr()?)))
            }
        };
        let start = part(self)?;
        if !self.eat(":") {
            self.expect("]")?;
            let Some(i) = start else {
                return Err(CompileError::at(pos, "an index is missing between [ and ]"));
            };
            return Ok(Expr {
                kind: ExprKind::Index(Box::new(seq), i),
                pos,
            });
        }
        let end = part(self)?;
        let step = if self.eat(":") { part(self)? } else { None };
        self.expect("]")?;
        Ok(Expr {
            kind: ExprKind::Slice {
                seq: Box::new(seq),
                start,
                end,
                step,
            },
            pos,
        })
    }

    pub fn expr(&mut self) -> PResult<Expr> {
        let lhs = self.ternary()?;
        if let Tok::Punct(p) = *self.peek() {
            if ASSIGN_OPS.contains(&p) {
                let pos = self.pos();
                self.bump();
                // `a = b = c...` nests to the right: each `=` is a level.
                let rhs = self.nested(0, Parser::expr)?;
                return Ok(Expr {
                    kind: ExprKind::Assign(p, Box::new(lhs), Box::new(rhs)),
                    pos,
                });
            }
        }
        Ok(lhs)
    }

    fn ternary(&mut self) -> PResult<Expr> {
        let c = self.binary(0)?;
        if !self.is("?") {
            return Ok(c);
        }
        let pos = self.pos();
        self.bump();
        // `c ? x : c ? y : z...` nests to the right: each `?` is a level.
        let a = self.nested(0, Parser::expr)?;
        self.expect(":")?;
        let b = self.nested(0, Parser::expr)?;
        Ok(Expr {
            kind: ExprKind::Ternary(Box::new(c), Box::new(a), Box::new(b)),
            pos,
        })
    }

    fn binary(&mut self, level: usize) -> PResult<Expr> {
        if level == LEVELS.len() {
            return self.unary();
        }
        let mut lhs = self.binary(level + 1)?;
        let mut chain = 0;
        loop {
            let op = match *self.peek() {
                Tok::Punct(p) if LEVELS[level].contains(&p) => p,
                _ => return Ok(lhs),
            };
            let pos = self.pos();
            self.bump();
            // `a + b + c...` nests to the left: each operator is a level.
            chain += 1;
            let rhs = self.nested(chain, |me| me.binary(level + 1))?;
            lhs = Expr {
                kind: ExprKind::Binary(op, Box::new(lhs), Box::new(rhs)),
                pos,
            };
        }
    }

    fn unary(&mut self) -> PResult<Expr> {
        self.nested(0, Parser::unary_here)
    }

    fn unary_here(&mut self) -> PResult<Expr> {
        let pos = self.pos();
        if let Tok::Punct(p) = *self.peek() {
            match p {
                "-" | "!" | "~" | "+" => {
                    self.bump();
                    let e = self.unary()?;
                    return Ok(Expr {
                        kind: ExprKind::Unary(p, Box::new(e)),
                        pos,
                    });
                }
                "++" | "--" => {
                    self.bump();
                    let e = self.unary()?;
                    let delta = if p == "++" { 1 } else { -1 };
                    return Ok(Expr {
                        kind: ExprKind::IncDec {
                            delta,
                            prefix: true,
                            target: Box::new(e),
                        },
                        pos,
                    });
                }
                _ => {}
            }
        }
        self.postfix()
    }

    fn postfix(&mut self) -> PResult<Expr> {
        let mut e = self.primary()?;
        let mut chain = 0;
        loop {
            let pos = self.pos();
            chain += 1;
            if self.depth + chain > MAX_DEPTH {
                return Err(CompileError::at(
                    pos,
                    format!("nested too deeply (more than {MAX_DEPTH} levels; each operator of a chain counts one: split a long one into statements)"),
                ));
            }
            if self.eat(".") {
                let name = self.ident()?;
                e = Expr {
                    kind: ExprKind::Member(Box::new(e), name),
                    pos,
                };
            } else if self.eat("[") {
                e = self.index_or_slice(e, pos)?;
            } else if self.is("++") || self.is("--") {
                let delta = if self.is("++") { 1 } else { -1 };
                self.bump();
                e = Expr {
                    kind: ExprKind::IncDec {
                        delta,
                        prefix: false,
                        target: Box::new(e),
                    },
                    pos,
                };
            } else {
                return Ok(e);
            }
        }
    }

    fn primary(&mut self) -> PResult<Expr> {
        let pos = self.pos();
        let t = self.bump();
        let kind = match t.tok {
            Tok::Int(n) => ExprKind::Int(n),
            Tok::Float(x) => ExprKind::Float(x),
            Tok::Str(s) => {
                // Adjacent literals concatenate, as in C.
                let mut s = s;
                while let Tok::Str(more) = self.peek().clone() {
                    self.bump();
                    s.push_str(&more);
                }
                ExprKind::Str(s)
            }
            Tok::Binding {
                prefix,
                array,
                name,
            } => ExprKind::Binding {
                prefix,
                array,
                name,
            },
            Tok::Punct("(") => {
                let e = self.comma_expr()?;
                self.expect(")")?;
                return Ok(e);
            }
            Tok::Punct("{") => {
                let mut items = Vec::new();
                while !self.is("}") {
                    items.push(self.expr()?);
                    if !self.eat(",") {
                        break;
                    }
                }
                self.expect("}")?;
                ExprKind::Braces(items)
            }
            Tok::Ident(name) => {
                if self.is("(") {
                    self.bump();
                    let mut args = Vec::new();
                    while !self.is(")") {
                        args.push(self.expr()?);
                        if !self.eat(",") {
                            break;
                        }
                    }
                    self.expect(")")?;
                    match Ty::from_keyword(&name) {
                        Some(ty) if args.len() == 1 => {
                            ExprKind::Cast(ty, Box::new(args.pop().expect("one")))
                        }
                        _ => ExprKind::Call(name, args),
                    }
                } else {
                    ExprKind::Var(name)
                }
            }
            other => {
                return Err(CompileError::at(
                    pos,
                    format!("expected an expression but found {}", describe(&other)),
                ))
            }
        };
        Ok(Expr { kind, pos })
    }
}

fn describe(t: &Tok) -> String {
    match t {
        Tok::Ident(s) => format!("'{s}'"),
        Tok::Int(n) => format!("'{n}'"),
        Tok::Float(x) => format!("'{x}'"),
        Tok::Str(s) => format!("\"{s}\""),
        Tok::Binding { name, .. } => format!("'@{name}'"),
        Tok::Punct(p) => format!("'{p}'"),
        Tok::Global(g) => {
            format!("'${g}' (a parameter expression's variable; in VEX use @Frame, @Time)")
        }
        Tok::Eof => "the end of the snippet".into(),
    }
}
