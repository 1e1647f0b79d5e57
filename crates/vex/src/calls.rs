//! Lowering of function calls: user functions are inlined, component-wise
//! math becomes instructions, and the rest of the library becomes calls.
//! Argument types are checked here; return types that VEX picks from the
//! context (`point`, `rand`, `ident`) follow the hint.

use geode_geo::AttribClass;

use crate::ast::*;
use crate::builtins::Builtin;
use crate::ir::*;
use crate::lex::Pos;
use crate::lower::{convertible, LResult, Lower};
use crate::ty::{Elem, Ty};
use crate::{suggest, CompileError};

/// Every library name: the resolver accepts these and no others (user
/// functions aside), suggests among them, and `signatures` lists each.
pub const LIBRARY: &[&str] = &[
    "abs",
    "floor",
    "ceil",
    "frac",
    "rint",
    "trunc",
    "sqrt",
    "exp",
    "log",
    "log10",
    "sin",
    "cos",
    "tan",
    "asin",
    "acos",
    "atan",
    "atan2",
    "sinh",
    "cosh",
    "tanh",
    "radians",
    "degrees",
    "sign",
    "pow",
    "min",
    "max",
    "clamp",
    "lerp",
    "fit",
    "fit01",
    "fit10",
    "fit11",
    "efit",
    "smooth",
    "length",
    "length2",
    "distance",
    "distance2",
    "dot",
    "cross",
    "normalize",
    "avg",
    "set",
    "getcomp",
    "setcomp",
    "ch",
    "chf",
    "chi",
    "chv",
    "chs",
    "chu",
    "chp",
    "point",
    "prim",
    "vertex",
    "detail",
    "npoints",
    "nprimitives",
    "nvertices",
    "primpoints",
    "pointprims",
    "neighbours",
    "neighbourcount",
    "nearpoint",
    "nearpoints",
    "inpointgroup",
    "inprimgroup",
    "haspointattrib",
    "hasprimattrib",
    "hasdetailattrib",
    "hasvertexattrib",
    "setpointattrib",
    "setprimattrib",
    "setvertexattrib",
    "setdetailattrib",
    "addpoint",
    "addprim",
    "addvertex",
    "removepoint",
    "removeprim",
    "setpointgroup",
    "setprimgroup",
    "rand",
    "random",
    "noise",
    "snoise",
    "curlnoise",
    "len",
    "push",
    "append",
    "pop",
    "insert",
    "removeindex",
    "find",
    "sort",
    "reverse",
    "resize",
    "array",
    "sprintf",
    "itoa",
    "atof",
    "atoi",
    "concat",
    "startswith",
    "endswith",
    "split",
    "strlen",
    "ident",
    "invert",
    "transpose",
    "determinant",
    "qmultiply",
    "qrotate",
    "qconvert",
    "quaternion",
    "eulertoquaternion",
    "dihedral",
    "rotate",
    "scale",
    "translate",
    "maketransform",
    "lookat",
    "printf",
    "pointhedge",
    "primhedge",
    "hedge_next",
    "hedge_srcpoint",
    "hedge_dstpoint",
    "hedge_isvalid",
    "hedge_prim",
];

fn err<T>(pos: Pos, msg: impl Into<String>) -> LResult<T> {
    Err(CompileError::at(pos, msg))
}

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
    fn eval_args(&mut self, args: &[Expr]) -> LResult<Vec<Loc>> {
        args.iter().map(|a| self.expr(a, None)).collect()
    }

    fn arity(&self, name: &str, args: &[Expr], lo: usize, hi: usize, pos: Pos) -> LResult<()> {
        if args.len() < lo || args.len() > hi {
            let want = if lo == hi {
                format!("{lo}")
            } else {
                format!("{lo} to {hi}")
            };
            return err(
                pos,
                format!("'{name}' takes {want} arguments, not {}", args.len()),
            );
        }
        Ok(())
    }

    fn no_form(&self, name: &str, vals: &[Loc], pos: Pos) -> CompileError {
        let got: Vec<String> = vals.iter().map(|v| v.ty.to_string()).collect();
        CompileError::at(
            pos,
            format!("no form of '{name}' takes ({})", got.join(", ")),
        )
    }

    /// Converts an int to float; float-based values pass.
    fn floaty(&mut self, v: Loc, name: &str, pos: Pos) -> LResult<Loc> {
        match v.ty {
            Ty::Int => self.convert(v, Ty::Float, pos),
            t if t.is_floaty() => Ok(v),
            _ => Err(self.no_form(name, &[v], pos)),
        }
    }

    fn arg(&mut self, e: &Expr, ty: Ty, name: &str) -> LResult<Loc> {
        let v = self.expr(e, Some(ty))?;
        if !convertible(v.ty, ty) {
            return err(
                e.pos,
                format!("'{name}' expects {} here, not {}", ty.a(), v.ty.a()),
            );
        }
        self.convert(v, ty, e.pos)
    }

    /// Writes `v` back to the variable passed as the first argument.
    fn in_place(&mut self, target: &Expr, v: Loc, pos: Pos) -> LResult<()> {
        let t = self.target(target)?;
        self.write_target(t, v, pos)
    }

    fn dot(&mut self, a: Loc, b: Loc) -> Loc {
        let p = self.fzip(FBinOp::Mul, a, b);
        let mut acc = Loc {
            ty: Ty::Float,
            reg: p.reg,
        };
        for k in 1..p.ty.floats() as u32 {
            acc = self.fzip(
                FBinOp::Add,
                acc,
                Loc {
                    ty: Ty::Float,
                    reg: p.reg + k,
                },
            );
        }
        acc
    }

    fn clamp(&mut self, x: Loc, lo: Loc, hi: Loc) -> Loc {
        let t = self.fzip(FBinOp::Min, x, hi);
        self.fzip(FBinOp::Max, t, lo)
    }

    /// `nmin + (nmax - nmin) * t`.
    fn mix(&mut self, a: Loc, b: Loc, t: Loc) -> Loc {
        let d = self.fzip(FBinOp::Sub, b, a);
        let s = self.fzip(FBinOp::Mul, d, t);
        self.fzip(FBinOp::Add, a, s)
    }

    /// The attribute type `name` has in input `geo` when both are constants.
    fn attrib_type(&self, geo: &Expr, name: &Expr, class: AttribClass) -> Option<Ty> {
        let (ExprKind::Int(i), ExprKind::Str(n)) = (&geo.kind, &name.kind) else {
            return None;
        };
        let g = self.spec.inputs.get(*i as usize).copied().flatten()?;
        if class == AttribClass::Point && n == "P" {
            return Some(Ty::Vec3);
        }
        crate::bind::ty_of(g.attrib(class, n)?.data())
    }

    pub fn call(&mut self, name: &str, args: &[Expr], hint: Option<Ty>, pos: Pos) -> LResult<Loc> {
        if name == "__sequence" {
            let mut last = None;
            for a in args {
                last = Some(self.expr(a, None)?);
            }
            return Ok(last.expect("a sequence has items"));
        }
        if let Some(v) = self.user_call(name, args, pos)? {
            return Ok(v);
        }
        // The library is exactly `LIBRARY`: a name missing from it is
        // unknown even if an arm below would lower it, so the list (and the
        // signature table checked against it) cannot fall behind the arms.
        if !LIBRARY.contains(&name) {
            return Err(self.unknown_function(name, pos));
        }
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
            _ => self.library(name, args, hint, pos),
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
        use crate::bind::Channel as C;
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

    fn library(&mut self, name: &str, args: &[Expr], hint: Option<Ty>, pos: Pos) -> LResult<Loc> {
        use Builtin as B;
        let int = Ty::Int;
        let s = Ty::Str;
        let ia = Ty::Array(Elem::Int);
        let call = |me: &mut Self, f: Builtin, specs: &[Ty], out: Ty| -> LResult<Loc> {
            let mut vals = Vec::new();
            for (a, t) in args.iter().zip(specs) {
                vals.push(me.arg(a, *t, name)?);
            }
            Ok(me.call_site(f, vals, out, pos))
        };
        let value_ty = |me: &mut Self, e: &Expr| -> LResult<Loc> { me.expr(e, None) };
        match name {
            "rand" | "random" | "noise" | "snoise" => {
                self.arity(name, args, 1, 4, pos)?;
                let mut vals = Vec::new();
                for a in args {
                    let v = self.expr(a, None)?;
                    vals.push(self.floaty(v, name, pos)?);
                }
                let out = match hint {
                    Some(t) if t.is_floaty() && !t.is_matrix() => t,
                    _ => Ty::Float,
                };
                let f = match name {
                    "noise" => B::Noise,
                    "snoise" => B::SNoise,
                    _ => B::Rand,
                };
                if f != B::Rand {
                    let p = self.convert(vals[0], Ty::Vec3, pos)?;
                    return Ok(self.call_site(f, vec![p], out, pos));
                }
                Ok(self.call_site(f, vals, out, pos))
            }
            "curlnoise" => {
                self.arity(name, args, 1, 1, pos)?;
                call(self, B::CurlNoise, &[Ty::Vec3], Ty::Vec3)
            }
            "point" | "prim" | "vertex" => {
                self.arity(name, args, 3, 3, pos)?;
                let class = match name {
                    "point" => AttribClass::Point,
                    "prim" => AttribClass::Primitive,
                    _ => AttribClass::Vertex,
                };
                let out = hint
                    .filter(|t| *t != Ty::Void)
                    .or_else(|| self.attrib_type(&args[0], &args[1], class))
                    .unwrap_or(Ty::Float);
                call(self, B::Read(class), &[int, s, int], out)
            }
            "detail" => {
                self.arity(name, args, 2, 3, pos)?;
                let out = hint
                    .filter(|t| *t != Ty::Void)
                    .or_else(|| self.attrib_type(&args[0], &args[1], AttribClass::Detail))
                    .unwrap_or(Ty::Float);
                call(self, B::Read(AttribClass::Detail), &[int, s], out)
            }
            "npoints" | "nprimitives" | "nvertices" => {
                self.arity(name, args, 1, 1, pos)?;
                let f = match name {
                    "npoints" => B::NPoints,
                    "nprimitives" => B::NPrims,
                    _ => B::NVertices,
                };
                call(self, f, &[int], int)
            }
            "primpoints" => {
                self.arity(name, args, 2, 2, pos)?;
                call(self, B::PrimPoints, &[int, int], ia)
            }
            "pointprims" | "neighbours" => {
                self.arity(name, args, 2, 2, pos)?;
                call(
                    self,
                    if name == "pointprims" {
                        B::PointPrims
                    } else {
                        B::Neighbours
                    },
                    &[int, int],
                    ia,
                )
            }
            "neighbourcount" => {
                self.arity(name, args, 2, 2, pos)?;
                call(self, B::NeighbourCount, &[int, int], int)
            }
            "nearpoint" | "nearpoints" => {
                // (geo, [group,] position, [maxdist, [maxpoints]]): the
                // group form when the second argument is a string.
                let grouped = args.len() >= 3
                    && match &args[1].kind {
                        ExprKind::Str(_) => true,
                        ExprKind::Var(v) => self.lookup(v).is_some_and(|l| l.ty == Ty::Str),
                        _ => false,
                    };
                let (lo, hi) = match (name, grouped) {
                    ("nearpoint", false) => (2, 3),
                    ("nearpoint", true) => (3, 4),
                    (_, false) => (3, 4),
                    (_, true) => (4, 5),
                };
                self.arity(name, args, lo, hi, pos)?;
                let mut specs = vec![int];
                if grouped {
                    specs.push(s);
                }
                specs.extend([Ty::Vec3, Ty::Float, int]);
                let f = if name == "nearpoint" {
                    B::NearPoint(grouped)
                } else {
                    B::NearPoints(grouped)
                };
                call(
                    self,
                    f,
                    &specs[..args.len()],
                    if name == "nearpoint" { int } else { ia },
                )
            }
            "pointhedge" | "primhedge" | "hedge_next" | "hedge_srcpoint" | "hedge_dstpoint"
            | "hedge_isvalid" | "hedge_prim" => {
                use crate::builtins::HedgeFn as H;
                self.arity(name, args, 2, 2, pos)?;
                let f = match name {
                    "pointhedge" => H::PointHedge,
                    "primhedge" => H::PrimHedge,
                    "hedge_next" => H::Next,
                    "hedge_srcpoint" => H::SrcPoint,
                    "hedge_dstpoint" => H::DstPoint,
                    "hedge_isvalid" => H::IsValid,
                    _ => H::Prim,
                };
                call(self, B::Hedge(f), &[int, int], int)
            }
            "inpointgroup" | "inprimgroup" => {
                self.arity(name, args, 3, 3, pos)?;
                let class = if name == "inpointgroup" {
                    AttribClass::Point
                } else {
                    AttribClass::Primitive
                };
                call(self, B::InGroup(class), &[int, s, int], int)
            }
            "haspointattrib" | "hasprimattrib" | "hasdetailattrib" | "hasvertexattrib" => {
                self.arity(name, args, 2, 2, pos)?;
                let class = match name {
                    "haspointattrib" => AttribClass::Point,
                    "hasprimattrib" => AttribClass::Primitive,
                    "hasvertexattrib" => AttribClass::Vertex,
                    _ => AttribClass::Detail,
                };
                call(self, B::HasAttrib(class), &[int, s], int)
            }
            "setpointattrib" | "setprimattrib" | "setvertexattrib" | "setdetailattrib" => {
                let (class, lead) = match name {
                    "setpointattrib" => (AttribClass::Point, 3),
                    "setprimattrib" => (AttribClass::Primitive, 3),
                    "setvertexattrib" => (AttribClass::Vertex, 4),
                    _ => (AttribClass::Detail, 2),
                };
                self.arity(name, args, lead + 1, lead + 2, pos)?;
                let mut vals = vec![self.arg(&args[0], int, name)?, self.arg(&args[1], s, name)?];
                for a in &args[2..lead] {
                    vals.push(self.arg(a, int, name)?);
                }
                let v = value_ty(self, &args[lead])?;
                vals.push(v);
                if let Some(m) = args.get(lead + 1) {
                    vals.push(self.arg(m, s, name)?);
                }
                Ok(self.call_site(B::SetAttrib(class), vals, int, pos))
            }
            "addpoint" => {
                self.arity(name, args, 2, 2, pos)?;
                let g = self.arg(&args[0], int, name)?;
                let v = self.expr(&args[1], None)?;
                let v = match v.ty {
                    Ty::Int => v,
                    Ty::Vec3 => v,
                    _ => return Err(self.no_form(name, &[g, v], pos)),
                };
                Ok(self.call_site(B::AddPoint, vec![g, v], int, pos))
            }
            "addprim" => {
                if args.len() < 2 {
                    return err(
                        pos,
                        "'addprim' takes a geometry, a type and optionally points",
                    );
                }
                let mut vals = vec![self.arg(&args[0], int, name)?, self.arg(&args[1], s, name)?];
                for a in &args[2..] {
                    let v = self.expr(a, None)?;
                    if v.ty != int && v.ty != ia {
                        return err(
                            a.pos,
                            format!(
                                "\'addprim\' takes point numbers or an int array, not {}",
                                v.ty.a()
                            ),
                        );
                    }
                    vals.push(v);
                }
                Ok(self.call_site(B::AddPrim, vals, int, pos))
            }
            "addvertex" => {
                self.arity(name, args, 3, 3, pos)?;
                call(self, B::AddVertex, &[int, int, int], int)
            }
            "removepoint" => {
                self.arity(name, args, 2, 2, pos)?;
                call(self, B::RemovePoint, &[int, int], int)
            }
            "removeprim" => {
                self.arity(name, args, 2, 3, pos)?;
                call(self, B::RemovePrim, &[int, int, int], int)
            }
            "setpointgroup" | "setprimgroup" => {
                self.arity(name, args, 4, 5, pos)?;
                let class = if name == "setpointgroup" {
                    AttribClass::Point
                } else {
                    AttribClass::Primitive
                };
                call(self, B::SetGroup(class), &[int, s, int, int], int)
            }
            "len" | "strlen" => {
                self.arity(name, args, 1, 1, pos)?;
                let v = self.expr(&args[0], None)?;
                if !matches!(v.ty, Ty::Array(_) | Ty::Str) && !v.ty.is_vector() {
                    return Err(self.no_form(name, &[v], pos));
                }
                Ok(self.call_site(
                    if name == "len" { B::Len } else { B::StrLen },
                    vec![v],
                    int,
                    pos,
                ))
            }
            "push" | "append" | "insert" | "removeindex" | "resize" | "pop" => {
                let (lo, hi) = match name {
                    "pop" => (1, 1),
                    "insert" => (3, 3),
                    "push" | "append" => (2, 2),
                    _ => (2, 2),
                };
                self.arity(name, args, lo, hi, pos)?;
                let arr = self.expr(&args[0], None)?;
                let Ty::Array(e) = arr.ty else {
                    if name == "append" && arr.ty == Ty::Str {
                        let x = self.arg(&args[1], s, name)?;
                        let joined = self.call_site(B::Concat, vec![arr, x], s, pos);
                        self.in_place(&args[0], joined, pos)?;
                        return Ok(Loc {
                            ty: Ty::Void,
                            reg: 0,
                        });
                    }
                    return err(
                        args[0].pos,
                        format!("'{name}' needs an array, not {}", arr.ty.a()),
                    );
                };
                let mut vals = vec![arr];
                match name {
                    "insert" => {
                        vals.push(self.arg(&args[1], int, name)?);
                        vals.push(self.arg(&args[2], e.ty(), name)?);
                    }
                    "removeindex" | "resize" => vals.push(self.arg(&args[1], int, name)?),
                    "push" | "append" => {
                        let v = self.expr(&args[1], Some(e.ty()))?;
                        let v = if v.ty == arr.ty {
                            v
                        } else {
                            self.convert_arg(v, e.ty(), name, args[1].pos)?
                        };
                        vals.push(v);
                    }
                    _ => {}
                }
                if name == "pop" {
                    let last = self.call_site(B::Pop, vals.clone(), e.ty(), pos);
                    let last = self.copy(last);
                    let n = self.call_site(B::Len, vec![arr], int, pos);
                    let one = self.iconst(1);
                    let m = self.ibin(IBinOp::Sub, n.reg, one.reg);
                    let shorter =
                        self.call_site(B::Resize, vec![arr, Loc { ty: int, reg: m }], arr.ty, pos);
                    self.in_place(&args[0], shorter, pos)?;
                    return Ok(last);
                }
                let f = match name {
                    "insert" => B::Insert,
                    "removeindex" => B::RemoveIndex,
                    "resize" => B::Resize,
                    _ => B::Push,
                };
                let new = self.call_site(f, vals, arr.ty, pos);
                self.in_place(&args[0], new, pos)?;
                Ok(Loc {
                    ty: Ty::Void,
                    reg: 0,
                })
            }
            "find" => {
                self.arity(name, args, 2, 2, pos)?;
                let v = self.eval_args(args)?;
                if !matches!(v[0].ty, Ty::Array(_) | Ty::Str) {
                    return Err(self.no_form(name, &v, pos));
                }
                Ok(self.call_site(B::Find, v, int, pos))
            }
            "sort" | "reverse" => {
                self.arity(name, args, 1, 1, pos)?;
                let v = self.expr(&args[0], None)?;
                if !(matches!(v.ty, Ty::Array(_)) || (name == "reverse" && v.ty == Ty::Str)) {
                    return Err(self.no_form(name, &[v], pos));
                }
                Ok(self.call_site(
                    if name == "sort" { B::Sort } else { B::Reverse },
                    vec![v],
                    v.ty,
                    pos,
                ))
            }
            "array" => {
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
                    vals.push(self.arg(a, elem, name)?);
                }
                Ok(self.call_site(B::ArrayOf, vals, out, pos))
            }
            "sprintf" | "printf" => {
                if args.is_empty() {
                    return err(pos, format!("'{name}' needs a format string"));
                }
                let mut vals = vec![self.arg(&args[0], s, name)?];
                for a in &args[1..] {
                    vals.push(self.expr(a, None)?);
                }
                Ok(self.call_site(
                    if name == "printf" {
                        B::Print
                    } else {
                        B::Sprintf
                    },
                    vals,
                    s,
                    pos,
                ))
            }
            "itoa" => {
                self.arity(name, args, 1, 1, pos)?;
                call(self, B::Itoa, &[int], s)
            }
            "atof" | "atoi" => {
                self.arity(name, args, 1, 1, pos)?;
                call(
                    self,
                    if name == "atof" { B::Atof } else { B::Atoi },
                    &[s],
                    if name == "atof" { Ty::Float } else { int },
                )
            }
            "concat" => {
                let specs = vec![s; args.len()];
                call(self, B::Concat, &specs, s)
            }
            "startswith" | "endswith" => {
                self.arity(name, args, 2, 2, pos)?;
                call(
                    self,
                    if name == "startswith" {
                        B::StartsWith
                    } else {
                        B::EndsWith
                    },
                    &[s, s],
                    int,
                )
            }
            "split" => {
                self.arity(name, args, 1, 2, pos)?;
                call(self, B::Split, &[s, s], Ty::Array(Elem::Str))
            }
            "ident" => {
                self.arity(name, args, 0, 0, pos)?;
                let out = match hint {
                    Some(Ty::Mat3) => Ty::Mat3,
                    _ => Ty::Mat4,
                };
                Ok(self.call_site(B::Ident, vec![], out, pos))
            }
            "invert" | "transpose" | "determinant" => {
                self.arity(name, args, 1, 1, pos)?;
                let v = self.expr(&args[0], None)?;
                if !(v.ty.is_matrix() || (name == "invert" && v.ty == Ty::Float)) {
                    return Err(self.no_form(name, &[v], pos));
                }
                let out = if name == "determinant" {
                    Ty::Float
                } else {
                    v.ty
                };
                let f = match name {
                    "invert" => B::Invert,
                    "transpose" => B::Transpose,
                    _ => B::Determinant,
                };
                Ok(self.call_site(f, vec![v], out, pos))
            }
            "qmultiply" => {
                self.arity(name, args, 2, 2, pos)?;
                call(self, B::QMultiply, &[Ty::Vec4, Ty::Vec4], Ty::Vec4)
            }
            "qrotate" => {
                self.arity(name, args, 2, 2, pos)?;
                call(self, B::QRotate, &[Ty::Vec4, Ty::Vec3], Ty::Vec3)
            }
            "qconvert" => {
                self.arity(name, args, 1, 1, pos)?;
                call(self, B::QConvert, &[Ty::Vec4], Ty::Mat3)
            }
            "quaternion" => {
                self.arity(name, args, 1, 2, pos)?;
                if args.len() == 2 {
                    return call(self, B::QuaternionAxis, &[Ty::Float, Ty::Vec3], Ty::Vec4);
                }
                let v = self.expr(&args[0], None)?;
                if v.ty != Ty::Mat3 && v.ty != Ty::Vec3 && v.ty != Ty::Mat4 {
                    return Err(self.no_form(name, &[v], pos));
                }
                Ok(self.call_site(B::Quaternion, vec![v], Ty::Vec4, pos))
            }
            "eulertoquaternion" => {
                self.arity(name, args, 2, 2, pos)?;
                call(self, B::EulerToQuaternion, &[Ty::Vec3, int], Ty::Vec4)
            }
            "dihedral" => {
                self.arity(name, args, 2, 2, pos)?;
                let out = if hint == Some(Ty::Mat3) {
                    Ty::Mat3
                } else {
                    Ty::Vec4
                };
                call(self, B::Dihedral, &[Ty::Vec3, Ty::Vec3], out)
            }
            "rotate" | "scale" | "translate" => {
                self.arity(
                    name,
                    args,
                    if name == "rotate" { 3 } else { 2 },
                    if name == "rotate" { 3 } else { 2 },
                    pos,
                )?;
                let m = self.expr(&args[0], None)?;
                if !m.ty.is_matrix() || (name == "translate" && m.ty != Ty::Mat4) {
                    return Err(self.no_form(name, &[m], pos));
                }
                let mut vals = vec![m];
                if name == "rotate" {
                    vals.push(self.arg(&args[1], Ty::Float, name)?);
                    vals.push(self.arg(&args[2], Ty::Vec3, name)?);
                } else {
                    vals.push(self.arg(&args[1], Ty::Vec3, name)?);
                }
                let f = match name {
                    "rotate" => B::Rotate,
                    "scale" => B::Scale,
                    _ => B::Translate,
                };
                let new = self.call_site(f, vals, m.ty, pos);
                self.in_place(&args[0], new, pos)?;
                Ok(Loc {
                    ty: Ty::Void,
                    reg: 0,
                })
            }
            "maketransform" => {
                let out = if hint == Some(Ty::Mat3) {
                    Ty::Mat3
                } else {
                    Ty::Mat4
                };
                if args.len() >= 4 {
                    self.arity(name, args, 4, 6, pos)?;
                    let specs = [int, int, Ty::Vec3, Ty::Vec3, Ty::Vec3, Ty::Vec3];
                    return call(self, B::MakeTransform, &specs[..args.len()], out);
                }
                self.arity(name, args, 2, 3, pos)?;
                let out = if args.len() == 2 && hint != Some(Ty::Mat4) {
                    Ty::Mat3
                } else {
                    out
                };
                call(self, B::MakeTransform, &[Ty::Vec3, Ty::Vec3, Ty::Vec3], out)
            }
            "lookat" => {
                self.arity(name, args, 2, 3, pos)?;
                call(self, B::LookAt, &[Ty::Vec3, Ty::Vec3, Ty::Vec3], Ty::Mat3)
            }
            _ => Err(self.unknown_function(name, pos)),
        }
    }

    /// "unknown function", with the closest library or snippet function.
    fn unknown_function(&self, name: &str, pos: Pos) -> CompileError {
        let mut known: Vec<&str> = LIBRARY.to_vec();
        let user = self.function_names();
        known.extend(user.iter().map(String::as_str));
        CompileError::at(
            pos,
            format!(
                "unknown function '{name}'{}",
                suggest(name, known.into_iter())
            ),
        )
    }

    fn convert_arg(&mut self, v: Loc, to: Ty, name: &str, pos: Pos) -> LResult<Loc> {
        if !convertible(v.ty, to) {
            return err(
                pos,
                format!("'{name}' expects {} here, not {}", to.a(), v.ty.a()),
            );
        }
        self.convert(v, to, pos)
    }
}
