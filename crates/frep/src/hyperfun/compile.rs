//! Runs a HyperFun object once on symbolic values (see the module's doc):
//! variables hold fields (constants folded as they go), arrays hold one
//! field per element.

use std::collections::BTreeMap;

use super::library::{self, Lib};
use super::parse::{Expr, Object, Op, Pos, Stmt};
use super::HfError;
use crate::field::{self, Binary, Field, Node, Unary};

#[derive(Clone, Debug)]
pub(crate) enum Value {
    Scalar(Field),
    Array(Vec<Field>),
}

/// The number a field is, when it does not depend on the point.
pub(crate) fn num(f: &Field) -> Option<f64> {
    match f.node() {
        Node::Const(c) => Some(*c),
        _ => None,
    }
}

pub(crate) fn konst(v: f64) -> Field {
    Field::constant(v)
}

/// `a op b`, folded to a number when both are numbers.
pub(crate) fn bin(op: Binary, a: &Field, b: &Field) -> Field {
    match (num(a), num(b)) {
        (Some(x), Some(y)) => konst(field::binary(op, x, y)),
        _ => a.binary(op, b.clone()),
    }
}

/// `op a`, folded to a number when `a` is one.
pub(crate) fn un(op: Unary, a: &Field) -> Field {
    match num(a) {
        Some(x) => konst(field::unary(op, x)),
        None => a.unary(op),
    }
}

pub(crate) fn add(a: &Field, b: &Field) -> Field {
    bin(Binary::Add, a, b)
}
pub(crate) fn sub(a: &Field, b: &Field) -> Field {
    bin(Binary::Sub, a, b)
}
pub(crate) fn mul(a: &Field, b: &Field) -> Field {
    bin(Binary::Mul, a, b)
}
pub(crate) fn div(a: &Field, b: &Field) -> Field {
    bin(Binary::Div, a, b)
}
pub(crate) fn sq(a: &Field) -> Field {
    un(Unary::Square, a)
}
pub(crate) fn sqrt(a: &Field) -> Field {
    un(Unary::Sqrt, a)
}

/// `a ^ b`: whole exponents by multiplication (exact for negative bases),
/// others as `exp(b ln a)` (C's `pow` for positive bases).
pub(crate) fn pow(a: &Field, b: &Field) -> Field {
    if let (Some(x), Some(y)) = (num(a), num(b)) {
        return konst(x.powf(y));
    }
    match num(b) {
        Some(n) if n.fract() == 0.0 && n.abs() <= 64.0 => {
            let mut result = konst(1.0);
            let mut base = a.clone();
            let mut k = n.abs() as u32;
            while k > 0 {
                if k & 1 == 1 {
                    result = mul(&result, &base);
                }
                base = sq(&base);
                k >>= 1;
            }
            if n < 0.0 {
                div(&konst(1.0), &result)
            } else {
                result
            }
        }
        Some(0.5) => sqrt(a),
        _ => un(Unary::Exp, &mul(b, &un(Unary::Ln, a))),
    }
}

/// HyperFun's set operations: R-functions of the `sqrt(f1² + f2²)` system.
pub(crate) fn union(a: &Field, b: &Field) -> Field {
    add(&add(a, b), &sqrt(&add(&sq(a), &sq(b))))
}
pub(crate) fn intersect(a: &Field, b: &Field) -> Field {
    sub(&add(a, b), &sqrt(&add(&sq(a), &sq(b))))
}

/// 1 where `v` is not zero, else 0.
fn truth(v: &Field) -> Field {
    un(Unary::Not, &un(Unary::Not, v))
}

fn relation(op: Op, a: &Field, b: &Field) -> Field {
    let s = bin(Binary::Compare, a, b);
    let one = konst(1.0);
    match op {
        Op::Less => un(Unary::Not, &add(&s, &one)),
        Op::Greater => un(Unary::Not, &sub(&s, &one)),
        Op::Equal => un(Unary::Not, &s),
        Op::NotEqual => truth(&s),
        Op::LessEq => truth(&sub(&s, &one)),
        Op::GreaterEq => truth(&add(&s, &one)),
        _ => unreachable!("not a relation"),
    }
}

/// `b + mask (a - b)`: a where the mask is 1, b where it is 0.
fn select(mask: &Field, a: &Field, b: &Field) -> Field {
    if a.identity() == b.identity() {
        return a.clone();
    }
    add(b, &mul(mask, &sub(a, b)))
}

/// Loops longer than this are refused (a runaway loop at compile time).
const MAX_ITERATIONS: usize = 100_000;

/// Statements run at compile time, all loops and object calls together,
/// beyond which a program is refused: nested loops each under
/// `MAX_ITERATIONS` would otherwise run for hours.
const MAX_STEPS: usize = 1_000_000;

/// Objects calling objects deeper than this are refused (recursion).
const MAX_CALL_DEPTH: usize = 64;

type Env = BTreeMap<String, Value>;

pub(crate) fn compile(
    objects: &[Object],
    object: Option<&str>,
    params: &[f64],
) -> Result<Field, HfError> {
    let target = match object {
        Some(name) => objects
            .iter()
            .find(|o| o.name == name.to_lowercase())
            .ok_or_else(|| {
                let names: Vec<&str> = objects.iter().map(|o| o.name.as_str()).collect();
                HfError::at(
                    1,
                    1,
                    format!(
                        "the program has no object '{name}' (it has {})",
                        names.join(", ")
                    ),
                )
            })?,
        None => objects
            .last()
            .expect("the parser returns at least one object"),
    };
    if target.coords.1 != 3 {
        return Err(HfError::at(
            target.pos.line,
            target.pos.column,
            format!(
                "'{}' declares {}[{}]: geode reads objects in 3D (x[3])",
                target.name, target.coords.0, target.coords.1
            ),
        ));
    }
    let n = target.params.as_ref().map_or(0, |p| p.1);
    let params: Vec<Field> = (0..n)
        .map(|i| konst(params.get(i).copied().unwrap_or(0.0)))
        .collect();
    Program {
        objects,
        steps: std::cell::Cell::new(0),
    }
    .run(target, vec![Field::x(), Field::y(), Field::z()], params, 0)
}

struct Program<'a> {
    objects: &'a [Object],
    /// Statements run so far, against `MAX_STEPS`.
    steps: std::cell::Cell<usize>,
}

fn err(pos: Pos, message: String) -> HfError {
    HfError::at(pos.line, pos.column, message)
}

/// Where a statement starts (a call's position for a bare call).
fn stmt_pos(stmt: &Stmt) -> Pos {
    match stmt {
        Stmt::Arrays(arrays) => arrays.first().map_or(Pos { line: 1, column: 1 }, |a| a.2),
        Stmt::Assign(_, _, _, p) | Stmt::If(_, _, _, p) | Stmt::While(_, _, p) => *p,
        Stmt::Call(call) => expr_pos(call, Pos { line: 1, column: 1 }),
    }
}

/// Where an expression starts (the enclosing statement's position for a bare number).
fn expr_pos(e: &Expr, fallback: Pos) -> Pos {
    match e {
        Expr::Num(_) => fallback,
        Expr::Var(_, p) | Expr::Elem(_, _, p) | Expr::Call(_, _, p) | Expr::List(_, p) => *p,
        Expr::Neg(a) | Expr::Complement(a) | Expr::Not(a) => expr_pos(a, fallback),
        Expr::Binary(_, a, _, p) => expr_pos(a, *p),
    }
}

impl Program<'_> {
    fn run(
        &self,
        obj: &Object,
        coords: Vec<Field>,
        params: Vec<Field>,
        depth: usize,
    ) -> Result<Field, HfError> {
        let mut env = Env::new();
        env.insert(obj.coords.0.clone(), Value::Array(coords));
        if let Some((name, _)) = &obj.params {
            env.insert(name.clone(), Value::Array(params));
        }
        self.block(&obj.body, &mut env, depth)?;
        match env.get(&obj.name) {
            Some(Value::Scalar(f)) => Ok(f.clone()),
            Some(Value::Array(_)) => Err(err(
                obj.pos,
                format!("'{}' is given an array, not a value", obj.name),
            )),
            None => Err(err(
                obj.pos,
                format!("'{0}' never sets its value ('{0} = ...;')", obj.name),
            )),
        }
    }

    fn block(&self, stmts: &[Stmt], env: &mut Env, depth: usize) -> Result<(), HfError> {
        stmts.iter().try_for_each(|s| self.stmt(s, env, depth))
    }

    fn stmt(&self, stmt: &Stmt, env: &mut Env, depth: usize) -> Result<(), HfError> {
        self.steps.set(self.steps.get() + 1);
        if self.steps.get() > MAX_STEPS {
            return Err(err(
                stmt_pos(stmt),
                format!(
                    "the program runs more than {MAX_STEPS} statements while compiling (loops inside loops?)"
                ),
            ));
        }
        match stmt {
            Stmt::Arrays(arrays) => {
                for (name, n, _) in arrays {
                    env.insert(name.clone(), Value::Array(vec![konst(0.0); *n]));
                }
            }
            Stmt::Assign(name, None, e, pos) => {
                let v = self.eval(e, env, depth, *pos)?;
                if let (Some(Value::Array(old)), Value::Array(new)) = (env.get(name), &v) {
                    if old.len() != new.len() {
                        return Err(err(
                            *pos,
                            format!(
                                "'{name}' has {} elements, the value given {}",
                                old.len(),
                                new.len()
                            ),
                        ));
                    }
                }
                env.insert(name.clone(), v);
            }
            Stmt::Assign(name, Some(index), e, pos) => {
                let i = self.index(name, index, env, depth, *pos)?;
                let v = self.scalar(e, env, depth, *pos)?;
                if let Some(Value::Array(items)) = env.get_mut(name) {
                    items[i] = v;
                }
            }
            Stmt::Call(call) => {
                self.eval(call, env, depth, expr_pos(call, Pos { line: 1, column: 1 }))?;
            }
            Stmt::If(cond, then, otherwise, pos) => {
                let c = self.scalar(cond, env, depth, *pos)?;
                match num(&c) {
                    Some(v) if v != 0.0 => self.block(then, env, depth)?,
                    Some(_) => self.block(otherwise, env, depth)?,
                    None => {
                        let (mut a, mut b) = (env.clone(), env.clone());
                        self.block(then, &mut a, depth)?;
                        self.block(otherwise, &mut b, depth)?;
                        *env = merge(&truth(&c), a, b, *pos)?;
                    }
                }
            }
            Stmt::While(cond, body, pos) => {
                for _ in 0..=MAX_ITERATIONS {
                    let c = self.scalar(cond, env, depth, *pos)?;
                    match num(&c) {
                        Some(v) if v != 0.0 => self.block(body, env, depth)?,
                        Some(_) => return Ok(()),
                        None => {
                            return Err(err(
                                *pos,
                                "this loop's condition depends on the point: it cannot be unrolled into a field".into(),
                            ))
                        }
                    }
                }
                return Err(err(
                    *pos,
                    format!("this loop runs more than {MAX_ITERATIONS} times"),
                ));
            }
        }
        Ok(())
    }

    /// The 0-based index of `name[index]`, checked against the array's size.
    fn index(
        &self,
        name: &str,
        index: &Expr,
        env: &Env,
        depth: usize,
        at: Pos,
    ) -> Result<usize, HfError> {
        let pos = expr_pos(index, at);
        let len = match env.get(name) {
            Some(Value::Array(items)) => items.len(),
            Some(Value::Scalar(_)) => return Err(err(at, format!("'{name}' is not an array"))),
            None => {
                return Err(err(
                    at,
                    format!("'{name}' is used before it is declared ('array {name}[n];')"),
                ))
            }
        };
        let i = self.scalar(index, env, depth, pos)?;
        match num(&i) {
            Some(v) if v.fract() == 0.0 && v >= 1.0 && v <= len as f64 => Ok(v as usize - 1),
            Some(v) => Err(err(
                pos,
                format!("index {v} is outside '{name}' (1 to {len})"),
            )),
            None => Err(err(pos, "an array index cannot depend on the point".into())),
        }
    }

    fn scalar(&self, e: &Expr, env: &Env, depth: usize, at: Pos) -> Result<Field, HfError> {
        match self.eval(e, &mut env.clone(), depth, at)? {
            Value::Scalar(f) => Ok(f),
            Value::Array(_) => Err(err(
                expr_pos(e, at),
                "an array where a value is expected".into(),
            )),
        }
    }

    fn eval(&self, e: &Expr, env: &mut Env, depth: usize, at: Pos) -> Result<Value, HfError> {
        let scalar = |f: Field| Ok(Value::Scalar(f));
        match e {
            Expr::Num(v) => scalar(konst(*v)),
            Expr::Var(name, pos) => env
                .get(name)
                .cloned()
                .ok_or_else(|| err(*pos, format!("'{name}' is used before it is given a value"))),
            Expr::Elem(name, index, pos) => {
                let i = self.index(name, index, env, depth, *pos)?;
                match &env[name] {
                    Value::Array(items) => scalar(items[i].clone()),
                    Value::Scalar(_) => unreachable!("index() checked it is an array"),
                }
            }
            Expr::List(items, pos) => {
                let values: Result<Vec<Field>, HfError> = items
                    .iter()
                    .map(|i| self.scalar(i, env, depth, *pos))
                    .collect();
                Ok(Value::Array(values?))
            }
            Expr::Neg(a) | Expr::Complement(a) => {
                scalar(un(Unary::Neg, &self.scalar(a, env, depth, at)?))
            }
            Expr::Not(a) => scalar(un(Unary::Not, &self.scalar(a, env, depth, at)?)),
            Expr::Binary(op, a, b, pos) => {
                let (a, b) = (
                    self.scalar(a, env, depth, *pos)?,
                    self.scalar(b, env, depth, *pos)?,
                );
                scalar(match op {
                    Op::Add => add(&a, &b),
                    Op::Sub => sub(&a, &b),
                    Op::Mul => mul(&a, &b),
                    Op::Div => div(&a, &b),
                    Op::Pow => pow(&a, &b),
                    Op::Union => union(&a, &b),
                    Op::Intersect => intersect(&a, &b),
                    Op::Subtract => intersect(&a, &un(Unary::Neg, &b)),
                    Op::And => mul(&truth(&a), &truth(&b)),
                    Op::Or => truth(&add(&truth(&a), &truth(&b))),
                    rel => relation(*rel, &a, &b),
                })
            }
            Expr::Call(name, args, pos) => self.call(name, args, env, depth, *pos),
        }
    }

    fn call(
        &self,
        name: &str,
        args: &[Expr],
        env: &mut Env,
        depth: usize,
        pos: Pos,
    ) -> Result<Value, HfError> {
        let values: Vec<Value> = args
            .iter()
            .map(|a| self.eval(a, env, depth, pos))
            .collect::<Result<_, _>>()?;
        if let Some(obj) = self.objects.iter().find(|o| o.name == name) {
            if depth >= MAX_CALL_DEPTH {
                return Err(err(
                    pos,
                    format!("objects call each other more than {MAX_CALL_DEPTH} deep (recursion?)"),
                ));
            }
            let array = |i: usize| match values.get(i) {
                Some(Value::Array(a)) => Ok(a.clone()),
                _ => Err(err(
                    pos,
                    format!(
                        "'{name}' takes ({}[{}]{}) arrays",
                        obj.coords.0,
                        obj.coords.1,
                        obj.params
                            .as_ref()
                            .map_or(String::new(), |p| format!(", {}[{}]", p.0, p.1))
                    ),
                )),
            };
            let coords = array(0)?;
            if coords.len() != obj.coords.1 {
                return Err(err(
                    pos,
                    format!(
                        "'{name}' takes {} coordinates, given {}",
                        obj.coords.1,
                        coords.len()
                    ),
                ));
            }
            let params = match &obj.params {
                Some((_, n)) if values.len() > 1 => {
                    let mut p = array(1)?;
                    p.resize(*n, konst(0.0));
                    p
                }
                Some((_, n)) => vec![konst(0.0); *n],
                None => Vec::new(),
            };
            return Ok(Value::Scalar(self.run(obj, coords, params, depth + 1)?));
        }
        match library::call(name, &values).map_err(|m| err(pos, m))? {
            Lib::Value(f) => Ok(Value::Scalar(f)),
            Lib::Transform(coords) => {
                // A transformation rewrites the array it was given.
                let Some(Expr::Var(array, _)) = args.first() else {
                    return Err(err(
                        pos,
                        format!(
                            "{name} rewrites its first argument, which must be an array's name"
                        ),
                    ));
                };
                env.insert(array.clone(), Value::Array(coords));
                Ok(Value::Scalar(konst(1.0)))
            }
            Lib::Unknown => Err(err(pos, format!("unknown function or object '{name}'"))),
        }
    }
}

/// The variables after an `if` on the point: each a select of its two branches.
fn merge(mask: &Field, a: Env, b: Env, pos: Pos) -> Result<Env, HfError> {
    let zero = konst(0.0);
    let mut out = Env::new();
    let names: std::collections::BTreeSet<&String> = a.keys().chain(b.keys()).collect();
    for name in names {
        let v = match (a.get(name), b.get(name)) {
            (Some(Value::Scalar(x)), Some(Value::Scalar(y))) => Value::Scalar(select(mask, x, y)),
            (Some(Value::Scalar(x)), None) => Value::Scalar(select(mask, x, &zero)),
            (None, Some(Value::Scalar(y))) => Value::Scalar(select(mask, &zero, y)),
            (Some(Value::Array(x)), Some(Value::Array(y))) if x.len() == y.len() => {
                Value::Array(x.iter().zip(y).map(|(x, y)| select(mask, x, y)).collect())
            }
            (Some(Value::Array(x)), None) => {
                Value::Array(x.iter().map(|x| select(mask, x, &zero)).collect())
            }
            (None, Some(Value::Array(y))) => {
                Value::Array(y.iter().map(|y| select(mask, &zero, y)).collect())
            }
            _ => {
                return Err(err(
                    pos,
                    format!("'{name}' differs in kind or size between the branches of this if"),
                ))
            }
        };
        out.insert(name.clone(), v);
    }
    Ok(out)
}
