//! Type checking and lowering of a parsed snippet to the batch IR: values
//! get registers, vector math becomes per-component instructions, control
//! flow becomes masks, and user functions are inlined (VEX forbids
//! recursion and passes arguments by reference).

use std::collections::HashMap;

use super::ast::*;
use super::bind::BindSpec;
use super::lex::Pos;
use crate::error::CompileError;
use crate::ir::*;
use crate::library::{array_ops, Callee};
use crate::program::{ArgMode, Binding, CallSite, Counts};
use crate::ty::{Elem, Ty};
use crate::value::Val;

mod access;
mod calls;
mod expr;
mod flow;
mod inline;
mod pool;
mod update;

use flow::{FuncCtl, LoopCtl};

/// Register counters, saved and restored around statements so temporaries
/// are reused.
#[derive(Clone, Copy, Default)]
pub(crate) struct Alloc {
    pub c: Counts,
}

pub(crate) struct Lower<'a> {
    pub ops: Vec<Op>,
    /// The statement each instruction belongs to, for errors at run time.
    op_pos: Vec<Pos>,
    /// The statement being lowered.
    at: Pos,
    pub calls: Vec<CallSite>,
    pub strings: Vec<String>,
    pub alloc: Alloc,
    pub high: Counts,
    /// Variables by name, innermost scope last (maps: a snippet of many
    /// declarations compiles in linear time).
    scopes: Vec<HashMap<String, Loc>>,
    /// Masks in effect, innermost last (block, loop, function masks).
    masks: Vec<Reg>,
    loops: Vec<LoopCtl>,
    /// The inlined functions being lowered, innermost last.
    funcs: Vec<FuncCtl>,
    inlining: Vec<String>,
    functions: HashMap<String, Vec<&'a Function>>,
    pub bindings: &'a [Binding],
    pub spec: &'a BindSpec<'a>,
    /// Registers holding a literal (set by the constant helpers, dropped
    /// when the register is allocated again): calls read them once.
    consts: HashMap<(FileKey, Reg), (Loc, Val)>,
    /// Which bindings the snippet assigns.
    pub written: Vec<bool>,
    /// The ramp parameters `chramp` reads, by index.
    pub ramps: Vec<geode_geo::Ramp>,
    /// A register holding 1 in every lane (masks start from it).
    ones: Reg,
    /// The program runs one lane (over the detail): control flow is jumps,
    /// not masks (see `flow`).
    uniform: bool,
    /// Numeric constants, each in a register of its own set once per frame.
    pool: pool::Pool,
}

pub(crate) type LResult<T> = Result<T, CompileError>;

/// How deep snippet functions may call one another (each call is inlined).
pub const MAX_INLINE: usize = 64;

fn err<T>(pos: Pos, msg: impl Into<String>) -> LResult<T> {
    Err(CompileError::at(pos, msg))
}

impl<'a> Lower<'a> {
    pub fn new(
        snippet: &'a Snippet,
        bindings: &'a [Binding],
        spec: &'a BindSpec<'a>,
        base: Counts,
    ) -> Lower<'a> {
        let mut functions: HashMap<String, Vec<&Function>> = HashMap::new();
        for f in &snippet.functions {
            functions.entry(f.name.clone()).or_default().push(f);
        }
        let mut pool = pool::Pool::default();
        let ones = pool.int(1);
        Lower {
            ops: Vec::new(),
            op_pos: Vec::new(),
            at: Pos::default(),
            calls: Vec::new(),
            strings: Vec::new(),
            alloc: Alloc { c: base },
            high: base,
            scopes: vec![HashMap::new()],
            masks: Vec::new(),
            loops: Vec::new(),
            funcs: Vec::new(),
            inlining: Vec::new(),
            functions,
            bindings,
            spec,
            ones,
            uniform: spec.run_over == geode_geo::AttribClass::Detail,
            pool,
            written: vec![false; bindings.len()],
            consts: HashMap::new(),
            ramps: Vec::new(),
        }
    }

    // ---- registers -------------------------------------------------------

    pub fn alloc(&mut self, ty: Ty) -> Loc {
        let c = &mut self.alloc.c;
        let reg = match ty {
            Ty::Int => bump(&mut c.i, 1),
            Ty::Str => bump(&mut c.s, 1),
            Ty::Void => 0,
            Ty::Array(Elem::Int) => bump(&mut c.ai, 1),
            Ty::Array(Elem::Str) => bump(&mut c.as_, 1),
            Ty::Array(_) => bump(&mut c.af, 1),
            t => bump(&mut c.f, t.floats() as u32),
        };
        self.high = self.high.max(&self.alloc.c);
        let loc = Loc { ty, reg };
        // A reused register no longer holds the constant it held.
        if !self.consts.is_empty() {
            let file = file_of(ty);
            for r in reg..reg + ty.floats().max(1) as u32 {
                self.consts.remove(&(file, r));
            }
        }
        loc
    }

    pub fn emit_op(&mut self, op: Op) -> usize {
        self.emit(op)
    }

    pub fn masks_mut(&mut self) -> &mut Vec<Reg> {
        &mut self.masks
    }

    pub fn mark_written(&mut self, binding: usize) {
        self.written[binding] = true;
    }

    fn emit(&mut self, op: Op) -> usize {
        self.ops.push(op);
        self.op_pos.push(self.at);
        self.ops.len() - 1
    }

    fn here(&self) -> u32 {
        self.ops.len() as u32
    }

    fn patch(&mut self, at: usize, to: u32) {
        let target = self.ops[at].target_mut();
        *target.expect("only jumps are patched") = to;
    }

    /// The value `v` holds when it is a constant.
    pub fn constant(&self, v: Loc) -> Option<Val> {
        self.consts
            .get(&(file_of(v.ty), v.reg))
            .filter(|(l, _)| *l == v)
            .map(|(_, c)| c.clone())
    }

    /// A float constant: its pool register (no instruction).
    pub fn fconst(&mut self, v: f32) -> Loc {
        let d = Loc {
            ty: Ty::Float,
            reg: self.pool.float(v),
        };
        self.consts
            .insert((file_of(d.ty), d.reg), (d, Val::float(v)));
        d
    }

    /// An int constant: its pool register (no instruction).
    pub fn iconst(&mut self, v: i32) -> Loc {
        let d = Loc {
            ty: Ty::Int,
            reg: self.pool.int(v),
        };
        self.consts.insert((file_of(d.ty), d.reg), (d, Val::I(v)));
        d
    }

    pub fn sconst(&mut self, s: &str) -> Loc {
        let idx = match self.strings.iter().position(|x| x == s) {
            Some(i) => i,
            None => {
                self.strings.push(s.to_string());
                self.strings.len() - 1
            }
        };
        let d = self.alloc(Ty::Str);
        self.emit(Op::SConst {
            d: d.reg,
            s: idx as u32,
        });
        self.consts
            .insert((file_of(d.ty), d.reg), (d, Val::S(s.to_string())));
        d
    }

    /// The current mask register, if any lanes are masked off.
    pub fn mask(&self) -> Option<Reg> {
        self.masks.last().copied()
    }

    /// A copy of the current mask (all ones when unmasked) in a new register.
    fn mask_copy(&mut self) -> Reg {
        let d = self.alloc(Ty::Int).reg;
        match self.mask() {
            Some(m) => self.emit(Op::IMov { d, s: m }),
            None => self.emit(Op::IMov { d, s: self.ones }),
        };
        d
    }

    pub fn ibin(&mut self, op: IBinOp, a: Reg, b: Reg) -> Reg {
        let d = self.alloc(Ty::Int).reg;
        self.emit(Op::IBin { op, d, a, b });
        d
    }

    /// `reg = reg op other`, through a temporary (no aliasing).
    fn update_int(&mut self, reg: Reg, op: IBinOp, other: Reg) {
        let t = self.ibin(op, reg, other);
        self.emit(Op::IMov { d: reg, s: t });
    }

    // ---- storing ---------------------------------------------------------

    /// Copies `src` into `dst` (same type) on the lanes of the current mask.
    pub fn store(&mut self, dst: Loc, src: Loc) {
        if dst == src || dst.ty == Ty::Void {
            return;
        }
        let m = self.mask();
        if dst.ty.is_floaty() {
            for k in 0..dst.ty.floats() as u32 {
                self.emit(copy_op(Ty::Float, dst.reg + k, src.reg + k, m));
            }
        } else {
            self.emit(copy_op(dst.ty, dst.reg, src.reg, m));
        }
    }

    /// An unmasked copy into a fresh register.
    pub fn copy(&mut self, src: Loc) -> Loc {
        let d = self.alloc(src.ty);
        let saved = std::mem::take(&mut self.masks);
        self.store(d, src);
        self.masks = saved;
        d
    }

    // ---- statements ------------------------------------------------------

    pub fn body(&mut self, stmts: &[Stmt]) -> LResult<()> {
        for s in stmts {
            self.stmt(s)?;
        }
        Ok(())
    }

    fn scoped(&mut self, f: impl FnOnce(&mut Self) -> LResult<()>) -> LResult<()> {
        let mark = self.alloc;
        self.scopes.push(HashMap::new());
        let r = f(self);
        self.scopes.pop();
        self.alloc = mark;
        r
    }

    pub fn declare(&mut self, name: &str, loc: Loc, pos: Pos) -> LResult<()> {
        let scope = self.scopes.last_mut().expect("a scope");
        if scope.contains_key(name) {
            return err(pos, format!("redeclaration of '{name}'"));
        }
        scope.insert(name.to_string(), loc);
        Ok(())
    }

    pub fn lookup(&self, name: &str) -> Option<Loc> {
        self.scopes.iter().rev().find_map(|s| s.get(name).copied())
    }

    fn visible_names(&self) -> Vec<String> {
        self.scopes.iter().flat_map(|s| s.keys().cloned()).collect()
    }

    fn stmt(&mut self, s: &Stmt) -> LResult<()> {
        match s {
            Stmt::Expr(e) => self.at = e.pos,
            Stmt::Decls(d) => self.at = d.first().map_or(self.at, |d| d.pos),
            _ => {}
        }
        match s {
            Stmt::Empty => Ok(()),
            Stmt::Expr(e) => self.discarded(e),
            Stmt::Decls(ds) => {
                for d in ds {
                    let loc = self.alloc(d.ty);
                    let mark = self.alloc;
                    if let Some(init) = &d.init {
                        let v = self.expr(init, Some(d.ty))?;
                        let v = self.convert(v, d.ty, init.pos)?;
                        self.store_unmasked_if_fresh(loc, v);
                    } else {
                        self.zero(loc);
                    }
                    self.alloc = mark;
                    self.declare(&d.name, loc, d.pos)?;
                }
                Ok(())
            }
            Stmt::Block(b) => self.scoped(|me| me.body(b)),
            Stmt::If(c, then, other) => self.if_stmt(c, then, other.as_deref()),
            Stmt::While(c, body) => self.scoped(|me| me.loop_stmt(Some(c), None, body, false)),
            Stmt::DoWhile(body, c) => self.scoped(|me| me.loop_stmt(Some(c), None, body, true)),
            Stmt::For(init, c, step, body) => self.scoped(|me| {
                if let Some(i) = init {
                    me.stmt(i)?;
                }
                me.loop_stmt(c.as_ref(), step.as_ref(), body, false)
            }),
            Stmt::Foreach {
                index,
                elem,
                array,
                body,
            } => self.scoped(|me| me.foreach(index.as_deref(), elem, array, body)),
            Stmt::Break(pos) => self.break_or_continue(true, *pos),
            Stmt::Continue(pos) => self.break_or_continue(false, *pos),
            Stmt::Return(v, pos) => self.return_stmt(v.as_ref(), *pos),
        }
    }

    /// Declarations initialise every lane (the variable is new), so the
    /// store ignores the mask.
    fn store_unmasked_if_fresh(&mut self, dst: Loc, src: Loc) {
        let saved = std::mem::take(&mut self.masks);
        self.store(dst, src);
        self.masks = saved;
    }

    fn zero(&mut self, loc: Loc) {
        match loc.ty {
            Ty::Int => {
                self.emit(Op::IConst { d: loc.reg, v: 0 });
            }
            Ty::Str => {
                let e = self.sconst("");
                self.store_unmasked_if_fresh(loc, e);
            }
            Ty::Array(_) | Ty::Void => {
                // Array registers of a frame start empty and a declaration
                // inside a loop must reset them: copy from a fresh one.
                if let Ty::Array(e) = loc.ty {
                    let fresh = self.alloc(loc.ty);
                    self.emit(Op::Call {
                        call: self.calls.len() as u32,
                    });
                    self.calls.push(CallSite {
                        name: array_ops::ARRAY_OF.name,
                        lane: array_ops::ARRAY_OF.lane,
                        bytes: None,
                        args: vec![],
                        consts: vec![],
                        modes: vec![],
                        out: fresh,
                        mask: None,
                        counted: false,
                        num: None,
                        edit: None,
                        pos: Pos::default(),
                    });
                    self.emit(Op::AMov {
                        file: arr_file(e),
                        d: loc.reg,
                        s: fresh.reg,
                    });
                }
            }
            t => {
                for k in 0..t.floats() as u32 {
                    self.emit(Op::FConst {
                        d: loc.reg + k,
                        v: 0.0,
                    });
                }
            }
        }
    }

    // ---- user functions --------------------------------------------------

    /// Inlines user function `name` if one takes these arguments.
    pub fn user_call(&mut self, name: &str, args: &[Expr], pos: Pos) -> LResult<Option<Loc>> {
        let Some(cands) = self.functions.get(name).cloned() else {
            return Ok(None);
        };
        let mut vals = Vec::new();
        for a in args {
            vals.push(self.expr(a, None)?);
        }
        let chosen = cands
            .iter()
            .filter(|f| f.params.len() == args.len())
            .min_by_key(|f| {
                f.params
                    .iter()
                    .zip(&vals)
                    .map(|(p, v)| {
                        if p.ty == v.ty {
                            0
                        } else if convertible(v.ty, p.ty) {
                            1
                        } else {
                            100
                        }
                    })
                    .sum::<u32>()
            })
            .copied();
        let Some(f) = chosen.filter(|f| {
            f.params
                .iter()
                .zip(&vals)
                .all(|(p, v)| p.ty == v.ty || convertible(v.ty, p.ty))
        }) else {
            let got: Vec<String> = vals.iter().map(|v| v.ty.to_string()).collect();
            return err(
                pos,
                format!("no form of '{name}' takes ({})", got.join(", ")),
            );
        };
        if self.inlining.iter().any(|n| n == name) {
            return err(
                pos,
                format!("'{name}' calls itself: VEX functions cannot recurse"),
            );
        }
        // Calls are inlined: a chain of functions each calling the next is
        // as deep as the chain.
        if self.inlining.len() >= MAX_INLINE {
            return err(
                pos,
                format!("functions call each other more than {MAX_INLINE} deep ('{name}')"),
            );
        }
        // Arguments pass by reference: an argument of the parameter's type is
        // the parameter itself, so writes reach the caller.
        let mut params = Vec::new();
        for ((p, v), a) in f.params.iter().zip(&vals).zip(args) {
            let loc = self.convert(*v, p.ty, a.pos)?;
            // A constant's register is shared: the parameter gets a copy.
            let loc = if pool::holds(loc.reg) {
                self.copy(loc)
            } else {
                loc
            };
            params.push((p.name.clone(), loc));
        }
        let slot = (f.ret != Ty::Void).then(|| self.alloc(f.ret));
        if let Some(s) = slot {
            self.zero(s);
        }
        self.inlining.push(name.to_string());
        let void = Loc {
            ty: Ty::Void,
            reg: 0,
        };
        self.enter_function(&f.body, slot.or(Some(void)));
        let saved_scopes = std::mem::replace(&mut self.scopes, vec![params.into_iter().collect()]);
        let saved_loops = std::mem::take(&mut self.loops);
        let r = self.scoped(|me| me.body(&f.body));
        self.scopes = saved_scopes;
        self.loops = saved_loops;
        self.leave_function();
        self.inlining.pop();
        r?;
        Ok(Some(slot.unwrap_or(void)))
    }

    pub fn function_names(&self) -> Vec<String> {
        self.functions.keys().cloned().collect()
    }

    pub fn undeclared(&self, name: &str, pos: Pos) -> CompileError {
        let names = self.visible_names();
        CompileError::at(
            pos,
            format!(
                "undeclared variable '{name}'{}",
                crate::suggest(name, names.iter().map(String::as_str))
            ),
        )
    }

    /// Emits a library call over the current mask into a new register.
    /// A call of `callee` with its result in a new register of type `out`.
    pub fn call_site(&mut self, callee: Callee, args: Vec<Loc>, out: Ty, pos: Pos) -> Loc {
        let outs = vec![false; args.len()];
        self.call_site_outs(callee, args, outs, out, pos)
    }

    /// A call whose arguments marked in `outs` the function may change in
    /// place (their registers are moved into the call and back).
    pub fn call_site_outs(
        &mut self,
        callee: Callee,
        args: Vec<Loc>,
        outs: Vec<bool>,
        out: Ty,
        pos: Pos,
    ) -> Loc {
        // A constant's register is shared: an output gets a copy.
        let args: Vec<Loc> = args
            .into_iter()
            .zip(&outs)
            .map(|(a, o)| {
                if *o && pool::holds(a.reg) {
                    self.copy(a)
                } else {
                    a
                }
            })
            .collect();
        let consts: Vec<Option<Val>> = args
            .iter()
            .zip(&outs)
            .map(|(a, o)| {
                if *o {
                    return None;
                }
                self.consts
                    .get(&(file_of(a.ty), a.reg))
                    .filter(|(l, _)| l == a)
                    .map(|(_, v)| v.clone())
            })
            .collect();
        // A literal is never copied per lane: only other strings and
        // arrays are charged to the memory budget.
        let heap = |t: Ty| matches!(t, Ty::Str | Ty::Array(_));
        let counted = heap(out)
            || args
                .iter()
                .zip(&consts)
                .any(|(a, c)| heap(a.ty) && c.is_none())
            || callee.bytes.is_some();
        let out = self.alloc(out);
        let call = self.calls.len() as u32;
        let modes = ArgMode::of(&args, &consts, &outs);
        self.calls.push(CallSite {
            modes,
            name: callee.name,
            lane: callee.lane,
            bytes: callee.bytes,
            args,
            consts,
            out,
            mask: self.mask(),
            counted,
            num: None,
            edit: None,
            pos,
        });
        self.emit(Op::Call { call });
        out
    }

    /// The last call site runs `num` when its arguments and result are all
    /// numbers and it writes no argument.
    pub fn runs_on_numbers(&mut self, num: crate::program::NumFn) {
        let Some(site) = self.calls.last_mut() else {
            return;
        };
        let number = |t: Ty| t == Ty::Int || t.is_floaty();
        let plain = site.modes.iter().all(|m| *m != ArgMode::Move);
        let floats: usize = site.args.iter().map(|a| a.ty.floats().max(1)).sum();
        if plain
            && floats <= crate::program::NUM_ARGS
            && site.out.ty.is_floaty()
            && site.args.iter().all(|a| number(a.ty))
        {
            site.num = Some(num);
        }
    }

    /// The last call site runs `edit` when its arguments are numbers and
    /// string literals, its result an int, and it writes no argument.
    pub fn runs_on_edits(&mut self, edit: crate::program::EditFn) {
        let Some(site) = self.calls.last_mut() else {
            return;
        };
        let plain = site.modes.iter().all(|m| *m != ArgMode::Move);
        let (mut ints, mut floats, mut texts) = (0, 0, 0);
        for (a, c) in site.args.iter().zip(&site.consts) {
            match a.ty {
                Ty::Int => ints += 1,
                Ty::Str if c.is_some() => texts += 1,
                t if t.is_floaty() => floats += t.floats(),
                _ => return,
            }
        }
        let most = crate::program::EDIT_ARGS;
        if plain && site.out.ty == Ty::Int && ints <= most && floats <= most && texts <= 1 {
            site.edit = Some(edit);
        }
    }

    /// The instructions, each one's statement position, the call sites,
    /// the string constants and the register counts.
    pub fn finish(mut self) -> Lowered {
        let constants = self
            .pool
            .renumber(&mut self.ops, &mut self.calls, &mut self.high);
        Lowered {
            ops: self.ops,
            op_pos: self.op_pos,
            calls: self.calls,
            strings: self.strings,
            counts: self.high,
            constants,
            uniform: self.uniform,
        }
    }
}

/// What lowering made of a snippet, for the program.
pub(crate) struct Lowered {
    pub ops: Vec<Op>,
    pub op_pos: Vec<Pos>,
    pub calls: Vec<CallSite>,
    pub strings: Vec<String>,
    pub counts: Counts,
    pub constants: crate::program::Constants,
    pub uniform: bool,
}

/// The instruction copying register `s` to `d` for a value of `ty` (one
/// register of its file), on the lanes of mask `m` or all of them.
fn copy_op(ty: Ty, d: Reg, s: Reg, m: Option<Reg>) -> Op {
    match (ty, m) {
        (Ty::Int, Some(m)) => Op::ISel { d, s, m },
        (Ty::Int, None) => Op::IMov { d, s },
        (Ty::Str, Some(m)) => Op::SSel { d, s, m },
        (Ty::Str, None) => Op::SMov { d, s },
        (Ty::Array(e), Some(m)) => Op::ASel {
            file: arr_file(e),
            d,
            s,
            m,
        },
        (Ty::Array(e), None) => Op::AMov {
            file: arr_file(e),
            d,
            s,
        },
        (_, Some(m)) => Op::FSel { d, s, m },
        (_, None) => Op::FMov { d, s },
    }
}

/// Which register file a type lives in (registers are numbered per file).
pub(super) type FileKey = u8;

pub(super) fn file_of(ty: Ty) -> FileKey {
    match ty {
        Ty::Int => 0,
        Ty::Str => 1,
        Ty::Array(Elem::Int) => 2,
        Ty::Array(Elem::Str) => 3,
        Ty::Array(_) => 4,
        Ty::Void => 5,
        _ => 6,
    }
}

fn bump(c: &mut u32, n: u32) -> Reg {
    let r = *c;
    *c += n;
    r
}

pub fn arr_file(e: Elem) -> ArrFile {
    match e {
        Elem::Int => ArrFile::I,
        Elem::Str => ArrFile::S,
        _ => ArrFile::F,
    }
}

/// Whether VEX converts `from` to `to` implicitly.
pub fn convertible(from: Ty, to: Ty) -> bool {
    from == to
        || (from.is_numeric()
            && to.is_numeric()
            && !(from.is_matrix() && !to.is_matrix() && to != Ty::Float))
}

impl Counts {
    fn max(&self, o: &Counts) -> Counts {
        Counts {
            f: self.f.max(o.f),
            i: self.i.max(o.i),
            s: self.s.max(o.s),
            af: self.af.max(o.af),
            ai: self.ai.max(o.ai),
            as_: self.as_.max(o.as_),
        }
    }
}

/// The type of `e` in an empty snippet (a parameter expression's).
pub fn type_of(e: &Expr, spec: &BindSpec) -> LResult<Ty> {
    let snippet = Snippet::default();
    let mut lower = Lower::new(&snippet, &[], spec, Counts::default());
    Ok(lower.expr(e, None)?.ty)
}
