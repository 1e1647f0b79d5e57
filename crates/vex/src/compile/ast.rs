//! The syntax tree the parser builds and the lowering reads.

use crate::compile::lex::Pos;
use crate::ty::Ty;

#[derive(Clone, Debug)]
pub struct Expr {
    pub kind: ExprKind,
    pub pos: Pos,
}

#[derive(Clone, Debug)]
pub enum ExprKind {
    Int(i64),
    Float(f64),
    Str(String),
    Var(String),
    Binding {
        prefix: Option<char>,
        array: bool,
        name: String,
    },
    /// `{a, b, c}`: constants only, as VEX requires.
    Braces(Vec<Expr>),
    Unary(&'static str, Box<Expr>),
    Binary(&'static str, Box<Expr>, Box<Expr>),
    /// `x = y`, `x += y` (op is `=` or the compound operator).
    Assign(&'static str, Box<Expr>, Box<Expr>),
    /// `++x`, `x--` (prefix: whether the value is the updated one).
    IncDec {
        delta: i32,
        prefix: bool,
        target: Box<Expr>,
    },
    Ternary(Box<Expr>, Box<Expr>, Box<Expr>),
    Call(String, Vec<Expr>),
    /// `v.x`, `v.zyx`, `m.xx`.
    Member(Box<Expr>, String),
    Index(Box<Expr>, Box<Expr>),
    /// `a[start:end:step]` on an array or string; each part may be left
    /// out.
    Slice {
        seq: Box<Expr>,
        start: Option<Box<Expr>>,
        end: Option<Box<Expr>>,
        step: Option<Box<Expr>>,
    },
    /// `vector(x)`, `(float)x`: an explicit conversion.
    Cast(Ty, Box<Expr>),
}

#[derive(Clone, Debug)]
pub struct Decl {
    pub name: String,
    pub ty: Ty,
    pub init: Option<Expr>,
    pub pos: Pos,
}

#[derive(Clone, Debug)]
pub enum Stmt {
    Expr(Expr),
    Decls(Vec<Decl>),
    Block(Vec<Stmt>),
    If(Expr, Box<Stmt>, Option<Box<Stmt>>),
    While(Expr, Box<Stmt>),
    DoWhile(Box<Stmt>, Expr),
    For(Option<Box<Stmt>>, Option<Expr>, Option<Expr>, Box<Stmt>),
    /// `foreach (int i; type x; array)` (index optional).
    Foreach {
        index: Option<String>,
        elem: Decl,
        array: Expr,
        body: Box<Stmt>,
    },
    Break(Pos),
    Continue(Pos),
    Return(Option<Expr>, Pos),
    Empty,
}

#[derive(Clone, Debug)]
pub struct Param {
    pub name: String,
    pub ty: Ty,
}

#[derive(Clone, Debug)]
pub struct Function {
    pub name: String,
    pub ret: Ty,
    pub params: Vec<Param>,
    pub body: Vec<Stmt>,
    pub pos: Pos,
}

#[derive(Clone, Debug, Default)]
pub struct Snippet {
    pub functions: Vec<Function>,
    pub body: Vec<Stmt>,
}
