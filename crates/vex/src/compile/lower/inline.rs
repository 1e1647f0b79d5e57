//! Lowering of the library functions the compiler handles itself:
//! component-wise math becomes batch instructions (no call per lane),
//! `ch*` reads the node's parameters once per cook, `array` builds an
//! array of the declared element type.

use crate::compile::ast::*;
use crate::compile::lex::Pos;
use crate::ir::*;
use crate::library::array_ops;
use crate::ty::Ty;
use crate::{suggest, CompileError};

use super::calls::err;
use super::{LResult, Lower};

fn unary_op(name: &str) -> Option<FUnOp> {
    Some(match name {
        "floor" => FUnOp::Floor,
        "ceil" => FUnOp::Ceil,
        "frac" => FUnOp::Frac,
        "rint" => FUnOp::Rint,
        "trunc" => FUnOp::Trunc,
        "sqrt" => FUnOp::Sqrt,
        "exp" => FUnOp::Exp,
        "log" => FUnOp::Log,
        "log10" => FUnOp::Log10,
        "sin" => FUnOp::Sin,
        "cos" => FUnOp::Cos,
        "tan" => FUnOp::Tan,
        "asin" => FUnOp::Asin,
        "acos" => FUnOp::Acos,
        "sinh" => FUnOp::Sinh,
        "cosh" => FUnOp::Cosh,
        "tanh" => FUnOp::Tanh,
        "radians" => FUnOp::Radians,
        "degrees" => FUnOp::Degrees,
        "sign" => FUnOp::Sign,
        _ => return None,
    })
}

impl<'a> Lower<'a> {
    /// Lowers a function the library table marks as the compiler's.
    pub(super) fn inline_call(
        &mut self,
        name: &str,
        args: &[Expr],
        hint: Option<Ty>,
        pos: Pos,
    ) -> LResult<Loc> {
        if let Some(op) = unary_op(name) {
            self.arity(name, args, 1, 1, pos)?;
            let v = self.expr(&args[0], hint)?;
            let v = self.floaty(v, name, pos)?;
            return Ok(self.fmap(v, op));
        }
        let hint_num = hint.filter(|t| t.is_numeric());
        match name {
            "abs" => {
                self.arity(name, args, 1, 1, pos)?;
                let v = self.expr(&args[0], hint)?;
                if v.ty == Ty::Int {
                    return Ok(self.iun(IUnOp::Abs, v));
                }
                let v = self.floaty(v, name, pos)?;
                Ok(self.fmap(v, FUnOp::Abs))
            }
            "atan" | "atan2" if args.len() == 2 => {
                let v = self.eval_args(args)?;
                let y = self.floaty(v[0], name, pos)?;
                let x = self.floaty(v[1], name, pos)?;
                Ok(self.fzip(FBinOp::Atan2, y, x))
            }
            "atan" => {
                self.arity(name, args, 1, 2, pos)?;
                let v = self.expr(&args[0], None)?;
                let v = self.floaty(v, name, pos)?;
                Ok(self.fmap(v, FUnOp::Atan))
            }
            "pow" => {
                self.arity(name, args, 2, 2, pos)?;
                let v = self.eval_args(args)?;
                let a = self.floaty(v[0], name, pos)?;
                let b = self.floaty(v[1], name, pos)?;
                if a.ty.floats() != b.ty.floats() && b.ty.floats() != 1 {
                    return Err(self.no_form(name, &v, pos));
                }
                Ok(self.fzip(FBinOp::Pow, a, b))
            }
            "min" | "max" => {
                if args.is_empty() {
                    return err(pos, format!("'{name}' needs arguments"));
                }
                let v = self.eval_args(args)?;
                if v.len() == 1 && v[0].ty.is_vector() {
                    // The smallest or largest component.
                    let (op, r) = (
                        if name == "min" {
                            FBinOp::Min
                        } else {
                            FBinOp::Max
                        },
                        v[0].reg,
                    );
                    let mut acc = Loc {
                        ty: Ty::Float,
                        reg: r,
                    };
                    for k in 1..v[0].ty.floats() as u32 {
                        acc = self.fzip(
                            op,
                            acc,
                            Loc {
                                ty: Ty::Float,
                                reg: r + k,
                            },
                        );
                    }
                    return Ok(acc);
                }
                if v.iter().all(|x| x.ty == Ty::Int) {
                    let op = if name == "min" {
                        IBinOp::Min
                    } else {
                        IBinOp::Max
                    };
                    let mut acc = v[0];
                    for x in &v[1..] {
                        acc = Loc {
                            ty: Ty::Int,
                            reg: self.ibin(op, acc.reg, x.reg),
                        };
                    }
                    return Ok(acc);
                }
                let op = if name == "min" {
                    FBinOp::Min
                } else {
                    FBinOp::Max
                };
                let mut acc = self.floaty(v[0], name, pos)?;
                for x in &v[1..] {
                    let x = self.floaty(*x, name, pos)?;
                    if x.ty.floats() != acc.ty.floats()
                        && x.ty.floats() != 1
                        && acc.ty.floats() != 1
                    {
                        return Err(self.no_form(name, &v, pos));
                    }
                    acc = self.fzip(op, acc, x);
                }
                Ok(acc)
            }
            "clamp" => {
                self.arity(name, args, 3, 3, pos)?;
                let v = self.eval_args(args)?;
                if v.iter().all(|x| x.ty == Ty::Int) {
                    let t = self.ibin(IBinOp::Min, v[0].reg, v[2].reg);
                    return Ok(Loc {
                        ty: Ty::Int,
                        reg: self.ibin(IBinOp::Max, t, v[1].reg),
                    });
                }
                let x = self.floaty(v[0], name, pos)?;
                let lo = self.floaty(v[1], name, pos)?;
                let hi = self.floaty(v[2], name, pos)?;
                Ok(self.clamp(x, lo, hi))
            }
            "lerp" => {
                self.arity(name, args, 3, 3, pos)?;
                let v = self.eval_args(args)?;
                let a = self.floaty(v[0], name, pos)?;
                let b = self.floaty(v[1], name, pos)?;
                let t = self.floaty(v[2], name, pos)?;
                if a.ty.floats() != b.ty.floats() && a.ty.floats() != 1 && b.ty.floats() != 1 {
                    return Err(self.no_form(name, &v, pos));
                }
                Ok(self.mix(a, b, t))
            }
            "fit" | "efit" | "fit01" | "fit10" | "fit11" => {
                let full = name == "fit" || name == "efit";
                self.arity(
                    name,
                    args,
                    if full { 5 } else { 3 },
                    if full { 5 } else { 3 },
                    pos,
                )?;
                let v = self.eval_args(args)?;
                let mut f = Vec::new();
                for x in &v {
                    f.push(self.floaty(*x, name, pos)?);
                }
                let (x, omin, omax, nmin, nmax) = if full {
                    (f[0], f[1], f[2], f[3], f[4])
                } else {
                    let (lo, hi) = match name {
                        "fit01" => (0.0, 1.0),
                        "fit10" => (1.0, 0.0),
                        _ => (-1.0, 1.0),
                    };
                    let (a, b) = (self.fconst(lo), self.fconst(hi));
                    (f[0], a, b, f[1], f[2])
                };
                let num = self.fzip(FBinOp::Sub, x, omin);
                let den = self.fzip(FBinOp::Sub, omax, omin);
                let mut t = self.fzip(FBinOp::Div, num, den);
                if name != "efit" {
                    let (z, o) = (self.fconst(0.0), self.fconst(1.0));
                    t = self.clamp(t, z, o);
                }
                Ok(self.mix(nmin, nmax, t))
            }
            "smooth" => {
                self.arity(name, args, 3, 3, pos)?;
                let v = self.eval_args(args)?;
                let lo = self.floaty(v[0], name, pos)?;
                let hi = self.floaty(v[1], name, pos)?;
                let x = self.floaty(v[2], name, pos)?;
                let num = self.fzip(FBinOp::Sub, x, lo);
                let den = self.fzip(FBinOp::Sub, hi, lo);
                let t = self.fzip(FBinOp::Div, num, den);
                let (z, o) = (self.fconst(0.0), self.fconst(1.0));
                let t = self.clamp(t, z, o);
                let (two, three) = (self.fconst(2.0), self.fconst(3.0));
                let tt = self.fzip(FBinOp::Mul, t, t);
                let k = self.fzip(FBinOp::Mul, two, t);
                let k = self.fzip(FBinOp::Sub, three, k);
                // Past the range the step is 0 or 1 exactly.
                Ok(self.fzip(FBinOp::Mul, tt, k))
            }
            "length" | "length2" => {
                self.arity(name, args, 1, 1, pos)?;
                let v = self.expr(&args[0], None)?;
                let v = self.floaty(v, name, pos)?;
                if v.ty.is_matrix() {
                    return Err(self.no_form(name, &[v], pos));
                }
                let d = self.dot(v, v);
                Ok(if name == "length" {
                    self.fmap(d, FUnOp::Sqrt)
                } else {
                    d
                })
            }
            "distance" | "distance2" => {
                self.arity(name, args, 2, 2, pos)?;
                let v = self.eval_args(args)?;
                let a = self.floaty(v[0], name, pos)?;
                let b = self.floaty(v[1], name, pos)?;
                if a.ty != b.ty || a.ty.is_matrix() {
                    return Err(self.no_form(name, &v, pos));
                }
                let d = self.fzip(FBinOp::Sub, a, b);
                let d2 = self.dot(d, d);
                Ok(if name == "distance" {
                    self.fmap(d2, FUnOp::Sqrt)
                } else {
                    d2
                })
            }
            "dot" => {
                self.arity(name, args, 2, 2, pos)?;
                let v = self.eval_args(args)?;
                if v[0].ty != v[1].ty || !v[0].ty.is_vector() {
                    return Err(self.no_form(name, &v, pos));
                }
                Ok(self.dot(v[0], v[1]))
            }
            "cross" => {
                self.arity(name, args, 2, 2, pos)?;
                let v = self.eval_args(args)?;
                if v[0].ty != Ty::Vec3 || v[1].ty != Ty::Vec3 {
                    return Err(self.no_form(name, &v, pos));
                }
                let (a, b) = (v[0].reg, v[1].reg);
                let out = self.alloc(Ty::Vec3);
                for k in 0..3u32 {
                    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
                    let p = self.fzip(
                        FBinOp::Mul,
                        Loc {
                            ty: Ty::Float,
                            reg: a + i,
                        },
                        Loc {
                            ty: Ty::Float,
                            reg: b + j,
                        },
                    );
                    let q = self.fzip(
                        FBinOp::Mul,
                        Loc {
                            ty: Ty::Float,
                            reg: a + j,
                        },
                        Loc {
                            ty: Ty::Float,
                            reg: b + i,
                        },
                    );
                    self.emit_op(Op::FBin {
                        op: FBinOp::Sub,
                        d: out.reg + k,
                        a: p.reg,
                        b: q.reg,
                    });
                }
                Ok(out)
            }
            "normalize" => {
                self.arity(name, args, 1, 1, pos)?;
                let v = self.expr(&args[0], None)?;
                if !v.ty.is_vector() {
                    return Err(self.no_form(name, &[v], pos));
                }
                let d = self.dot(v, v);
                let len = self.fmap(d, FUnOp::Sqrt);
                // A zero vector stays zero (the division gives 0).
                Ok(self.fzip(FBinOp::Div, v, len))
            }
            "avg" => {
                let v = self.eval_args(args)?;
                if v.is_empty() {
                    // Found by fuzzing: `avg()` indexed an empty list.
                    return Err(self.no_form(name, &v, pos));
                }
                if v.len() == 1 && v[0].ty.is_vector() {
                    let n = self.fconst(v[0].ty.floats() as f32);
                    let one = self.fconst(1.0);
                    let w = self.fzip(FBinOp::Div, one, n);
                    let weights = self.convert(w, v[0].ty, pos)?;
                    return Ok(self.dot(v[0], weights));
                }
                let mut acc = self.floaty(v[0], name, pos)?;
                for x in &v[1..] {
                    let x = self.floaty(*x, name, pos)?;
                    acc = self.fzip(FBinOp::Add, acc, x);
                }
                let n = self.fconst(v.len() as f32);
                Ok(self.fzip(FBinOp::Div, acc, n))
            }
            "set" => {
                let v = self.eval_args(args)?;
                if v.len() == 1 {
                    let to = hint_num.unwrap_or(v[0].ty);
                    return self.convert(v[0], to, pos);
                }
                let mut comps = Vec::new();
                for x in &v {
                    let x = self.floaty(*x, name, pos)?;
                    comps.extend((0..x.ty.floats() as u32).map(|k| x.reg + k));
                }
                let ty = Ty::of_floats(comps.len()).ok_or_else(|| self.no_form(name, &v, pos))?;
                let out = self.alloc(ty);
                for (k, c) in comps.into_iter().enumerate() {
                    self.emit_op(Op::FMov {
                        d: out.reg + k as u32,
                        s: c,
                    });
                }
                Ok(out)
            }
            "getcomp" => {
                self.arity(name, args, 2, 3, pos)?;
                let v = self.expr(&args[0], None)?;
                let ExprKind::Int(k) = args[1].kind else {
                    return err(args[1].pos, "getcomp's index must be a constant");
                };
                let k = if args.len() == 3 {
                    let ExprKind::Int(c) = args[2].kind else {
                        return err(args[2].pos, "getcomp's column must be a constant");
                    };
                    k * if v.ty == Ty::Mat3 { 3 } else { 4 } + c
                } else {
                    k
                };
                if !(0..v.ty.floats() as i64).contains(&k) || v.ty.floats() < 2 {
                    return Err(self.no_form(name, &[v], pos));
                }
                Ok(Loc {
                    ty: Ty::Float,
                    reg: v.reg + k as u32,
                })
            }
            "setcomp" => {
                self.arity(name, args, 3, 3, pos)?;
                let t = self.target(&args[0])?;
                let cur = self.read_target(t, pos)?;
                let x = self.arg(&args[1], Ty::Float, name)?;
                let ExprKind::Int(k) = args[2].kind else {
                    return err(args[2].pos, "setcomp's index must be a constant");
                };
                if !(0..cur.ty.floats() as i64).contains(&k) || cur.ty.floats() < 2 {
                    return Err(self.no_form(name, &[cur], pos));
                }
                self.store(
                    Loc {
                        ty: Ty::Float,
                        reg: cur.reg + k as u32,
                    },
                    x,
                );
                Ok(Loc {
                    ty: Ty::Void,
                    reg: 0,
                })
            }
            "ch" | "chf" | "chi" | "chv" | "chs" | "chu" | "chp" => self.channel(name, args, pos),
            "chramp" => self.chramp(args, hint, pos),
            "array" => self.array_call(args, hint, pos),
            _ => Err(self.unknown_function(name, pos)),
        }
    }

    /// `ch("name")`: the node's parameter, a constant of this cook.
    fn channel(&mut self, name: &str, args: &[Expr], pos: Pos) -> LResult<Loc> {
        self.arity(name, args, 1, 2, pos)?;
        let ExprKind::Str(param) = &args[0].kind else {
            return err(
                args[0].pos,
                format!("'{name}' needs the parameter's name as a string literal"),
            );
        };
        let Some(value) = (self.spec.channels)(param) else {
            let known = (self.spec.channel_names)();
            return err(
                args[0].pos,
                format!(
                    "{name}(\"{param}\"): the node has no parameter '{param}'{}",
                    suggest(param, known.iter().map(String::as_str))
                ),
            );
        };
        let ty = match name {
            "chi" => Ty::Int,
            "chv" => Ty::Vec3,
            "chs" => Ty::Str,
            "chu" => Ty::Vec2,
            "chp" => Ty::Vec4,
            _ => Ty::Float,
        };
        use crate::compile::Channel as C;
        // ch() of a ramp is its number of keys (a multiparm's count).
        let value = match value {
            C::Ramp(r) => C::Num(vec![r.keys().len() as f64]),
            other => other,
        };
        Ok(match (ty, value) {
            (Ty::Str, C::Str(s)) => self.sconst(&s),
            (Ty::Str, _) => {
                return err(
                    pos,
                    format!("{name}(\"{param}\"): the parameter is not a string"),
                )
            }
            (_, C::Str(_)) => {
                return err(
                    pos,
                    format!("{name}(\"{param}\"): the parameter is a string; use chs"),
                )
            }
            (Ty::Int, C::Num(v)) => self.iconst(v.first().copied().unwrap_or(0.0).round() as i32),
            (_, C::Ramp(_)) => unreachable!("read as its key count above"),
            (t, C::Num(v)) => {
                let out = self.alloc(t);
                for k in 0..t.floats() {
                    // A scalar parameter fills every component.
                    let x = v
                        .get(k)
                        .or_else(|| (v.len() == 1).then(|| &v[0]))
                        .copied()
                        .unwrap_or(0.0);
                    self.emit_op(Op::FConst {
                        d: out.reg + k as u32,
                        v: x as f32,
                    });
                }
                out
            }
        })
    }

    /// `chramp("name", x)`: the ramp parameter at x (clamped to [0, 1]), a
    /// float for a float ramp, a vector for a colour ramp (or the declared
    /// type). The ramp is a constant of the cook, kept in the program.
    fn chramp(&mut self, args: &[Expr], hint: Option<Ty>, pos: Pos) -> LResult<Loc> {
        self.arity("chramp", args, 2, 3, pos)?;
        let ExprKind::Str(param) = &args[0].kind else {
            return err(
                args[0].pos,
                "'chramp' needs the parameter's name as a string literal",
            );
        };
        let ramp = match (self.spec.channels)(param) {
            Some(crate::compile::Channel::Ramp(r)) => r,
            Some(_) => {
                return err(
                    args[0].pos,
                    format!("chramp(\"{param}\"): the parameter is not a ramp"),
                )
            }
            None => {
                let known = (self.spec.channel_names)();
                return err(
                    args[0].pos,
                    format!(
                        "chramp(\"{param}\"): the node has no parameter '{param}'{}",
                        suggest(param, known.iter().map(String::as_str))
                    ),
                );
            }
        };
        let natural = match ramp.kind() {
            geode_geo::RampKind::Color => Ty::Vec3,
            _ => Ty::Float,
        };
        let out = match hint {
            Some(t) if t.is_floaty() && !t.is_matrix() => t,
            _ => natural,
        };
        let k = self.ramps.len() as i32;
        self.ramps.push(ramp);
        let x = self.arg(&args[1], Ty::Float, "chramp")?;
        let index = self.iconst(k);
        Ok(self.call_site(
            crate::library::channel_ops::CHRAMP,
            vec![index, x],
            out,
            pos,
        ))
    }

    /// `array(a, b, ...)`: the element type is the declared one, else the
    /// first argument's.
    fn array_call(&mut self, args: &[Expr], hint: Option<Ty>, pos: Pos) -> LResult<Loc> {
        let elem = match hint {
            Some(Ty::Array(e)) => e.ty(),
            _ => {
                let first = args.first().map(|a| self.expr(a, None)).transpose()?;
                first.map_or(Ty::Float, |v| v.ty)
            }
        };
        let out = elem
            .array()
            .ok_or_else(|| CompileError::at(pos, "no arrays of arrays"))?;
        let mut vals = Vec::new();
        for a in args {
            vals.push(self.arg(a, elem, "array")?);
        }
        Ok(self.call_site(array_ops::ARRAY_OF, vals, out, pos))
    }
}
