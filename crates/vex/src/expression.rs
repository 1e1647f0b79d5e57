//! Parameter expressions in the wrangle's language: one VEX expression with
//! Houdini's globals (`$F`, `$FF`, `$T`, `$FPS`, `$HIP`, `$OS`, `$PI`, `$E`)
//! and `ch()` references, parsed once and evaluated per frame by the same
//! compiler and runtime as snippets (a detail run over no geometry), so a
//! function means the same in a field as in a wrangle.

use geode_geo::{AttribClass, AttribData, Geometry};

use crate::compile::ast::{Expr, ExprKind, Snippet, Stmt};
use crate::compile::lex::{Tok, Token};
use crate::compile::{BindSpec, Channel};
use crate::error::CompileError;
use crate::run::RunOptions;
use crate::ty::Ty;

/// What one evaluation may hold: a parameter's expression computes a few
/// values, and one that builds more (a `sprintf` a gigabyte wide) is an
/// error in that parameter, not an exhausted machine.
const EXPRESSION_MEMORY: u64 = 256 << 20;

/// The globals an expression may name.
pub const GLOBALS: &[(&str, &str)] = &[
    ("F", "the frame, rounded to a whole number"),
    ("FF", "the frame, with its fraction"),
    ("T", "the time in seconds (frame 1 is 0)"),
    ("FPS", "frames per second"),
    ("HIP", "the network file's folder"),
    ("OS", "the node's name"),
    ("PI", "π"),
    ("E", "e, the base of natural logarithms"),
];

/// What the globals are while an expression is evaluated.
pub struct Globals<'a> {
    pub frame: f64,
    pub fps: f64,
    pub hip: &'a str,
    pub node: &'a str,
}

/// An expression's value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Num(Vec<f64>),
    Str(String),
}

/// A parsed expression, ready to evaluate at any frame.
#[derive(Clone, Debug)]
pub struct Expression {
    tokens: Vec<Token>,
    references: Vec<String>,
    reads_time: bool,
}

/// The detail attribute the evaluation writes its result to.
const RESULT: &str = "__expression_value";

/// Parses `text`: syntax, globals and `ch()` paths are checked now.
pub fn parse_expression(text: &str) -> Result<Expression, CompileError> {
    let tokens = crate::compile::lex::lex(text)?;
    let mut reads_time = false;
    for t in &tokens {
        if let Tok::Global(name) = &t.tok {
            if !GLOBALS.iter().any(|(g, _)| g == name) {
                return Err(CompileError::at(
                    t.pos,
                    format!(
                        "unknown variable ${name}{}; known: {}",
                        crate::suggest(name, GLOBALS.iter().map(|(g, _)| *g)),
                        GLOBALS
                            .iter()
                            .map(|(g, _)| format!("${g}"))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                ));
            }
            reads_time |= matches!(name.as_str(), "F" | "FF" | "T");
        }
    }
    let probe = Globals {
        frame: 1.0,
        fps: 24.0,
        hip: ".",
        node: "node",
    };
    let expr = parse_tokens(substitute(&tokens, &probe))?;
    let mut references = Vec::new();
    walk(&expr, &mut |e| match &e.kind {
        ExprKind::Binding { name, .. } => Err(CompileError::at(
            e.pos,
            format!("@{name}: a parameter has no geometry to read (use ch() or a $ variable)"),
        )),
        ExprKind::Assign(..) | ExprKind::IncDec { .. } => {
            Err(CompileError::at(e.pos, "an expression cannot assign"))
        }
        ExprKind::Call(f, args) if is_channel_call(f) => match args.first().map(|a| &a.kind) {
            Some(ExprKind::Str(path)) => {
                references.push(path.clone());
                Ok(())
            }
            _ => Err(CompileError::at(
                e.pos,
                format!("{f}() needs the parameter's path as a string literal"),
            )),
        },
        _ => Ok(()),
    })?;
    Ok(Expression {
        tokens,
        references,
        reads_time,
    })
}

fn is_channel_call(name: &str) -> bool {
    matches!(name, "ch" | "chf" | "chi" | "chv" | "chs" | "chu" | "chp")
}

impl Expression {
    /// The paths its `ch()` calls name, in order.
    pub fn references(&self) -> &[String] {
        &self.references
    }

    /// Whether it names `$F`, `$FF` or `$T`.
    pub fn reads_time(&self) -> bool {
        self.reads_time
    }

    /// The value with these globals; `channel` gives each referenced
    /// parameter's value.
    pub fn eval(
        &self,
        globals: &Globals,
        channel: &dyn Fn(&str) -> Option<Channel>,
    ) -> Result<Value, CompileError> {
        let expr = parse_tokens(substitute(&self.tokens, globals))?;
        // No suggestions: a reference that cannot be read is reported by the
        // network, which knows why.
        let names = Vec::new;
        let empty = Geometry::new();
        let spec = BindSpec {
            run_over: AttribClass::Detail,
            inputs: vec![Some(&empty)],
            channels: channel,
            channel_names: &names,
            frame: globals.frame,
            time: (globals.frame - 1.0) / globals.fps,
        };
        let ty = crate::compile::type_of(&expr, &spec)?;
        let prefix = match ty {
            Ty::Float => 'f',
            Ty::Int => 'i',
            Ty::Vec2 => 'u',
            Ty::Vec3 => 'v',
            Ty::Vec4 => 'p',
            Ty::Str => 's',
            other => {
                return Err(CompileError::at(
                    expr.pos,
                    format!("the expression gives a {other}; a parameter takes a number, a vector or a string"),
                ))
            }
        };
        let pos = expr.pos;
        let snippet = Snippet {
            functions: Vec::new(),
            body: vec![Stmt::Expr(Expr {
                kind: ExprKind::Assign(
                    "=",
                    Box::new(Expr {
                        kind: ExprKind::Binding {
                            prefix: Some(prefix),
                            array: false,
                            name: RESULT.into(),
                        },
                        pos,
                    }),
                    Box::new(expr),
                ),
                pos,
            })],
        };
        let program = crate::compile::compile_snippet(&snippet, &spec)?;
        let mut out = empty.clone();
        let never = || false;
        crate::run(
            &program,
            &mut out,
            &[Some(&empty)],
            &RunOptions {
                group: None,
                cancel: &never,
                memory_budget: EXPRESSION_MEMORY,
            },
        )
        .map_err(|e| CompileError::at(pos, e.to_string()))?;
        let data = out
            .attribs(AttribClass::Detail)
            .get(RESULT)
            .map(|a| a.data())
            .ok_or_else(|| CompileError::at(pos, "the expression gave no value"))?;
        Ok(match data {
            AttribData::Float(v) => Value::Num(vec![f64::from(v[0])]),
            AttribData::Int(v) => Value::Num(vec![f64::from(v[0])]),
            AttribData::Vec2(v) => Value::Num(v[0].to_array().map(f64::from).to_vec()),
            AttribData::Vec3(v) => Value::Num(v[0].to_array().map(f64::from).to_vec()),
            AttribData::Vec4(v) => Value::Num(v[0].to_array().map(f64::from).to_vec()),
            AttribData::String(s) => Value::Str(s.get(0).to_owned()),
            _ => return Err(CompileError::at(pos, "the expression gave no value")),
        })
    }
}

/// The tokens with each global replaced by its value.
fn substitute(tokens: &[Token], g: &Globals) -> Vec<Token> {
    tokens
        .iter()
        .map(|t| match &t.tok {
            Tok::Global(name) => Token {
                tok: match name.as_str() {
                    "F" => Tok::Int(g.frame.round() as i64),
                    "FF" => Tok::Float(g.frame),
                    "T" => Tok::Float((g.frame - 1.0) / g.fps),
                    "FPS" => Tok::Float(g.fps),
                    "HIP" => Tok::Str(g.hip.to_owned()),
                    "OS" => Tok::Str(g.node.to_owned()),
                    "PI" => Tok::Float(std::f64::consts::PI),
                    _ => Tok::Float(std::f64::consts::E),
                },
                pos: t.pos,
            },
            _ => t.clone(),
        })
        .collect()
}

/// One whole expression from the tokens, nothing after it.
fn parse_tokens(tokens: Vec<Token>) -> Result<Expr, CompileError> {
    let tokens = crate::compile::lex::fold_prefixes(tokens)?;
    let mut parser = crate::compile::parse::Parser::new(tokens);
    let e = parser.expr()?;
    parser.end()?;
    Ok(e)
}

/// Calls `f` on `e` and every expression inside it (the parser bounds the depth).
fn walk(
    e: &Expr,
    f: &mut dyn FnMut(&Expr) -> Result<(), CompileError>,
) -> Result<(), CompileError> {
    f(e)?;
    match &e.kind {
        ExprKind::Int(_)
        | ExprKind::Float(_)
        | ExprKind::Str(_)
        | ExprKind::Var(_)
        | ExprKind::Binding { .. } => Ok(()),
        ExprKind::Braces(v) | ExprKind::Call(_, v) => v.iter().try_for_each(|x| walk(x, f)),
        ExprKind::Unary(_, a) | ExprKind::Member(a, _) | ExprKind::Cast(_, a) => walk(a, f),
        ExprKind::IncDec { target, .. } => walk(target, f),
        ExprKind::Binary(_, a, b) | ExprKind::Assign(_, a, b) | ExprKind::Index(a, b) => {
            walk(a, f)?;
            walk(b, f)
        }
        ExprKind::Ternary(a, b, c) => {
            walk(a, f)?;
            walk(b, f)?;
            walk(c, f)
        }
        ExprKind::Slice {
            seq,
            start,
            end,
            step,
        } => {
            walk(seq, f)?;
            [start, end, step]
                .into_iter()
                .flatten()
                .try_for_each(|part| walk(part, f))
        }
    }
}
