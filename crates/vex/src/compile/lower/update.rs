//! In-place updates in a one-lane program: `x += y`, `x++` and the like
//! compute straight into the variable's registers. One lane reads an
//! instruction's operands before writing its result, so a destination may
//! be a source there; a batch needs the result in a temporary and a copy.

use super::expr::Target;
use super::{LResult, Lower};
use crate::compile::ast::{Expr, ExprKind};
use crate::ir::{Loc, Op};

impl Lower<'_> {
    /// Lowers `e` for its effects alone (a statement, a loop's step).
    pub(super) fn discarded(&mut self, e: &Expr) -> LResult<()> {
        let mark = self.alloc;
        let r = match &e.kind {
            ExprKind::IncDec { delta, target, .. } => self.inc_dec(*delta, None, target, e.pos),
            _ => self.expr(e, None),
        };
        self.alloc = mark;
        r.map(|_| ())
    }

    /// After `binary` computed `new` from target `t`'s registers with the
    /// instructions from `start` on: when the program is uniform and those
    /// are one instruction per component, each reading the same component
    /// of the target, they write the target directly. Returns the target
    /// then (its value is the new one).
    pub(super) fn retarget(&mut self, t: Target, start: usize, new: Loc) -> Option<Loc> {
        let Target::Regs(l) = t else { return None };
        if !self.uniform || new.ty != l.ty {
            return None;
        }
        let n = if l.ty.is_floaty() {
            l.ty.floats() as u32
        } else {
            1
        };
        let ops = &self.ops[start..];
        let own = |r: u32| (new.reg..new.reg + n).contains(&r);
        let matches = ops.len() == n as usize
            && ops.iter().zip(0..).all(|(op, k)| match *op {
                Op::FBin { d, a, b, .. } if l.ty.is_floaty() => {
                    d == new.reg + k && a == l.reg + k && !own(b)
                }
                Op::IBin { d, a, b, .. } if !l.ty.is_floaty() => {
                    d == new.reg + k && a == l.reg + k && !own(b)
                }
                _ => false,
            });
        if !matches {
            return None;
        }
        for (op, k) in self.ops[start..].iter_mut().zip(0..) {
            if let Op::FBin { d, .. } | Op::IBin { d, .. } = op {
                *d = l.reg + k;
            }
        }
        Some(l)
    }
}
