//! A small expression language for per-element formulas (`x > 0 && y < 0.5`):
//! numbers, variables, + - * / % ^, comparisons, && || !, and math functions.
//! Nesting deeper than `MAX_DEPTH` is refused with the column where it goes
//! over, so evaluating, converting and dropping a parsed tree never recurse
//! past it.

use std::fmt;

/// A parsed expression over named variables.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    Num(f64),
    Var(usize),
    Neg(Box<Expr>),
    Not(Box<Expr>),
    Bin(Op, Box<Expr>, Box<Expr>),
    Call(Func, Vec<Expr>),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Op {
    Add,
    Sub,
    Mul,
    Div,
    Rem,
    Pow,
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
    And,
    Or,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Func {
    Sin,
    Cos,
    Tan,
    Abs,
    Sqrt,
    Floor,
    Ceil,
    Min,
    Max,
    Pow,
    Atan2,
}

impl Func {
    fn lookup(name: &str) -> Option<(Func, usize)> {
        Some(match name {
            "sin" => (Func::Sin, 1),
            "cos" => (Func::Cos, 1),
            "tan" => (Func::Tan, 1),
            "abs" => (Func::Abs, 1),
            "sqrt" => (Func::Sqrt, 1),
            "floor" => (Func::Floor, 1),
            "ceil" => (Func::Ceil, 1),
            "min" => (Func::Min, 2),
            "max" => (Func::Max, 2),
            "pow" => (Func::Pow, 2),
            "atan2" => (Func::Atan2, 2),
            _ => return None,
        })
    }
}

/// A syntax error with the 1-based column where it was found.
#[derive(Clone, Debug, PartialEq)]
pub struct ExprError {
    pub column: usize,
    pub message: String,
}

impl fmt::Display for ExprError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "column {}: {}", self.column, self.message)
    }
}

/// The deepest nesting an expression may have (VEX's limit: formulas written
/// by hand stay far below; a generated or hostile one is refused before the
/// parser, evaluation or dropping the tree can overflow the stack).
pub const MAX_DEPTH: usize = 200;

struct Parser<'a> {
    src: &'a [u8],
    pos: usize,
    vars: &'a [&'a str],
    /// How deep the tree being built is: parentheses, operands, unary
    /// operators and chains of binary operators all count.
    depth: usize,
}

impl Parser<'_> {
    /// Runs `f` `1 + extra` levels deeper, refusing to go past `MAX_DEPTH`.
    fn nested(
        &mut self,
        extra: usize,
        f: impl FnOnce(&mut Self) -> Result<Expr, ExprError>,
    ) -> Result<Expr, ExprError> {
        let levels = 1 + extra;
        if self.depth + levels > MAX_DEPTH {
            self.skip_ws();
            return self.err(format!("nested too deeply (more than {MAX_DEPTH} levels)"));
        }
        self.depth += levels;
        let r = f(self);
        self.depth -= levels;
        r
    }

    fn err<T>(&self, message: impl Into<String>) -> Result<T, ExprError> {
        Err(ExprError {
            column: self.pos + 1,
            message: message.into(),
        })
    }

    fn skip_ws(&mut self) {
        while self.pos < self.src.len() && self.src[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    fn eat(&mut self, tok: &str) -> bool {
        self.skip_ws();
        if self.src[self.pos..].starts_with(tok.as_bytes()) {
            self.pos += tok.len();
            true
        } else {
            false
        }
    }

    /// Binary operators by precedence level, lowest first.
    fn binary(&mut self, level: usize) -> Result<Expr, ExprError> {
        const LEVELS: &[&[(&str, Op)]] = &[
            &[("||", Op::Or)],
            &[("&&", Op::And)],
            &[("==", Op::Eq), ("!=", Op::Ne)],
            &[("<=", Op::Le), (">=", Op::Ge), ("<", Op::Lt), (">", Op::Gt)],
            &[("+", Op::Add), ("-", Op::Sub)],
            &[("*", Op::Mul), ("/", Op::Div), ("%", Op::Rem)],
        ];
        if level == LEVELS.len() {
            return self.power();
        }
        let mut lhs = self.binary(level + 1)?;
        let mut chain = 0;
        'outer: loop {
            for (tok, op) in LEVELS[level] {
                if self.eat(tok) {
                    // `a + b + c...` nests to the left: each operator is a level.
                    chain += 1;
                    let rhs = self.nested(chain, |p| p.binary(level + 1))?;
                    lhs = Expr::Bin(*op, Box::new(lhs), Box::new(rhs));
                    continue 'outer;
                }
            }
            return Ok(lhs);
        }
    }

    fn power(&mut self) -> Result<Expr, ExprError> {
        let base = self.unary()?;
        if self.eat("^") {
            // Right associative.
            let exp = self.nested(0, Self::power)?;
            return Ok(Expr::Bin(Op::Pow, Box::new(base), Box::new(exp)));
        }
        Ok(base)
    }

    fn unary(&mut self) -> Result<Expr, ExprError> {
        self.nested(0, Self::unary_here)
    }

    fn unary_here(&mut self) -> Result<Expr, ExprError> {
        if self.eat("-") {
            return Ok(Expr::Neg(Box::new(self.unary()?)));
        }
        if self.eat("!") {
            return Ok(Expr::Not(Box::new(self.unary()?)));
        }
        self.atom()
    }

    fn atom(&mut self) -> Result<Expr, ExprError> {
        self.skip_ws();
        let start = self.pos;
        let Some(&c) = self.src.get(self.pos) else {
            return self.err("expected a value, found the end");
        };
        if c == b'(' {
            self.pos += 1;
            let e = self.binary(0)?;
            if !self.eat(")") {
                return self.err("expected `)`");
            }
            return Ok(e);
        }
        if c.is_ascii_digit() || c == b'.' {
            while self.pos < self.src.len()
                && (self.src[self.pos].is_ascii_digit() || self.src[self.pos] == b'.')
            {
                self.pos += 1;
            }
            if self.pos < self.src.len()
                && (self.src[self.pos] == b'e' || self.src[self.pos] == b'E')
            {
                self.pos += 1;
                if self.pos < self.src.len()
                    && (self.src[self.pos] == b'-' || self.src[self.pos] == b'+')
                {
                    self.pos += 1;
                }
                while self.pos < self.src.len() && self.src[self.pos].is_ascii_digit() {
                    self.pos += 1;
                }
            }
            let text = std::str::from_utf8(&self.src[start..self.pos]).unwrap_or("");
            return match text.parse() {
                Ok(x) => Ok(Expr::Num(x)),
                Err(_) => {
                    self.pos = start;
                    self.err(format!("bad number `{text}`"))
                }
            };
        }
        if c.is_ascii_alphabetic() || c == b'_' {
            while self.pos < self.src.len()
                && (self.src[self.pos].is_ascii_alphanumeric() || self.src[self.pos] == b'_')
            {
                self.pos += 1;
            }
            let name = std::str::from_utf8(&self.src[start..self.pos]).unwrap_or("");
            if self.eat("(") {
                let Some((f, arity)) = Func::lookup(name) else {
                    self.pos = start;
                    return self.err(format!("unknown function `{name}`"));
                };
                let mut args = vec![self.binary(0)?];
                while self.eat(",") {
                    args.push(self.binary(0)?);
                }
                if !self.eat(")") {
                    return self.err("expected `)` after the arguments");
                }
                if args.len() != arity {
                    self.pos = start;
                    return self.err(format!(
                        "`{name}` takes {arity} argument(s), found {}",
                        args.len()
                    ));
                }
                return Ok(Expr::Call(f, args));
            }
            if name == "pi" {
                return Ok(Expr::Num(std::f64::consts::PI));
            }
            return match self.vars.iter().position(|v| *v == name) {
                Some(i) => Ok(Expr::Var(i)),
                None => {
                    self.pos = start;
                    self.err(format!(
                        "unknown variable `{name}` (known: {})",
                        self.vars.join(", ")
                    ))
                }
            };
        }
        self.err(format!("unexpected `{}`", c as char))
    }
}

fn truth(x: bool) -> f64 {
    if x {
        1.0
    } else {
        0.0
    }
}

impl Expr {
    /// Parses `src`; variables are referred to by their index in `vars`.
    pub fn parse(src: &str, vars: &[&str]) -> Result<Expr, ExprError> {
        let mut p = Parser {
            src: src.as_bytes(),
            pos: 0,
            vars,
            depth: 0,
        };
        let e = p.binary(0)?;
        p.skip_ws();
        if p.pos != p.src.len() {
            return p.err(format!("unexpected `{}`", &src[p.pos..]));
        }
        Ok(e)
    }

    /// Evaluates with variable values in the order given to `parse`;
    /// comparisons give 1 or 0, and anything non-zero is true.
    pub fn eval(&self, vars: &[f64]) -> f64 {
        match self {
            Expr::Num(x) => *x,
            Expr::Var(i) => vars[*i],
            Expr::Neg(e) => -e.eval(vars),
            Expr::Not(e) => truth(e.eval(vars) == 0.0),
            Expr::Bin(op, a, b) => {
                let x = a.eval(vars);
                // Short-circuit the logical operators.
                match op {
                    Op::And => return truth(x != 0.0 && b.eval(vars) != 0.0),
                    Op::Or => return truth(x != 0.0 || b.eval(vars) != 0.0),
                    _ => {}
                }
                let y = b.eval(vars);
                match op {
                    Op::Add => x + y,
                    Op::Sub => x - y,
                    Op::Mul => x * y,
                    Op::Div => x / y,
                    Op::Rem => x % y,
                    Op::Pow => x.powf(y),
                    Op::Lt => truth(x < y),
                    Op::Le => truth(x <= y),
                    Op::Gt => truth(x > y),
                    Op::Ge => truth(x >= y),
                    Op::Eq => truth(x == y),
                    Op::Ne => truth(x != y),
                    Op::And | Op::Or => unreachable!("handled above"),
                }
            }
            Expr::Call(f, args) => {
                let a = args[0].eval(vars);
                let b = || args[1].eval(vars);
                match f {
                    Func::Sin => a.sin(),
                    Func::Cos => a.cos(),
                    Func::Tan => a.tan(),
                    Func::Abs => a.abs(),
                    Func::Sqrt => a.sqrt(),
                    Func::Floor => a.floor(),
                    Func::Ceil => a.ceil(),
                    Func::Min => a.min(b()),
                    Func::Max => a.max(b()),
                    Func::Pow => a.powf(b()),
                    Func::Atan2 => a.atan2(b()),
                }
            }
        }
    }
}

/// A small integer constant (exponents that expand into multiplications).
fn integer(e: &Expr) -> Option<i32> {
    match e {
        Expr::Num(k) if k.fract() == 0.0 && k.abs() <= 64.0 => Some(*k as i32),
        Expr::Neg(inner) => integer(inner).map(|k| -k),
        _ => None,
    }
}

fn rhs_integer(e: &Expr) -> Option<i32> {
    match e {
        Expr::Bin(Op::Pow, _, b) => integer(b),
        _ => None,
    }
}

/// `a ^ b`: integer exponents by repeated squaring (exact, and defined for
/// negative bases, as `powf` is), others through `exp(b ln a)`.
fn power(a: &geode_frep::Field, b: &geode_frep::Field, int: Option<i32>) -> geode_frep::Field {
    let Some(k) = int else {
        return (b * a.ln()).exp();
    };
    let mut result: Option<geode_frep::Field> = None;
    let mut base = a.clone();
    let mut n = k.unsigned_abs();
    while n > 0 {
        if n & 1 == 1 {
            result = Some(match result {
                Some(r) => r * &base,
                None => base.clone(),
            });
        }
        n >>= 1;
        if n > 0 {
            base = base.square();
        }
    }
    let r = result.unwrap_or_else(|| geode_frep::Field::constant(1.0));
    if k < 0 {
        1.0 / r
    } else {
        r
    }
}

impl Expr {
    /// The expression as an FRep field, variables bound to the given fields
    /// (in the order given to `parse`). `a ^ b` and `pow` use `exp(b ln a)`.
    pub fn to_field(&self, vars: &[geode_frep::Field]) -> geode_frep::Field {
        use geode_frep::{Binary as B, Field, Unary as U};
        match self {
            Expr::Num(x) => Field::constant(*x),
            Expr::Var(i) => vars[*i].clone(),
            Expr::Neg(e) => -e.to_field(vars),
            Expr::Not(e) => e.to_field(vars).unary(U::Not),
            Expr::Bin(op, a, b) => {
                let (a, b) = (a.to_field(vars), b.to_field(vars));
                let cmp = |x: &Field, y: &Field, want: f64| {
                    (x.binary(B::Compare, y) - want).abs().unary(U::Not)
                };
                match op {
                    Op::Add => a + b,
                    Op::Sub => a - b,
                    Op::Mul => a * b,
                    Op::Div => a / b,
                    Op::Rem => a.binary(B::Mod, b),
                    Op::Pow => power(&a, &b, rhs_integer(self)),
                    Op::Lt => cmp(&a, &b, -1.0),
                    Op::Gt => cmp(&a, &b, 1.0),
                    Op::Eq => cmp(&a, &b, 0.0),
                    Op::Le => cmp(&a, &b, 1.0).unary(U::Not),
                    Op::Ge => cmp(&a, &b, -1.0).unary(U::Not),
                    Op::Ne => cmp(&a, &b, 0.0).unary(U::Not),
                    // Truth values as 0 and 1, as `eval` gives them.
                    Op::And => a
                        .unary(U::Not)
                        .unary(U::Not)
                        .binary(B::And, b.unary(U::Not).unary(U::Not)),
                    Op::Or => a
                        .unary(U::Not)
                        .unary(U::Not)
                        .binary(B::Or, b.unary(U::Not).unary(U::Not)),
                }
            }
            Expr::Call(f, args) => {
                let a = args[0].to_field(vars);
                let b = || args[1].to_field(vars);
                match f {
                    Func::Sin => a.sin(),
                    Func::Cos => a.cos(),
                    Func::Tan => a.tan(),
                    Func::Abs => a.abs(),
                    Func::Sqrt => a.sqrt(),
                    Func::Floor => a.floor(),
                    Func::Ceil => a.ceil(),
                    Func::Min => a.min(b()),
                    Func::Max => a.max(b()),
                    Func::Pow => power(&a, &b(), args.get(1).and_then(integer)),
                    Func::Atan2 => a.atan2(b()),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ev(s: &str, v: &[f64]) -> f64 {
        Expr::parse(s, &["x", "y", "z"]).unwrap().eval(v)
    }

    #[test]
    fn precedence_and_functions() {
        assert_eq!(ev("1 + 2 * 3", &[0.0; 3]), 7.0);
        assert_eq!(ev("(1 + 2) * 3", &[0.0; 3]), 9.0);
        assert_eq!(ev("2 ^ 3 ^ 2", &[0.0; 3]), 512.0);
        assert_eq!(ev("-x ^ 2", &[3.0, 0.0, 0.0]), 9.0);
        assert_eq!(ev("x > 0 && y <= 1 || z == 5", &[1.0, 2.0, 5.0]), 1.0);
        assert_eq!(ev("!(x > 0)", &[1.0, 0.0, 0.0]), 0.0);
        assert_eq!(
            ev(
                "max(x, abs(y)) + sqrt(16) - floor(1.5e0)",
                &[1.0, -2.0, 0.0]
            ),
            5.0
        );
        assert!((ev("sin(pi / 2)", &[0.0; 3]) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn fields_from_expressions_agree_with_evaluation() {
        let vars = [
            geode_frep::Field::x(),
            geode_frep::Field::y(),
            geode_frep::Field::z(),
        ];
        for src in [
            "1 - (x*x + y*y + z*z)",
            "x > 0 && y <= 0.5 || z == 1",
            "max(x, abs(y)) % 0.7 + 2 ^ z",
            "!(x < y) + (x != z)",
            "x^3 - pow(y, 2) + z^-2 + x^0",
        ] {
            let e = Expr::parse(src, &["x", "y", "z"]).unwrap();
            let f = e.to_field(&vars);
            for p in [
                [0.3, -0.2, 1.0],
                [-1.5, 0.5, 0.25],
                [0.0, 0.0, 0.0],
                [2.0, 3.0, -1.0],
            ] {
                let (a, b) = (e.eval(&p), f.eval_tree(p));
                assert!(
                    a == b || (a - b).abs() < 1e-12,
                    "{src} at {p:?}: {a} vs {b}"
                );
            }
        }
    }

    #[test]
    fn errors_point_at_the_column() {
        let e = |s: &str| Expr::parse(s, &["x"]).unwrap_err().to_string();
        assert_eq!(e("x +"), "column 4: expected a value, found the end");
        assert_eq!(e("x + q"), "column 5: unknown variable `q` (known: x)");
        assert_eq!(e("foo(x)"), "column 1: unknown function `foo`");
        assert_eq!(e("min(x)"), "column 1: `min` takes 2 argument(s), found 1");
        assert_eq!(e("(x"), "column 3: expected `)`");
        assert_eq!(e("x x"), "column 3: unexpected `x`");
    }

    /// 100,000 levels of each kind of nesting are refused where they pass
    /// the limit, never overflowing the stack.
    #[test]
    fn deep_nesting_is_refused_with_its_column() {
        const LEVELS: usize = 100_000;
        let e = |s: String| Expr::parse(&s, &["x"]).unwrap_err().to_string();
        let too_deep = |column: usize| {
            format!("column {column}: nested too deeply (more than {MAX_DEPTH} levels)")
        };
        let parens = format!("{}x{}", "(".repeat(LEVELS), ")".repeat(LEVELS));
        assert_eq!(e(parens), too_deep(201));
        assert_eq!(e(vec!["x"; LEVELS].join("+")), too_deep(399));
        assert_eq!(e(vec!["x"; LEVELS].join(" && ")), too_deep(996));
        assert_eq!(e(vec!["x"; LEVELS].join("^")), too_deep(401));
        assert_eq!(e(format!("{}x", "-".repeat(LEVELS))), too_deep(201));
        assert_eq!(e(format!("{}x", "!".repeat(LEVELS))), too_deep(201));
        // Just inside the limit parses, evaluates and becomes a field.
        let deep = format!("{}x{}", "(".repeat(150), ")".repeat(150));
        let ok = Expr::parse(&deep, &["x"]).unwrap();
        assert_eq!(ok.eval(&[2.0]), 2.0);
        let _ = ok.to_field(&[geode_frep::Field::x()]);
    }
}
