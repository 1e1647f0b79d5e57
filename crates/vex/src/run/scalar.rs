//! The one-lane path: a batch of one lane (a detail run, a parameter
//! expression) runs its numeric instructions and jumps here, reading and
//! writing lane 0 of the register files directly instead of looping over
//! slices. The files are borrowed once for a run of such instructions, so
//! an instruction costs its dispatch and its arithmetic.

use super::rules::{compare, fbin1, fun1, ibin1, iun1};
use crate::ir::*;

/// Runs instructions from `pc` on lane 0 of `f` and `i` until one the
/// batch path runs (a call, a string or array instruction, a loop's back
/// edge whose turn polls cancellation), and returns its index (or the end).
/// `polls` counts the back edges taken.
pub(super) fn run_until_batch(
    ops: &[Op],
    mut pc: usize,
    f: &mut [f32],
    i: &mut [i32],
    polls: &mut u32,
) -> usize {
    let at = |r: Reg| r as usize * LANES;
    while let Some(op) = ops.get(pc) {
        pc = match *op {
            Op::FConst { d, v } => {
                f[at(d)] = v;
                pc + 1
            }
            Op::IConst { d, v } => {
                i[at(d)] = v;
                pc + 1
            }
            Op::FMov { d, s } => {
                f[at(d)] = f[at(s)];
                pc + 1
            }
            Op::IMov { d, s } => {
                i[at(d)] = i[at(s)];
                pc + 1
            }
            Op::FSel { d, s, m } => {
                if i[at(m)] != 0 {
                    f[at(d)] = f[at(s)];
                }
                pc + 1
            }
            Op::ISel { d, s, m } => {
                if i[at(m)] != 0 {
                    i[at(d)] = i[at(s)];
                }
                pc + 1
            }
            Op::FBin { op, d, a, b } => {
                f[at(d)] = fbin1(op, f[at(a)], f[at(b)]);
                pc + 1
            }
            Op::FUn { op, d, a } => {
                f[at(d)] = fun1(op, f[at(a)]);
                pc + 1
            }
            Op::IBin { op, d, a, b } => {
                i[at(d)] = ibin1(op, i[at(a)], i[at(b)]);
                pc + 1
            }
            Op::IUn { op, d, a } => {
                i[at(d)] = iun1(op, i[at(a)]);
                pc + 1
            }
            Op::FCmp { op, d, a, b } => {
                i[at(d)] = compare(op, &f[at(a)], &f[at(b)]);
                pc + 1
            }
            Op::ICmp { op, d, a, b } => {
                i[at(d)] = compare(op, &i[at(a)], &i[at(b)]);
                pc + 1
            }
            Op::IToF { d, s } => {
                f[at(d)] = i[at(s)] as f32;
                pc + 1
            }
            Op::FToI { d, s } => {
                i[at(d)] = f[at(s)] as i32;
                pc + 1
            }
            Op::Jump { to } => to as usize,
            Op::JumpIfNone { m, to } => jump(i[at(m)] == 0, pc, to),
            Op::JumpUnlessI { op, a, b, to } => {
                jump(compare(op, &i[at(a)], &i[at(b)]) == 0, pc, to)
            }
            Op::JumpUnlessF { op, a, b, to } => {
                jump(compare(op, &f[at(a)], &f[at(b)]) == 0, pc, to)
            }
            Op::Back { to } => {
                // Every 64th turn the batch path takes it, to poll.
                if (polls.wrapping_add(1)).is_multiple_of(64) {
                    return pc;
                }
                *polls = polls.wrapping_add(1);
                to as usize
            }
            _ => return pc,
        };
    }
    pc
}

#[inline(always)]
fn jump(taken: bool, pc: usize, to: u32) -> usize {
    if taken {
        to as usize
    } else {
        pc + 1
    }
}
