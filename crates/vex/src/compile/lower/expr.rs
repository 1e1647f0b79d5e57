//! Lowering of expressions: literals, variables and bindings, operators
//! with VEX's promotions (int to float, scalar to vector), assignment to
//! variables, components and array elements, and conversions.

use crate::compile::ast::*;
use crate::compile::lex::Pos;
use crate::error::CompileError;
use crate::ir::*;
use crate::library::{array_ops, matrix_ops, string_ops};
use crate::ty::Ty;
use crate::value::Val;

use super::{LResult, Lower};

pub(super) fn err<T>(pos: Pos, msg: impl Into<String>) -> LResult<T> {
    Err(CompileError::at(pos, msg))
}

/// Where an assignment writes.
#[derive(Clone, Copy, Debug)]
pub enum Target {
    /// Registers of a variable, binding, or one of their components.
    Regs(Loc),
    /// Element `idx` of the array in `arr`.
    Elem { arr: Loc, idx: Loc },
}

impl<'a> Lower<'a> {
    pub fn expr(&mut self, e: &Expr, hint: Option<Ty>) -> LResult<Loc> {
        match &e.kind {
            ExprKind::Int(n) => Ok(match hint {
                Some(t) if t.is_floaty() && t.floats() == 1 => self.fconst(*n as f32),
                _ => self.iconst(*n as i32),
            }),
            ExprKind::Float(x) => Ok(self.fconst(*x as f32)),
            ExprKind::Str(s) => Ok(self.sconst(s)),
            ExprKind::Var(name) => match self.lookup(name) {
                Some(v) => Ok(v),
                // math.h's constants, unless the snippet declares the name.
                None => match crate::library::constant(name) {
                    Some(crate::library::Constant::Float(x)) => Ok(self.fconst(x as f32)),
                    Some(crate::library::Constant::Int(i)) => Ok(self.iconst(i)),
                    None => Err(self.undeclared(name, e.pos)),
                },
            },
            ExprKind::Binding { name, .. } => Ok(self.binding(name)),
            ExprKind::Braces(items) => self.braces(items, hint, e.pos),
            ExprKind::Unary(op, x) => self.unary(op, x, e.pos),
            ExprKind::Binary(op, a, b) => {
                let x = self.expr(a, None)?;
                let y = self.expr(b, None)?;
                self.binary(op, x, y, e.pos)
            }
            ExprKind::Assign(op, target, value) => self.assign(op, target, value, e.pos),
            ExprKind::IncDec {
                delta,
                prefix,
                target,
            } => self.inc_dec(*delta, Some(*prefix), target, e.pos),
            ExprKind::Ternary(c, a, b) => {
                let cond = self.truth(c)?;
                let x = self.expr(a, hint)?;
                let y = self.expr(b, hint)?;
                let ty = unify(x.ty, y.ty).ok_or_else(|| {
                    CompileError::at(
                        e.pos,
                        format!("the branches of '?:' differ: {} and {}", x.ty, y.ty),
                    )
                })?;
                let x = self.convert(x, ty, a.pos)?;
                let y = self.convert(y, ty, b.pos)?;
                let out = self.copy(y);
                self.select_into(out, x, cond);
                Ok(out)
            }
            ExprKind::Call(name, args) => self.call(name, args, hint, e.pos),
            ExprKind::Member(x, name) => {
                let v = self.expr(x, None)?;
                self.swizzle(v, name, e.pos)
            }
            ExprKind::Index(x, i) => {
                let v = self.expr(x, None)?;
                self.index(v, i, e.pos)
            }
            ExprKind::Slice {
                seq,
                start,
                end,
                step,
            } => self.slice(seq, [start, end, step], e.pos),
            ExprKind::Cast(ty, x) => {
                let v = self.expr(x, Some(*ty))?;
                self.cast(v, *ty, e.pos)
            }
        }
    }

    /// `out = c ? x : out` on every lane, whatever the current mask.
    pub fn select_into(&mut self, out: Loc, x: Loc, c: Reg) {
        let saved = std::mem::take(self.masks_mut());
        self.masks_mut().push(c);
        self.store(out, x);
        *self.masks_mut() = saved;
    }

    /// The binding's registers.
    pub fn binding(&mut self, name: &str) -> Loc {
        let b = self
            .bindings
            .iter()
            .find(|b| b.name == name)
            .expect("every binding found by the pre-pass");
        b.loc
    }

    /// A value as a 0/1 truth register.
    pub fn truth(&mut self, e: &Expr) -> LResult<Reg> {
        let v = self.expr(e, None)?;
        self.truth_of(v, e.pos)
    }

    pub fn truth_of(&mut self, v: Loc, pos: Pos) -> LResult<Reg> {
        match v.ty {
            Ty::Int => {
                let d = self.alloc(Ty::Int).reg;
                self.emit_op(Op::IUn {
                    op: IUnOp::Truth,
                    d,
                    a: v.reg,
                });
                Ok(d)
            }
            Ty::Float => {
                let z = self.fconst(0.0);
                let d = self.alloc(Ty::Int).reg;
                self.emit_op(Op::FCmp {
                    op: Cmp::Ne,
                    d,
                    a: v.reg,
                    b: z.reg,
                });
                Ok(d)
            }
            Ty::Str => {
                let z = self.sconst("");
                let d = self.alloc(Ty::Int).reg;
                self.emit_op(Op::SCmp {
                    op: Cmp::Ne,
                    d,
                    a: v.reg,
                    b: z.reg,
                });
                Ok(d)
            }
            t if t.is_floaty() => {
                // A vector is true when any component is non-zero.
                let z = self.fconst(0.0);
                let mut acc: Option<Reg> = None;
                for k in 0..t.floats() as u32 {
                    let d = self.alloc(Ty::Int).reg;
                    self.emit_op(Op::FCmp {
                        op: Cmp::Ne,
                        d,
                        a: v.reg + k,
                        b: z.reg,
                    });
                    acc = Some(match acc {
                        Some(a) => self.ibin(IBinOp::LOr, a, d),
                        None => d,
                    });
                }
                Ok(acc.expect("a component"))
            }
            t => err(pos, format!("{} cannot be a condition", t.a())),
        }
    }

    fn braces(&mut self, items: &[Expr], hint: Option<Ty>, pos: Pos) -> LResult<Loc> {
        if let Some(t @ Ty::Array(e)) = hint {
            let mut vals = Vec::new();
            for it in items {
                let v = self.expr(it, Some(e.ty()))?;
                vals.push(self.convert(v, e.ty(), it.pos)?);
            }
            return Ok(self.call_site(array_ops::ARRAY_OF, vals, t, pos));
        }
        // Nested braces of a matrix ({{1,0,0},{0,1,0},{0,0,1}}) flatten.
        let mut vals = Vec::new();
        for it in items {
            let v = self.expr(it, None)?;
            vals.push(v);
        }
        let width: usize = vals
            .iter()
            .map(|v| if v.ty == Ty::Int { 1 } else { v.ty.floats() })
            .sum();
        let ty = match hint {
            Some(t) if t.is_floaty() && t.floats() == width => t,
            _ => Ty::of_floats(width).ok_or_else(|| {
                CompileError::at(pos, format!("{{...}} of {width} values is no VEX type"))
            })?,
        };
        let out = self.alloc(ty);
        let mut k = 0;
        for (v, it) in vals.into_iter().zip(items) {
            let v = if v.ty == Ty::Int {
                self.convert(v, Ty::Float, it.pos)?
            } else {
                v
            };
            if !v.ty.is_floaty() {
                return err(it.pos, format!("{{...}} holds numbers, not {}", v.ty.a()));
            }
            for c in 0..v.ty.floats() as u32 {
                self.emit_op(Op::FMov {
                    d: out.reg + k,
                    s: v.reg + c,
                });
                k += 1;
            }
        }
        Ok(out)
    }

    fn unary(&mut self, op: &str, x: &Expr, pos: Pos) -> LResult<Loc> {
        let v = self.expr(x, None)?;
        match (op, v.ty) {
            ("+", t) if t.is_numeric() => Ok(v),
            ("-", Ty::Int) => Ok(self.iun(IUnOp::Neg, v)),
            ("-", t) if t.is_floaty() => Ok(self.fmap(v, FUnOp::Neg)),
            ("!", _) => {
                let t = self.truth_of(v, pos)?;
                Ok(self.iun(
                    IUnOp::Not,
                    Loc {
                        ty: Ty::Int,
                        reg: t,
                    },
                ))
            }
            ("~", Ty::Int) => Ok(self.iun(IUnOp::BitNot, v)),
            (op, t) => err(pos, format!("operator '{op}' has no form for {t}")),
        }
    }

    pub fn iun(&mut self, op: IUnOp, v: Loc) -> Loc {
        let d = self.alloc(Ty::Int);
        self.emit_op(Op::IUn {
            op,
            d: d.reg,
            a: v.reg,
        });
        d
    }

    /// A unary float op applied to every component.
    pub fn fmap(&mut self, v: Loc, op: FUnOp) -> Loc {
        let d = self.alloc(v.ty);
        for k in 0..v.ty.floats() as u32 {
            self.emit_op(Op::FUn {
                op,
                d: d.reg + k,
                a: v.reg + k,
            });
        }
        d
    }

    /// A binary float op per component; a 1-wide operand is broadcast.
    pub fn fzip(&mut self, op: FBinOp, a: Loc, b: Loc) -> Loc {
        let ty = if a.ty.floats() >= b.ty.floats() {
            a.ty
        } else {
            b.ty
        };
        let d = self.alloc(ty);
        for k in 0..ty.floats() as u32 {
            let ak = if a.ty.floats() == 1 { a.reg } else { a.reg + k };
            let bk = if b.ty.floats() == 1 { b.reg } else { b.reg + k };
            self.emit_op(Op::FBin {
                op,
                d: d.reg + k,
                a: ak,
                b: bk,
            });
        }
        d
    }

    pub fn binary(&mut self, op: &str, x: Loc, y: Loc, pos: Pos) -> LResult<Loc> {
        let no_form = || {
            CompileError::at(
                pos,
                format!("operator '{op}' has no form for {} and {}", x.ty, y.ty),
            )
        };
        match op {
            "&&" | "||" => {
                let a = self.truth_of(x, pos)?;
                let b = self.truth_of(y, pos)?;
                let r = self.ibin(
                    if op == "&&" {
                        IBinOp::LAnd
                    } else {
                        IBinOp::LOr
                    },
                    a,
                    b,
                );
                return Ok(Loc {
                    ty: Ty::Int,
                    reg: r,
                });
            }
            "==" | "!=" | "<" | ">" | "<=" | ">=" => return self.compare(op, x, y, pos),
            _ => {}
        }
        if x.ty == Ty::Int && y.ty == Ty::Int {
            let iop = match op {
                "+" => IBinOp::Add,
                "-" => IBinOp::Sub,
                "*" => IBinOp::Mul,
                "/" => IBinOp::Div,
                "%" => IBinOp::Mod,
                "&" => IBinOp::And,
                "|" => IBinOp::Or,
                "^" => IBinOp::Xor,
                "<<" => IBinOp::Shl,
                ">>" => IBinOp::Shr,
                _ => return Err(no_form()),
            };
            return Ok(Loc {
                ty: Ty::Int,
                reg: self.ibin(iop, x.reg, y.reg),
            });
        }
        if !(x.ty.is_numeric() && y.ty.is_numeric()) {
            if op == "+" && x.ty == Ty::Str && y.ty == Ty::Str {
                return Ok(self.call_site(string_ops::CONCAT, vec![x, y], Ty::Str, pos));
            }
            return Err(no_form());
        }
        let x = if x.ty == Ty::Int {
            self.convert(x, Ty::Float, pos)?
        } else {
            x
        };
        let y = if y.ty == Ty::Int {
            self.convert(y, Ty::Float, pos)?
        } else {
            y
        };
        // Matrix products follow VEX's row-vector convention.
        if op == "*"
            && (x.ty.is_matrix() || y.ty.is_matrix())
            && x.ty.floats() > 1
            && y.ty.floats() > 1
        {
            return match (x.ty.is_matrix(), y.ty.is_matrix()) {
                (true, true) if x.ty == y.ty => {
                    Ok(self.call_site(matrix_ops::MATMUL, vec![x, y], x.ty, pos))
                }
                (true, true) => Ok(self.call_site(matrix_ops::MATMUL, vec![x, y], Ty::Mat4, pos)),
                (false, true) => Ok(self.call_site(matrix_ops::VECMAT, vec![x, y], x.ty, pos)),
                // matrix * vector: the vector as a column, i.e. v * transpose(m).
                (true, false) if y.ty.is_vector() => {
                    let t = self.call_site(matrix_ops::TRANSPOSE, vec![x], x.ty, pos);
                    Ok(self.call_site(matrix_ops::VECMAT, vec![y, t], y.ty, pos))
                }
                _ => Err(no_form()),
            };
        }
        let (wx, wy) = (x.ty.floats(), y.ty.floats());
        if wx != wy && wx != 1 && wy != 1 {
            return Err(no_form());
        }
        let fop = match op {
            "+" => FBinOp::Add,
            "-" => FBinOp::Sub,
            "*" => FBinOp::Mul,
            "/" => FBinOp::Div,
            "%" => FBinOp::Mod,
            _ => return Err(no_form()),
        };
        Ok(self.fzip(fop, x, y))
    }

    fn compare(&mut self, op: &str, x: Loc, y: Loc, pos: Pos) -> LResult<Loc> {
        let cmp = match op {
            "==" => Cmp::Eq,
            "!=" => Cmp::Ne,
            "<" => Cmp::Lt,
            ">" => Cmp::Gt,
            "<=" => Cmp::Le,
            _ => Cmp::Ge,
        };
        let d = self.alloc(Ty::Int);
        match (x.ty, y.ty) {
            (Ty::Int, Ty::Int) => {
                self.emit_op(Op::ICmp {
                    op: cmp,
                    d: d.reg,
                    a: x.reg,
                    b: y.reg,
                });
            }
            (Ty::Str, Ty::Str) => {
                self.emit_op(Op::SCmp {
                    op: cmp,
                    d: d.reg,
                    a: x.reg,
                    b: y.reg,
                });
            }
            (a, b) if a.is_numeric() && b.is_numeric() => {
                let x = if a == Ty::Int {
                    self.convert(x, Ty::Float, pos)?
                } else {
                    x
                };
                let y = if b == Ty::Int {
                    self.convert(y, Ty::Float, pos)?
                } else {
                    y
                };
                if x.ty.floats() == 1 && y.ty.floats() == 1 {
                    self.emit_op(Op::FCmp {
                        op: cmp,
                        d: d.reg,
                        a: x.reg,
                        b: y.reg,
                    });
                } else if x.ty == y.ty && matches!(cmp, Cmp::Eq | Cmp::Ne) {
                    // Vectors are equal when every component is.
                    let mut acc: Option<Reg> = None;
                    for k in 0..x.ty.floats() as u32 {
                        let c = self.alloc(Ty::Int).reg;
                        self.emit_op(Op::FCmp {
                            op: Cmp::Eq,
                            d: c,
                            a: x.reg + k,
                            b: y.reg + k,
                        });
                        acc = Some(match acc {
                            Some(a) => self.ibin(IBinOp::LAnd, a, c),
                            None => c,
                        });
                    }
                    let all = acc.expect("a component");
                    if cmp == Cmp::Eq {
                        self.emit_op(Op::IMov { d: d.reg, s: all });
                    } else {
                        self.emit_op(Op::IUn {
                            op: IUnOp::Not,
                            d: d.reg,
                            a: all,
                        });
                    }
                } else {
                    return err(
                        pos,
                        format!("operator '{op}' has no form for {} and {}", x.ty, y.ty),
                    );
                }
            }
            (a, b) => return err(pos, format!("operator '{op}' has no form for {a} and {b}")),
        }
        Ok(d)
    }

    /// `++x`/`x--`: its value is the old one (`prefix` false) or the new
    /// one; with `prefix` None the value is not used, so the old one is
    /// not kept.
    pub fn inc_dec(
        &mut self,
        delta: i32,
        prefix: Option<bool>,
        target: &Expr,
        pos: Pos,
    ) -> LResult<Loc> {
        let t = self.target(target)?;
        let old = self.read_target(t, target.pos)?;
        let old = if prefix == Some(false) {
            self.copy(old)
        } else {
            old
        };
        if !old.ty.is_numeric() || old.ty.is_matrix() {
            return err(
                pos,
                format!("'++'/'--' needs an int or float, not {}", old.ty),
            );
        }
        let one = if old.ty == Ty::Int {
            self.iconst(delta)
        } else {
            self.fconst(delta as f32)
        };
        let start = self.ops.len();
        let new = self.binary("+", old, one, pos)?;
        if let Some(l) = self.retarget(t, start, new) {
            return Ok(if prefix == Some(false) { old } else { l });
        }
        self.write_target(t, new, pos)?;
        Ok(if prefix == Some(false) { old } else { new })
    }

    fn assign(&mut self, op: &str, target: &Expr, value: &Expr, pos: Pos) -> LResult<Loc> {
        let t = self.target(target)?;
        let tty = self.target_ty(t);
        let v = self.expr(value, Some(tty))?;
        let v = if op == "=" {
            v
        } else if let (Target::Regs(l), "+=", Ty::Str, Ty::Str) = (t, op, tty, v.ty) {
            self.call_site_outs(
                array_ops::APPEND_STRING,
                vec![l, v],
                vec![true, false],
                Ty::Void,
                pos,
            );
            return Ok(l);
        } else {
            let old = self.read_target(t, target.pos)?;
            let bop = &op[..op.len() - 1];
            let start = self.ops.len();
            let new = self.binary(bop, old, v, pos)?;
            if let Some(l) = self.retarget(t, start, new) {
                return Ok(l);
            }
            new
        };
        let v = self.convert(v, tty, value.pos)?;
        self.write_target(t, v, pos)?;
        Ok(v)
    }

    fn target_ty(&self, t: Target) -> Ty {
        match t {
            Target::Regs(l) => l.ty,
            Target::Elem { arr, .. } => match arr.ty {
                Ty::Array(e) => e.ty(),
                _ => Ty::Float,
            },
        }
    }

    /// Resolves an assignable expression.
    pub fn target(&mut self, e: &Expr) -> LResult<Target> {
        match &e.kind {
            ExprKind::Var(name) => {
                let loc = self
                    .lookup(name)
                    .ok_or_else(|| self.undeclared(name, e.pos))?;
                self.writes_through(loc, e.pos)?;
                Ok(Target::Regs(loc))
            }
            ExprKind::Binding { name, .. } => {
                let b = self
                    .bindings
                    .iter()
                    .position(|b| b.name == *name)
                    .expect("pre-pass");
                if !self.bindings[b].writable() {
                    let why = self.bindings[b].read_only_because();
                    return err(e.pos, format!("@{name} is read-only{why}"));
                }
                self.mark_written(b);
                Ok(Target::Regs(self.bindings[b].loc))
            }
            ExprKind::Member(x, name) => {
                let Target::Regs(l) = self.target(x)? else {
                    return err(e.pos, "cannot assign to a component of an array element");
                };
                let comps = self.components(l.ty, name, e.pos)?;
                if comps.len() != 1 {
                    return err(e.pos, format!("cannot assign to the swizzle '.{name}'"));
                }
                Ok(Target::Regs(Loc {
                    ty: Ty::Float,
                    reg: l.reg + comps[0],
                }))
            }
            ExprKind::Index(x, i) => {
                let Target::Regs(l) = self.target(x)? else {
                    return err(e.pos, "arrays of arrays are not VEX");
                };
                match l.ty {
                    Ty::Array(_) => {
                        let idx = self.expr(i, Some(Ty::Int))?;
                        let idx = self.convert(idx, Ty::Int, i.pos)?;
                        let idx = self.copy(idx);
                        Ok(Target::Elem { arr: l, idx })
                    }
                    t if t.is_vector() || t.is_matrix() => Ok(Target::Regs(self.component(l, i)?)),
                    t => err(e.pos, format!("{} cannot be indexed", t.a())),
                }
            }
            _ => err(e.pos, "this expression cannot be assigned to"),
        }
    }

    /// A variable that is a binding passed to a function by reference:
    /// writing it writes the attribute (or is refused when read-only).
    fn writes_through(&mut self, loc: Loc, pos: Pos) -> LResult<()> {
        let width = |l: Loc| l.ty.floats().max(1) as u32;
        let found = self.bindings.iter().position(|b| {
            super::file_of(b.loc.ty) == super::file_of(loc.ty)
                && loc.reg < b.loc.reg + width(b.loc)
                && b.loc.reg < loc.reg + width(loc)
        });
        let Some(b) = found else { return Ok(()) };
        if !self.bindings[b].writable() {
            let name = &self.bindings[b].name;
            return Err(CompileError::at(
                pos,
                format!("@{name} is read-only (it was passed to a function by reference)"),
            ));
        }
        self.mark_written(b);
        Ok(())
    }

    /// An explicit conversion (`int(x)`, `vector(x)`, `string(x)`).
    fn cast(&mut self, v: Loc, ty: Ty, pos: Pos) -> LResult<Loc> {
        match (v.ty, ty) {
            (a, b) if a == b => Ok(v),
            (t, Ty::Int) if t.is_floaty() => {
                let d = self.alloc(Ty::Int);
                self.emit_op(Op::FToI { d: d.reg, s: v.reg });
                Ok(d)
            }
            (Ty::Int | Ty::Float, Ty::Str) => {
                let fmt = self_fmt(self, v);
                Ok(self.call_site(string_ops::FORMAT, vec![fmt, v], Ty::Str, pos))
            }
            (Ty::Str, Ty::Int) => Ok(self.call_site(string_ops::ATOI, vec![v], Ty::Int, pos)),
            (Ty::Str, Ty::Float) => Ok(self.call_site(string_ops::ATOF, vec![v], Ty::Float, pos)),
            _ => self.convert(v, ty, pos),
        }
    }

    /// VEX's implicit conversions: int to float, a scalar to every component
    /// (a matrix's diagonal), a wider vector to its leading components.
    pub fn convert(&mut self, v: Loc, to: Ty, pos: Pos) -> LResult<Loc> {
        if v.ty == to || to == Ty::Void {
            return Ok(v);
        }
        let bad = || CompileError::at(pos, format!("cannot convert {} to {to}", v.ty));
        // A constant converts now, by the rule the instruction would use.
        match self.constant(v) {
            Some(Val::F(x, 1)) if to == Ty::Int => return Ok(self.iconst(x[0] as i32)),
            Some(Val::I(i)) if to.is_floaty() => {
                let f = self.fconst(i as f32);
                return self.convert(f, to, pos);
            }
            _ => {}
        }
        if to == Ty::Int {
            if v.ty.is_floaty() {
                let d = self.alloc(Ty::Int);
                self.emit_op(Op::FToI { d: d.reg, s: v.reg });
                return Ok(d);
            }
            return Err(bad());
        }
        if !to.is_floaty() {
            return Err(bad());
        }
        let v = if v.ty == Ty::Int {
            let d = self.alloc(Ty::Float);
            self.emit_op(Op::IToF { d: d.reg, s: v.reg });
            d
        } else if v.ty.is_floaty() {
            v
        } else {
            return Err(bad());
        };
        if v.ty == to {
            return Ok(v);
        }
        let out = self.alloc(to);
        let n = to.floats() as u32;
        if v.ty == Ty::Float && to.is_matrix() {
            let side = if to == Ty::Mat3 { 3 } else { 4 };
            let zero = self.fconst(0.0);
            for k in 0..n {
                let s = if k % (side + 1) == 0 { v.reg } else { zero.reg };
                self.emit_op(Op::FMov { d: out.reg + k, s });
            }
            return Ok(out);
        }
        if v.ty.is_matrix() && to.is_matrix() {
            // matrix3 <-> matrix: the upper-left 3x3, identity elsewhere.
            let ident = self.call_site(matrix_ops::IDENT, vec![], to, pos);
            let (src_side, dst_side) = (
                if v.ty == Ty::Mat3 { 3 } else { 4 },
                if to == Ty::Mat3 { 3 } else { 4 },
            );
            for r in 0..3 {
                for c in 0..3 {
                    self.emit_op(Op::FMov {
                        d: ident.reg + r * dst_side + c,
                        s: v.reg + r * src_side + c,
                    });
                }
            }
            return Ok(ident);
        }
        if v.ty.is_matrix() {
            return Err(bad());
        }
        let zero = self.fconst(0.0);
        for k in 0..n {
            let s = if v.ty == Ty::Float {
                v.reg
            } else if k < v.ty.floats() as u32 {
                v.reg + k
            } else {
                zero.reg
            };
            self.emit_op(Op::FMov { d: out.reg + k, s });
        }
        Ok(out)
    }
}

/// The format string `string(x)` uses for a number.
fn self_fmt(me: &mut Lower, v: Loc) -> Loc {
    me.sconst(if v.ty == Ty::Int { "%d" } else { "%g" })
}

/// The common type of the two branches of `?:`.
fn unify(a: Ty, b: Ty) -> Option<Ty> {
    if a == b {
        return Some(a);
    }
    match (a, b) {
        (Ty::Int, t) | (t, Ty::Int) if t.is_floaty() => Some(t),
        (Ty::Float, t) | (t, Ty::Float) if t.is_floaty() => Some(t),
        _ => None,
    }
}
