//! Lowering of function calls: user functions are inlined; library
//! functions resolve against the one table (`crate::library`): the
//! compiler's own (math as instructions) go to `inline`, the rest resolve
//! to a form by their arguments' types and become a call of that form's
//! lane function. By-reference arguments (VEX's outputs) are moved into the
//! call and back, so a function that changes an array does not copy it.

use geode_geo::AttribClass;

use crate::compile::ast::*;
use crate::compile::lex::Pos;
use crate::ir::*;
use crate::library::{self, Callee, Form, Function, Lowering, Ret, T};
use crate::ty::{Elem, Ty};
use crate::{suggest, CompileError};

use super::expr::Target;
use super::{convertible, LResult, Lower};

pub(super) fn err<T>(pos: Pos, msg: impl Into<String>) -> LResult<T> {
    Err(CompileError::at(pos, msg))
}

/// What a form's generic types stand for in one call.
#[derive(Clone, Copy, Debug, Default)]
struct Bound {
    /// The type of the `Num` arguments.
    num: Option<Ty>,
    /// The array (or string) the `Array`/`Seq` argument is.
    seq: Option<Ty>,
}

impl Bound {
    fn elem(&self) -> Option<Ty> {
        match self.seq {
            Some(Ty::Array(e)) => Some(e.ty()),
            Some(Ty::Str) => Some(Ty::Str),
            _ => None,
        }
    }

    /// The concrete type a form's argument type means here.
    fn concrete(&self, t: T, given: Ty) -> Ty {
        match t {
            T::Is(t) => t,
            T::Num => self.num.unwrap_or(Ty::Float),
            T::Elem => self.elem().unwrap_or(given),
            T::Vector | T::Array | T::Seq | T::Any => given,
        }
    }
}

/// The widest of the types given to a form's `Num` arguments, if they
/// agree (floats and ints widen to any of them).
fn bind_num(form: &Form, vals: &[Loc]) -> Option<Option<Ty>> {
    let mut num: Option<Ty> = None;
    for (k, v) in vals.iter().enumerate() {
        if form.arg(k).map(|a| a.ty) != Some(T::Num) {
            continue;
        }
        if !v.ty.is_numeric() {
            return None;
        }
        let t = if v.ty == Ty::Int { Ty::Float } else { v.ty };
        num = match num {
            None => Some(t),
            Some(Ty::Float) => Some(t),
            Some(n) if t == Ty::Float || t == n => Some(n),
            Some(_) => return None,
        };
    }
    Some(num)
}

/// How well `got` fits a form's argument (higher is closer), if at all.
fn fit(t: T, out: bool, got: Ty, bound: &Bound) -> Option<u32> {
    let exact = |want: Ty| -> Option<u32> {
        if got == want {
            Some(3)
        } else if !out && convertible(got, want) {
            Some(1)
        } else {
            None
        }
    };
    match t {
        T::Is(want) => exact(want),
        T::Num => {
            let want = bound.num.unwrap_or(Ty::Float);
            if got == want {
                Some(3)
            } else if !out && (got == Ty::Float || got == Ty::Int) {
                Some(2)
            } else {
                None
            }
        }
        T::Vector => got.is_vector().then_some(3),
        T::Array => matches!(got, Ty::Array(_)).then_some(3),
        T::Seq => matches!(got, Ty::Array(_) | Ty::Str).then_some(3),
        T::Elem => exact(bound.elem()?),
        T::Any => (got != Ty::Void).then_some(2),
    }
}

/// The form's score for these argument types and what its generics bind.
fn match_form(form: &Form, vals: &[Loc]) -> Option<(u32, Bound)> {
    let mut bound = Bound {
        num: bind_num(form, vals)?,
        seq: None,
    };
    bound.seq = vals.iter().enumerate().find_map(|(k, v)| {
        let t = form.arg(k)?.ty;
        matches!(t, T::Array | T::Seq).then_some(v.ty)
    });
    let mut score = 0;
    for (k, v) in vals.iter().enumerate() {
        let arg = form.arg(k)?;
        score += fit(arg.ty, arg.out, v.ty, &bound)?;
    }
    Some((score, bound))
}

/// A call's arguments as values, the targets of those a form may write,
/// and the binding each such target is of.
type LaneArgs = (Vec<Loc>, Vec<Option<Target>>, Vec<Option<usize>>);

/// The form that fits the arguments best (a form writing an argument
/// needs a target there); a tie goes to the form whose result `suits` the
/// context, else to the first.
fn pick_form<'f>(
    forms: &[&'f Form],
    vals: &[Loc],
    targets: &[Option<Target>],
    suits: impl Fn(&Form, &Bound) -> bool,
) -> Option<(&'f Form, Bound)> {
    let mut best: Option<(u32, bool, &Form, Bound)> = None;
    for fm in forms {
        let writable =
            (0..vals.len()).all(|k| !fm.arg(k).is_some_and(|a| a.out) || targets[k].is_some());
        let Some((score, bound)) = match_form(fm, vals).filter(|_| writable) else {
            continue;
        };
        let suits = suits(fm, &bound);
        let better = match best {
            None => true,
            Some((s, b, ..)) => score > s || (score == s && suits && !b),
        };
        if better {
            best = Some((score, suits, fm, bound));
        }
    }
    best.map(|(_, _, fm, bound)| (fm, bound))
}

/// Whether an expression has the shape of an assignment target.
fn assignable(e: &Expr) -> bool {
    matches!(
        e.kind,
        ExprKind::Var(_) | ExprKind::Binding { .. } | ExprKind::Member(..) | ExprKind::Index(..)
    )
}

impl<'a> Lower<'a> {
    pub(super) fn eval_args(&mut self, args: &[Expr]) -> LResult<Vec<Loc>> {
        args.iter().map(|a| self.expr(a, None)).collect()
    }

    pub(super) fn arity(
        &self,
        name: &str,
        args: &[Expr],
        lo: usize,
        hi: usize,
        pos: Pos,
    ) -> LResult<()> {
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

    pub(super) fn no_form(&self, name: &str, vals: &[Loc], pos: Pos) -> CompileError {
        let got: Vec<String> = vals.iter().map(|v| v.ty.to_string()).collect();
        CompileError::at(
            pos,
            format!("no form of '{name}' takes ({})", got.join(", ")),
        )
    }

    /// Converts an int to float; float-based values pass.
    pub(super) fn floaty(&mut self, v: Loc, name: &str, pos: Pos) -> LResult<Loc> {
        match v.ty {
            Ty::Int => self.convert(v, Ty::Float, pos),
            t if t.is_floaty() => Ok(v),
            _ => Err(self.no_form(name, &[v], pos)),
        }
    }

    pub(super) fn arg(&mut self, e: &Expr, ty: Ty, name: &str) -> LResult<Loc> {
        let v = self.expr(e, Some(ty))?;
        if !convertible(v.ty, ty) {
            return err(
                e.pos,
                format!("'{name}' expects {} here, not {}", ty.a(), v.ty.a()),
            );
        }
        self.convert(v, ty, e.pos)
    }

    pub(super) fn dot(&mut self, a: Loc, b: Loc) -> Loc {
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

    pub(super) fn clamp(&mut self, x: Loc, lo: Loc, hi: Loc) -> Loc {
        let t = self.fzip(FBinOp::Min, x, hi);
        self.fzip(FBinOp::Max, t, lo)
    }

    /// `nmin + (nmax - nmin) * t`.
    pub(super) fn mix(&mut self, a: Loc, b: Loc, t: Loc) -> Loc {
        let d = self.fzip(FBinOp::Sub, b, a);
        let s = self.fzip(FBinOp::Mul, d, t);
        self.fzip(FBinOp::Add, a, s)
    }

    /// The attribute type `name` has in input `geo` when both are constants.
    pub(super) fn attrib_type(&self, geo: &Expr, name: &Expr, class: AttribClass) -> Option<Ty> {
        let (ExprKind::Int(i), ExprKind::Str(n)) = (&geo.kind, &name.kind) else {
            return None;
        };
        let g = self.spec.inputs.get(*i as usize).copied().flatten()?;
        if class == AttribClass::Point && n == "P" {
            return Some(Ty::Vec3);
        }
        crate::ty::ty_of(g.attrib(class, n)?.data())
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
        let Some(f) = library::find(name) else {
            return Err(self.unknown_function(name, pos));
        };
        match f.lowering {
            Lowering::Compiler => self.inline_call(name, args, hint, pos),
            Lowering::Lane => self.lane_call(f, args, hint, pos),
        }
    }

    /// A call of a lane function: the form its arguments' types pick, the
    /// arguments converted to it, outputs written back.
    fn lane_call(
        &mut self,
        f: &'static Function,
        args: &[Expr],
        hint: Option<Ty>,
        pos: Pos,
    ) -> LResult<Loc> {
        let forms: Vec<&Form> = f.forms.iter().filter(|fm| fm.takes(args.len())).collect();
        if forms.is_empty() {
            return err(
                pos,
                self.forms_message(f, &format!("takes no {} arguments", args.len())),
            );
        }
        let (vals, targets, roots) = self.lane_args(f, &forms, args)?;
        let Some((form, bound)) = pick_form(&forms, &vals, &targets, |fm, bound| {
            hint.is_some_and(|h| self.ret_of(fm.ret, bound, Some(h), args) == h)
        }) else {
            return Err(self.unmatched(f, &forms, &vals, args, pos));
        };
        // What the form writes is written; an argument other forms would
        // have written is only read.
        for (k, root) in roots.iter().enumerate() {
            if let Some(b) = root.filter(|_| form.arg(k).is_some_and(|a| a.out)) {
                self.mark_written(b);
            }
        }
        let mut converted = Vec::with_capacity(vals.len());
        let mut outs = Vec::with_capacity(vals.len());
        for (k, v) in vals.iter().enumerate() {
            let arg = form.arg(k).expect("the form takes the argument");
            let want = bound.concrete(arg.ty, v.ty);
            converted.push(if arg.out {
                *v
            } else {
                self.convert_arg(*v, want, f.name, args[k].pos)?
            });
            outs.push(arg.out);
        }
        let out = self.ret_of(form.ret, &bound, hint, args);
        let callee = Callee {
            name: f.name,
            lane: form.lane.expect("a lane function's form has its lane"),
            bytes: form.bytes,
        };
        let result = self.call_site_outs(callee, converted.clone(), outs, out, pos);
        if let Some(num) = form.num {
            self.runs_on_numbers(num);
        }
        if let Some(edit) = form.edit {
            self.runs_on_edits(edit);
        }
        // Registers of a variable, binding or component were written in
        // place; an array element is stored back.
        for (k, (t, v)) in targets.into_iter().zip(converted).enumerate() {
            let written = form.arg(k).is_some_and(|a| a.out);
            if let (true, Some(t @ Target::Elem { .. })) = (written, t) {
                self.write_target(t, v, pos)?;
            }
        }
        Ok(result)
    }

    /// A call's arguments: values, with the targets of those a form may
    /// write. Where every form writes an argument it must be a target;
    /// where only some do (`xyzdist(geo, pos, &prim...)` beside
    /// `xyzdist(geo, group, pos...)`) an assignable one is taken as a
    /// target, its binding (`roots`) marked written only if the form
    /// picked writes it.
    fn lane_args(&mut self, f: &Function, forms: &[&Form], args: &[Expr]) -> LResult<LaneArgs> {
        let mut vals = Vec::with_capacity(args.len());
        let mut targets: Vec<Option<Target>> = Vec::with_capacity(args.len());
        let mut roots = vec![None; args.len()];
        for (k, e) in args.iter().enumerate() {
            let writes = |fm: &&Form| fm.arg(k).is_some_and(|a| a.out);
            if forms.iter().all(writes) {
                let t = self.target(e).map_err(|_| {
                    CompileError::at(
                        e.pos,
                        format!(
                            "'{}' writes argument {}: it needs a variable, attribute, component or array element there",
                            f.name,
                            k + 1
                        ),
                    )
                })?;
                vals.push(self.read_target(t, e.pos)?);
                targets.push(Some(t));
                continue;
            }
            if forms.iter().any(writes) && assignable(e) {
                let before = self.written.clone();
                if let Ok(t) = self.target(e) {
                    // Marked once the form is known (see `lane_call`).
                    let root = self.root_binding(e);
                    if let Some(b) = root {
                        self.written[b] = before[b];
                    }
                    roots[k] = root;
                    vals.push(self.read_target(t, e.pos)?);
                    targets.push(Some(t));
                    continue;
                }
                self.written = before;
            }
            // A value, hinted with the type every form agrees on there.
            let agreed = forms
                .iter()
                .map(|fm| match fm.arg(k).map(|a| a.ty) {
                    Some(T::Is(t)) => Some(t),
                    _ => None,
                })
                .reduce(|a, b| if a == b { a } else { None })
                .flatten();
            vals.push(self.expr(e, agreed)?);
            targets.push(None);
        }
        Ok((vals, targets, roots))
    }

    /// The binding an assignable expression writes (`@a`, `@a.x`, `@a[i]`).
    fn root_binding(&self, e: &Expr) -> Option<usize> {
        match &e.kind {
            ExprKind::Binding { name, .. } => self.bindings.iter().position(|b| b.name == *name),
            ExprKind::Member(x, _) | ExprKind::Index(x, _) => self.root_binding(x),
            _ => None,
        }
    }

    /// Why no form takes these arguments: the argument that does not fit
    /// the one form there is, else every form.
    fn unmatched(
        &self,
        f: &Function,
        forms: &[&Form],
        vals: &[Loc],
        args: &[Expr],
        pos: Pos,
    ) -> CompileError {
        if let [only] = forms[..] {
            let bound = Bound {
                num: bind_num(only, vals).flatten(),
                seq: None,
            };
            for (k, v) in vals.iter().enumerate() {
                let arg = only.arg(k).expect("the form takes the argument");
                if fit(arg.ty, arg.out, v.ty, &bound).is_none() {
                    let want = match arg.ty {
                        T::Is(t) => t.a(),
                        other => other.spelling(),
                    };
                    return CompileError::at(
                        args[k].pos,
                        format!("'{}' expects {want} here, not {}", f.name, v.ty.a()),
                    );
                }
            }
        }
        let got: Vec<String> = vals.iter().map(|v| v.ty.to_string()).collect();
        CompileError::at(
            pos,
            self.forms_message(f, &format!("takes no ({})", got.join(", "))),
        )
    }

    /// `'name' <problem>; its forms: ...`.
    fn forms_message(&self, f: &Function, problem: &str) -> String {
        let forms: Vec<String> = f.forms.iter().map(|fm| fm.display(f.name)).collect();
        format!("'{}' {problem}; its forms: {}", f.name, forms.join("; "))
    }

    /// The type a form gives in this call.
    fn ret_of(&self, ret: Ret, bound: &Bound, hint: Option<Ty>, args: &[Expr]) -> Ty {
        let hint = hint.filter(|t| *t != Ty::Void);
        match ret {
            Ret::Is(t) => t,
            Ret::Num => bound.num.unwrap_or(Ty::Float),
            Ret::Same => bound.seq.unwrap_or(Ty::Array(Elem::Float)),
            Ret::Elem => bound.elem().unwrap_or(Ty::Float),
            Ret::Context(ts) => hint.filter(|h| ts.contains(h)).unwrap_or(ts[0]),
            Ret::Attrib(class) => hint
                .or_else(|| {
                    let (geo, name) = (args.first()?, args.get(1)?);
                    let classes: &[AttribClass] = if class == AttribClass::Point {
                        // primuv reads point, vertex or primitive values.
                        &[
                            AttribClass::Point,
                            AttribClass::Vertex,
                            AttribClass::Primitive,
                            AttribClass::Detail,
                        ]
                    } else {
                        std::slice::from_ref(&class)
                    };
                    classes.iter().find_map(|c| self.attrib_type(geo, name, *c))
                })
                .unwrap_or(Ty::Float),
            Ret::Intrinsic => args
                .get(1)
                .and_then(|n| match &n.kind {
                    ExprKind::Str(s) => library::intrinsic_type(s),
                    _ => None,
                })
                .or(hint)
                .unwrap_or(Ty::Float),
        }
    }

    /// "unknown function", with the closest library or snippet function.
    pub(super) fn unknown_function(&self, name: &str, pos: Pos) -> CompileError {
        let mut known: Vec<&str> = library::names().collect();
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
