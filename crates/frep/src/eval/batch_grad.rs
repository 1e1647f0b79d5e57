//! Values and exact gradients of many points at once: [`GradEval`]'s rules
//! (`grad_unary`, `grad_binary`, `grad_dataset`, written once in the parent)
//! run one instruction at a time over blocks of [`WIDTH`] points.
//!
//! A register is a fixed, cache-line-aligned block laid out by component,
//! not by point: `WIDTH` values, then `WIDTH` x-derivatives, then y, then
//! z. With a point's value and gradient side by side, `min` and `max`
//! compiled to scalar compares and spills; with blocks of `LANES` (256)
//! points of variable length, the mesher's calls (about 14 points each,
//! colonnade at depth 6) paid more for each instruction's slicing and loop
//! tails than for its arithmetic. Fixed rows are straight-line vector code
//! without bounds checks or tails, run 4, 8 or 16 lanes wide as the block
//! is full (the mesher's points, grouped by brick, often come a few at a
//! time); a last, partial block repeats its last point in the lanes left.
//! Colonnade's 64k gradients in one call: 53 ms before, 35 after; in
//! batches of 48 on a brick's tape: 1.60 ms, 1.09 (`cargo bench -p
//! geode-frep --bench eval -- batch_gradient`). Every row loop must
//! vectorise: `min`/`max` pick by bit mask and `neg`, `abs`, `square`,
//! `sqrt` scale by a slope row (see `each_pick`, `each_scaled`), and
//! registers are borrowed apart by index (`out_and_pair`): 21.6 ms and
//! 0.86 ms.
//!
//! [`GradEval`]: super::GradEval

use super::{
    grad_binary, grad_dataset, grad_unary, grow_file, keep_file, spare_file, unary_slope, Grad,
    Instr, Tape, SPARE_GRAD_REGS,
};
use crate::field::{unary, Binary, Unary};

/// Points evaluated together.
pub const WIDTH: usize = 16;

/// A register: value row, then the gradient's three rows; aligned to a
/// cache line, so no vector load straddles two (an allocation's alignment
/// otherwise varies from build to build: 34.8 against 37.9 ms measured on
/// the same code, colonnade's 64k gradients).
#[derive(Clone, Copy, Default)]
#[repr(C, align(64))]
pub(super) struct Block([[f64; WIDTH]; 4]);

impl std::ops::Index<usize> for Block {
    type Output = [f64; WIDTH];
    #[inline(always)]
    fn index(&self, row: usize) -> &[f64; WIDTH] {
        &self.0[row]
    }
}

impl std::ops::IndexMut<usize> for Block {
    #[inline(always)]
    fn index_mut(&mut self, row: usize) -> &mut [f64; WIDTH] {
        &mut self.0[row]
    }
}

/// Values and exact gradients of many points (see the module doc).
pub struct BatchGradEval<'t> {
    tape: &'t Tape,
    regs: Vec<Block>,
}

/// Lane `i` of a block as one value and gradient.
#[inline(always)]
fn lane(r: &Block, i: usize) -> Grad {
    Grad {
        v: r[0][i],
        d: [r[1][i], r[2][i], r[3][i]],
    }
}

#[inline(always)]
fn set_lane(r: &mut Block, i: usize, g: Grad) {
    r[0][i] = g.v;
    r[1][i] = g.d[0];
    r[2][i] = g.d[1];
    r[3][i] = g.d[2];
}

/// The output register and the registers before and after it (the tape
/// never gives an output the register of one of its arguments).
fn carve(regs: &mut [Block], o: usize) -> (&mut Block, &[Block], &[Block]) {
    let (before, rest) = regs.split_at_mut(o);
    let (dst, after) = rest.split_at_mut(1);
    (&mut dst[0], before, after)
}

/// The output register and the two argument registers (the same one for
/// `x * x` or a unary operation's one). Borrowed apart by index: finding
/// each on its side of a split file, as `carve` and `arg` do, cost a
/// branch and two bounds checks an instruction, where the mesher's short
/// blocks spend most of their time (colonnade at depth 6: 6% of meshing).
#[inline(always)]
fn out_and_pair(
    regs: &mut [Block],
    out: u32,
    (a, b): (u32, u32),
) -> (&mut Block, (&Block, &Block)) {
    const APART: &str = "the tape never gives an output its argument's register";
    if a == b {
        let [dst, a] = regs
            .get_disjoint_mut([out as usize, a as usize])
            .expect(APART);
        (dst, (a, a))
    } else {
        let [dst, a, b] = regs
            .get_disjoint_mut([out as usize, a as usize, b as usize])
            .expect(APART);
        (dst, (a, b))
    }
}

/// An argument's register, found on its side of the output.
fn arg<'a>(before: &'a [Block], after: &'a [Block], o: usize, x: usize) -> &'a Block {
    if x < o {
        &before[x]
    } else {
        &after[x - o - 1]
    }
}

/// `dst = rule(a)` lane by lane: the unary operations `each_scaled` does
/// not take (transcendentals, whose calls cost more than their lanes'
/// layout).
#[inline(always)]
fn each_unary<const W: usize>(op: Unary, a: &Block, dst: &mut Block) {
    for i in 0..W {
        set_lane(dst, i, grad_unary(op, lane(a, i)));
    }
}

#[inline(always)]
fn each_binary<const W: usize>(op: Binary, (a, b): (&Block, &Block), dst: &mut Block) {
    for i in 0..W {
        set_lane(dst, i, grad_binary(op, lane(a, i), lane(b, i)));
    }
}

/// `min` or `max` row by row: the value, then each gradient row taken from
/// the argument the rule picks (`grad_binary`'s choice: `a` where
/// `a <= b` for `min`, `a >= b` for `max`, so `b` at a NaN).
#[inline(always)]
fn each_pick<const W: usize>(op: Binary, (a, b): (&Block, &Block), dst: &mut Block) {
    let value = |x: f64, y: f64| {
        if op == Binary::Min {
            x.min(y)
        } else {
            x.max(y)
        }
    };
    let picks_a = |x: f64, y: f64| if op == Binary::Min { x <= y } else { x >= y };
    // The choice as a bit mask, then a bitwise select per row: a test per
    // lane in each row kept the rows' loops from vectorising (`min`, `max`
    // at 16 lanes: 8.6 ns an instruction before, 4.7 after).
    let mut mask = [0u64; WIDTH];
    for i in 0..W {
        mask[i] = (picks_a(a[0][i], b[0][i]) as u64).wrapping_neg();
    }
    for i in 0..W {
        dst[0][i] = value(a[0][i], b[0][i]);
    }
    for k in 1..4 {
        for i in 0..W {
            let (x, y) = (a[k][i].to_bits(), b[k][i].to_bits());
            dst[k][i] = f64::from_bits((x & mask[i]) | (y & !mask[i]));
        }
    }
}

/// `neg`, `abs`, `square` or `sqrt` row by row: the value row and a slope
/// row (`unary_slope`, `op` a constant so its `match` folds away), then
/// each gradient row scaled by the slope, as `grad_unary` has it. Lane by
/// lane, the slopes' selects did not vectorise (a sixth of the
/// instructions of colonnade's brick tapes are these four).
#[inline(always)]
fn each_scaled<const W: usize>(op: Unary, a: &Block, dst: &mut Block) {
    let mut slope = [0f64; WIDTH];
    for i in 0..W {
        let x = a[0][i];
        let v = unary(op, x);
        slope[i] = unary_slope(op, x, v);
        dst[0][i] = v;
    }
    for k in 1..4 {
        for i in 0..W {
            dst[k][i] = a[k][i] * slope[i];
        }
    }
}

/// `a + b` or `a - b` row by row (`grad_binary`'s rule: the gradients add
/// or subtract as the values do).
#[inline(always)]
fn each_sum<const W: usize>(negate_b: bool, (a, b): (&Block, &Block), dst: &mut Block) {
    for k in 0..4 {
        for i in 0..W {
            dst[k][i] = if negate_b {
                a[k][i] - b[k][i]
            } else {
                a[k][i] + b[k][i]
            };
        }
    }
}

/// `a * b` row by row: `d(ab) = b da + a db`, as `grad_binary` has it.
#[inline(always)]
fn each_product<const W: usize>((a, b): (&Block, &Block), dst: &mut Block) {
    for k in 1..4 {
        for i in 0..W {
            dst[k][i] = b[0][i] * a[k][i] + a[0][i] * b[k][i];
        }
    }
    for i in 0..W {
        dst[0][i] = a[0][i] * b[0][i];
    }
}

impl<'t> BatchGradEval<'t> {
    pub fn new(tape: &'t Tape) -> BatchGradEval<'t> {
        BatchGradEval {
            tape,
            regs: spare_file(&SPARE_GRAD_REGS, tape.slots()),
        }
    }

    /// Evaluates `tape` from now on, keeping the register file (grown
    /// only: a smaller tape uses a prefix).
    pub fn set_tape(&mut self, tape: &'t Tape) {
        self.tape = tape;
        grow_file(&mut self.regs, tape.slots());
    }

    /// `out[i]` = value and gradient at `points[i]`.
    pub fn eval(&mut self, points: &[[f64; 3]], out: &mut [Grad]) {
        assert_eq!(points.len(), out.len(), "a result per point");
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2, checked just above.
            return unsafe { self.eval_avx2(points, out) };
        }
        self.eval_any(points, out)
    }

    /// [`BatchGradEval::eval`] compiled for AVX2, chosen at run time: the
    /// lane loops then run on 256-bit registers where the baseline build
    /// has SSE2's 128. The same IEEE operations lane by lane (no fused
    /// multiply-add), so the results are the same bits on every machine.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn eval_avx2(&mut self, points: &[[f64; 3]], out: &mut [Grad]) {
        self.eval_any(points, out)
    }

    #[inline(always)]
    pub(super) fn eval_any(&mut self, points: &[[f64; 3]], out: &mut [Grad]) {
        for (pts, res) in points.chunks(WIDTH).zip(out.chunks_mut(WIDTH)) {
            let block: [[f64; 3]; WIDTH] = std::array::from_fn(|i| pts[i.min(pts.len() - 1)]);
            // Narrower code for a short block (grouped by brick, the
            // mesher's points often come a few at a time).
            match pts.len() {
                0..=4 => self.run::<4>(&block),
                5..=8 => self.run::<8>(&block),
                _ => self.run::<WIDTH>(&block),
            }
            let r = &self.regs[self.tape.output()];
            for (i, g) in res.iter_mut().enumerate() {
                *g = lane(r, i);
            }
        }
    }

    /// The tape over the first `W` points of a block.
    #[inline(always)]
    fn run<const W: usize>(&mut self, pts: &[[f64; 3]; WIDTH]) {
        for ins in self.tape.instrs() {
            self.step::<W>(ins, pts);
        }
    }

    /// One instruction over the first `W` points of a block.
    #[inline(always)]
    fn step<const W: usize>(&mut self, ins: &Instr, pts: &[[f64; 3]; WIDTH]) {
        let regs = &mut self.regs;
        match *ins {
            Instr::Var { out, axis } => {
                let dst = &mut regs[out as usize];
                for i in 0..W {
                    dst[0][i] = pts[i][axis as usize];
                }
                for k in 0..3 {
                    dst[k + 1][..W].fill(if k == axis as usize { 1.0 } else { 0.0 });
                }
            }
            Instr::Const { out, value } => {
                let dst = &mut regs[out as usize];
                dst[0][..W].fill(value);
                for k in 1..4 {
                    dst[k][..W].fill(0.0);
                }
            }
            Instr::Unary { op, out, a } => {
                let (dst, a) = out_and_pair(regs, out, (a, a));
                let a = a.0;
                match op {
                    Unary::Neg => each_scaled::<W>(Unary::Neg, a, dst),
                    Unary::Abs => each_scaled::<W>(Unary::Abs, a, dst),
                    Unary::Sqrt => each_scaled::<W>(Unary::Sqrt, a, dst),
                    Unary::Square => each_scaled::<W>(Unary::Square, a, dst),
                    _ => each_unary::<W>(op, a, dst),
                }
            }
            Instr::Binary { op, out, a, b } => {
                let (dst, args) = out_and_pair(regs, out, (a, b));
                match op {
                    Binary::Add => each_sum::<W>(false, args, dst),
                    Binary::Sub => each_sum::<W>(true, args, dst),
                    Binary::Mul => each_product::<W>(args, dst),
                    Binary::Min => each_pick::<W>(Binary::Min, args, dst),
                    Binary::Max => each_pick::<W>(Binary::Max, args, dst),
                    _ => each_binary::<W>(op, args, dst),
                }
            }
            Instr::Dataset { set, out, x, y, z } => {
                let set = self.tape.dataset(set);
                let o = out as usize;
                let (dst, before, after) = carve(regs, o);
                let [x, y, z] = [x, y, z].map(|r| arg(before, after, o, r as usize));
                for i in 0..W {
                    let args = [lane(x, i), lane(y, i), lane(z, i)];
                    set_lane(dst, i, grad_dataset(set, args));
                }
            }
        }
    }
}

impl Drop for BatchGradEval<'_> {
    fn drop(&mut self) {
        keep_file(&SPARE_GRAD_REGS, std::mem::take(&mut self.regs));
    }
}
