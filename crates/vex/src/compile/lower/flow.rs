//! Control flow: `if`, loops, `foreach`, `break`, `continue` and `return`.
//! A batch of many lanes runs in lockstep under masks: a branch narrows
//! the mask and jumps only when no lane is left. A one-lane program (a
//! detail wrangle, a parameter expression) is uniform: its branches are
//! plain jumps, its stores need no mask and a loop iteration costs only its
//! own instructions.

use super::{err, LResult, Lower};
use crate::compile::ast::*;
use crate::compile::lex::Pos;
use crate::ir::*;
use crate::library::array_ops;
use crate::ty::Ty;

/// A loop being lowered: its masks (batch) or its pending jumps (uniform).
pub(crate) struct LoopCtl {
    /// Mask stack index of the loop's active lanes (`break` narrows it).
    active_at: usize,
    /// Mask stack index of the iteration's live lanes (`continue`).
    live_at: usize,
    /// Uniform: `break` jumps, patched to the loop's end.
    breaks: Vec<usize>,
    /// Uniform: `continue` jumps, patched to the step.
    continues: Vec<usize>,
}

/// A function (or the snippet) being lowered.
pub(crate) struct FuncCtl {
    /// Mask stack index of its live lanes, when a `return` must narrow it.
    pub live_at: Option<usize>,
    /// Where `return` stores its value.
    pub slot: Option<Loc>,
    /// Uniform: whether a `return` jumps to the end (it is not the last
    /// statement), and those jumps.
    pub jumps: bool,
    pub returns: Vec<usize>,
}

impl<'a> Lower<'a> {
    pub(super) fn if_stmt(&mut self, c: &Expr, then: &Stmt, other: Option<&Stmt>) -> LResult<()> {
        if self.uniform {
            return self.if_uniform(c, then, other);
        }
        let mark = self.alloc;
        let cond = self.truth(c)?;
        let m = self.mask().unwrap_or(self.ones);
        let m_then = self.ibin(IBinOp::LAnd, m, cond);
        let m_else = self.ibin(IBinOp::AndNot, m, cond);
        let skip_then = self.emit(Op::JumpIfNone { m: m_then, to: 0 });
        self.masks.push(m_then);
        let r = self.scoped(|me| me.stmt(then));
        self.masks.pop();
        r?;
        if let Some(o) = other {
            let at = self.here();
            self.patch(skip_then, at);
            let skip_else = self.emit(Op::JumpIfNone { m: m_else, to: 0 });
            self.masks.push(m_else);
            let r = self.scoped(|me| me.stmt(o));
            self.masks.pop();
            r?;
            let end = self.here();
            self.patch(skip_else, end);
        } else {
            let end = self.here();
            self.patch(skip_then, end);
        }
        self.alloc = mark;
        Ok(())
    }

    fn if_uniform(&mut self, c: &Expr, then: &Stmt, other: Option<&Stmt>) -> LResult<()> {
        let skip_then = self.jump_unless(c)?;
        self.scoped(|me| me.stmt(then))?;
        match other {
            Some(o) => {
                let skip_else = self.emit(Op::Jump { to: 0 });
                let at = self.here();
                self.patch(skip_then, at);
                self.scoped(|me| me.stmt(o))?;
                let end = self.here();
                self.patch(skip_else, end);
            }
            None => {
                let end = self.here();
                self.patch(skip_then, end);
            }
        }
        Ok(())
    }

    /// The jump taken when `c` is false in a uniform program (patched by
    /// the caller); a comparison computing `c` becomes part of the jump.
    fn jump_unless(&mut self, c: &Expr) -> LResult<usize> {
        let mark = self.alloc;
        let start = self.ops.len();
        let v = self.expr(c, None)?;
        let fresh = v.ty == Ty::Int && v.reg >= mark.c.i && self.ops.len() > start;
        let fused = match self.ops.last() {
            Some(&Op::ICmp { op, d, a, b }) if fresh && d == v.reg => {
                Some(Op::JumpUnlessI { op, a, b, to: 0 })
            }
            Some(&Op::FCmp { op, d, a, b }) if fresh && d == v.reg => {
                Some(Op::JumpUnlessF { op, a, b, to: 0 })
            }
            _ => None,
        };
        let at = match (fused, v.ty) {
            (Some(j), _) => {
                let at = self.ops.len() - 1;
                self.ops[at] = j;
                at
            }
            (None, Ty::Int) => self.emit(Op::JumpIfNone { m: v.reg, to: 0 }),
            (None, Ty::Float) => {
                let zero = self.fconst(0.0);
                self.emit(Op::JumpUnlessF {
                    op: Cmp::Ne,
                    a: v.reg,
                    b: zero.reg,
                    to: 0,
                })
            }
            (None, _) => {
                let t = self.truth_of(v, c.pos)?;
                self.emit(Op::JumpIfNone { m: t, to: 0 })
            }
        };
        self.alloc = mark;
        Ok(at)
    }

    pub(super) fn loop_stmt(
        &mut self,
        cond: Option<&Expr>,
        step: Option<&Expr>,
        body: &Stmt,
        post_test: bool,
    ) -> LResult<()> {
        if self.uniform {
            return self.loop_uniform(cond, step, body, post_test);
        }
        let active = self.mask_copy();
        self.masks.push(active);
        let active_at = self.masks.len() - 1;
        let top = self.here();
        let mut exit = None;
        if !post_test {
            exit = Some(self.loop_test(cond, active)?);
        }
        self.loop_body(active_at, body)?;
        if let Some(s) = step {
            self.discarded(s)?;
        }
        if post_test {
            exit = Some(self.loop_test(cond, active)?);
        }
        self.emit(Op::Back { to: top });
        let end = self.here();
        if let Some(x) = exit {
            self.patch(x, end);
        }
        self.masks.pop();
        Ok(())
    }

    fn loop_uniform(
        &mut self,
        cond: Option<&Expr>,
        step: Option<&Expr>,
        body: &Stmt,
        post_test: bool,
    ) -> LResult<()> {
        let top = self.here();
        let mut exits = Vec::new();
        if let (false, Some(c)) = (post_test, cond) {
            exits.push(self.jump_unless(c)?);
        }
        let ctl = self.uniform_body(body)?;
        exits.extend(ctl.breaks);
        let next = self.here();
        for j in ctl.continues {
            self.patch(j, next);
        }
        if let Some(s) = step {
            self.discarded(s)?;
        }
        if let (true, Some(c)) = (post_test, cond) {
            exits.push(self.jump_unless(c)?);
        }
        self.emit(Op::Back { to: top });
        let end = self.here();
        for j in exits {
            self.patch(j, end);
        }
        Ok(())
    }

    /// A uniform loop's body; returns its pending `break`/`continue` jumps.
    fn uniform_body(&mut self, body: &Stmt) -> LResult<LoopCtl> {
        self.loops.push(LoopCtl {
            active_at: 0,
            live_at: 0,
            breaks: Vec::new(),
            continues: Vec::new(),
        });
        let r = self.scoped(|me| me.stmt(body));
        let ctl = self.loops.pop().expect("the loop");
        r.map(|()| ctl)
    }

    /// A loop's body under its own live mask (what `continue` narrows),
    /// with `break` narrowing from the loop's active mask at `active_at`.
    fn loop_body(&mut self, active_at: usize, body: &Stmt) -> LResult<()> {
        let live = self.mask_copy();
        self.masks.push(live);
        self.loops.push(LoopCtl {
            active_at,
            live_at: active_at + 1,
            breaks: Vec::new(),
            continues: Vec::new(),
        });
        let r = self.scoped(|me| me.stmt(body));
        self.loops.pop();
        self.masks.pop();
        r
    }

    /// Narrows a loop's `active` lanes by its condition and emits the exit
    /// jump (patched by the caller) taken when none is left.
    fn loop_test(&mut self, cond: Option<&Expr>, active: Reg) -> LResult<usize> {
        if let Some(c) = cond {
            let mark = self.alloc;
            let t = self.truth(c)?;
            self.update_int(active, IBinOp::LAnd, t);
            self.alloc = mark;
        }
        Ok(self.emit(Op::JumpIfNone { m: active, to: 0 }))
    }

    /// `break` (or `continue`) of the innermost loop.
    pub(super) fn break_or_continue(&mut self, is_break: bool, pos: Pos) -> LResult<()> {
        let word = if is_break { "break" } else { "continue" };
        let Some(ctl) = self.loops.last() else {
            return err(pos, format!("'{word}' outside a loop"));
        };
        if self.uniform {
            let j = self.emit(Op::Jump { to: 0 });
            let ctl = self.loops.last_mut().expect("the loop");
            if is_break {
                ctl.breaks.push(j);
            } else {
                ctl.continues.push(j);
            }
            return Ok(());
        }
        let from = if is_break { ctl.active_at } else { ctl.live_at };
        self.leave(from);
        Ok(())
    }

    /// Lanes of the current mask leave every mask from stack index `from`
    /// upward (break, continue, return).
    fn leave(&mut self, from: usize) {
        let Some(m) = self.mask() else { return };
        let gone = self.copy(Loc {
            ty: Ty::Int,
            reg: m,
        });
        for k in from..self.masks.len() {
            let r = self.masks[k];
            self.update_int(r, IBinOp::AndNot, gone.reg);
        }
    }

    pub(super) fn foreach(
        &mut self,
        index: Option<&str>,
        elem: &Decl,
        array: &Expr,
        body: &Stmt,
    ) -> LResult<()> {
        let arr = self.expr(array, None)?;
        let Ty::Array(e) = arr.ty else {
            return err(array.pos, format!("foreach needs an array, not {}", arr.ty));
        };
        if elem.ty != e.ty() && !(elem.ty.is_numeric() && e.ty().is_numeric()) {
            return err(
                elem.pos,
                format!("foreach over {} cannot bind {}", arr.ty, elem.ty.a()),
            );
        }
        let arr = self.copy(arr);
        let i = self.alloc(Ty::Int);
        self.emit(Op::IConst { d: i.reg, v: 0 });
        let n = self.call_site(array_ops::LEN, vec![arr], Ty::Int, elem.pos);
        let x = self.alloc(elem.ty);
        if let Some(name) = index {
            self.declare(name, i, elem.pos)?;
        }
        self.declare(&elem.name, x, elem.pos)?;
        // while (i < n) { x = arr[i]; body; i++ }
        let active_at = (!self.uniform).then(|| {
            let active = self.mask_copy();
            self.masks.push(active);
            self.masks.len() - 1
        });
        let top = self.here();
        let exit = match active_at {
            None => self.emit(Op::JumpUnlessI {
                op: Cmp::Lt,
                a: i.reg,
                b: n.reg,
                to: 0,
            }),
            Some(at) => {
                let active = self.masks[at];
                let t = self.alloc(Ty::Int);
                self.emit(Op::ICmp {
                    op: Cmp::Lt,
                    d: t.reg,
                    a: i.reg,
                    b: n.reg,
                });
                self.update_int(active, IBinOp::LAnd, t.reg);
                self.emit(Op::JumpIfNone { m: active, to: 0 })
            }
        };
        let item = self.call_site(array_ops::INDEX_GET, vec![arr, i], e.ty(), elem.pos);
        let item = self.convert(item, elem.ty, elem.pos)?;
        self.store(x, item);
        let one = self.iconst(1);
        let mut exits = vec![exit];
        match active_at {
            None => {
                let ctl = self.uniform_body(body)?;
                exits.extend(ctl.breaks);
                let next = self.here();
                for j in ctl.continues {
                    self.patch(j, next);
                }
                // One lane: the counter may be its own source.
                self.emit(Op::IBin {
                    op: IBinOp::Add,
                    d: i.reg,
                    a: i.reg,
                    b: one.reg,
                });
            }
            Some(at) => {
                self.loop_body(at, body)?;
                self.update_int(i.reg, IBinOp::Add, one.reg);
            }
        }
        self.emit(Op::Back { to: top });
        let end = self.here();
        for j in exits {
            self.patch(j, end);
        }
        if active_at.is_some() {
            self.masks.pop();
        }
        Ok(())
    }

    pub(super) fn return_stmt(&mut self, v: Option<&Expr>, pos: Pos) -> LResult<()> {
        let Some(f) = self.funcs.last() else {
            return err(pos, "'return' outside a function");
        };
        let (live_at, slot) = (f.live_at, f.slot);
        match (v, slot) {
            (Some(e), Some(slot)) => {
                let x = self.expr(e, Some(slot.ty))?;
                let x = self.convert(x, slot.ty, e.pos)?;
                self.store(slot, x);
            }
            (Some(e), None) => return err(e.pos, "a void function cannot return a value"),
            (None, Some(s)) if s.ty != Ty::Void => {
                return err(pos, format!("this function must return {}", s.ty.a()))
            }
            (None, _) => {}
        }
        if self.funcs.last().is_some_and(|f| f.jumps) {
            let j = self.emit(Op::Jump { to: 0 });
            self.funcs.last_mut().expect("the function").returns.push(j);
        }
        if let Some(at) = live_at {
            self.leave(at);
        }
        Ok(())
    }

    /// Starts a function's (or the snippet's) body: a `return` that is not
    /// its last statement narrows a live mask (batch) or jumps (uniform).
    pub(super) fn enter_function(&mut self, body: &[Stmt], slot: Option<Loc>) {
        let returns = count_returns(body);
        let simple =
            returns == 0 || (returns == 1 && matches!(body.last(), Some(Stmt::Return(..))));
        let live_at = if simple || self.uniform {
            None
        } else {
            let live = self.mask_copy();
            self.masks.push(live);
            Some(self.masks.len() - 1)
        };
        self.funcs.push(FuncCtl {
            live_at,
            slot,
            jumps: self.uniform && !simple,
            returns: Vec::new(),
        });
    }

    /// Ends the body `enter_function` started: returns land here.
    pub(super) fn leave_function(&mut self) {
        let f = self.funcs.pop().expect("a function");
        if f.live_at.is_some() {
            self.masks.pop();
        }
        let end = self.here();
        for j in f.returns {
            self.patch(j, end);
        }
    }

    /// Lowers the snippet's own statements: a top-level `return` ends the
    /// element, as in a wrangle.
    pub fn snippet_body(&mut self, body: &[Stmt]) -> LResult<()> {
        self.enter_function(
            body,
            Some(Loc {
                ty: Ty::Void,
                reg: 0,
            }),
        );
        let r = self.body(body);
        self.leave_function();
        r
    }
}

fn count_returns(stmts: &[Stmt]) -> usize {
    stmts
        .iter()
        .map(|s| match s {
            Stmt::Return(..) => 1,
            Stmt::Block(b) => count_returns(b),
            Stmt::If(_, a, b) => {
                count_returns(std::slice::from_ref(a))
                    + b.as_ref()
                        .map_or(0, |b| count_returns(std::slice::from_ref(b)))
            }
            Stmt::While(_, b) | Stmt::DoWhile(b, _) | Stmt::For(_, _, _, b) => {
                count_returns(std::slice::from_ref(b))
            }
            Stmt::Foreach { body, .. } => count_returns(std::slice::from_ref(body)),
            _ => 0,
        })
        .sum()
}
