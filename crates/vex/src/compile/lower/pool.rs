//! The constant pool: each distinct numeric constant of a snippet gets a
//! register of its own, filled once when a frame is made, so a literal in a
//! loop costs no instruction per iteration (or per batch).
//!
//! While lowering, pool registers are numbered from `FLOAT_BASE` and
//! `INT_BASE`, far above any real register; `renumber` moves them after the
//! program's own registers once their count is known. Nothing writes a pool
//! register: a constant passed where it may be written (a by-reference
//! parameter, a call's output argument) is copied first.

use std::collections::HashMap;

use crate::ir::{Op, Reg};
use crate::program::{CallSite, Constants, Counts};

const FLOAT_BASE: Reg = 1 << 30;
const INT_BASE: Reg = 1 << 29;

#[derive(Default)]
pub(crate) struct Pool {
    floats: Vec<f32>,
    ints: Vec<i32>,
    float_at: HashMap<u32, Reg>,
    int_at: HashMap<i32, Reg>,
}

/// Whether `reg` (of the float or int file) is a pool register.
pub(crate) fn holds(reg: Reg) -> bool {
    reg >= INT_BASE
}

impl Pool {
    pub fn float(&mut self, v: f32) -> Reg {
        // By bits: -0.0 and 0.0 (and NaNs) stay distinct constants.
        let next = FLOAT_BASE + self.floats.len() as Reg;
        let reg = *self.float_at.entry(v.to_bits()).or_insert(next);
        if reg == next {
            self.floats.push(v);
        }
        reg
    }

    pub fn int(&mut self, v: i32) -> Reg {
        let next = INT_BASE + self.ints.len() as Reg;
        let reg = *self.int_at.entry(v).or_insert(next);
        if reg == next {
            self.ints.push(v);
        }
        reg
    }

    /// Moves the pool's registers after the program's own (`counts`, which
    /// grow by the pool) in every instruction and call site, and returns
    /// the constants with their final registers.
    pub fn renumber(
        self,
        ops: &mut [Op],
        calls: &mut [CallSite],
        counts: &mut Counts,
    ) -> Constants {
        let (f0, i0) = (counts.f, counts.i);
        debug_assert!(f0 < INT_BASE && i0 < INT_BASE, "registers reach the pool");
        let map = |r: &mut Reg| {
            if *r >= FLOAT_BASE {
                *r = f0 + (*r - FLOAT_BASE);
            } else if *r >= INT_BASE {
                *r = i0 + (*r - INT_BASE);
            }
        };
        for op in ops.iter_mut() {
            debug_assert!(
                op.dest().is_none_or(|d| !holds(d)),
                "{op:?} writes a constant's register"
            );
            op.for_each_reg(map);
        }
        for c in calls.iter_mut() {
            for a in &mut c.args {
                map(&mut a.reg);
            }
            map(&mut c.out.reg);
            if let Some(m) = &mut c.mask {
                map(m);
            }
        }
        counts.f += self.floats.len() as u32;
        counts.i += self.ints.len() as u32;
        Constants {
            floats: (f0, self.floats),
            ints: (i0, self.ints),
        }
    }
}
