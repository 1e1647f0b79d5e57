//! Values and exact gradients of many points at once: forward automatic
//! differentiation as [`GradEval`] does it, one tape instruction at a time
//! over blocks of points laid out plane by plane for the compiler to
//! vectorise.
//!
//! [`GradEval`]: crate::eval::GradEval

use crate::eval::{grad_at, grad_binary, grad_capsules, grad_unary, Grad, LANES};
use crate::field::{binary, Binary};
use crate::tape::{Instr, Tape};

/// Values and exact gradients of many points: [`GradEval`]'s arithmetic run
/// one instruction at a time over blocks of up to [`LANES`] points, so the
/// interpreter's dispatch is paid once per block, not per point. Each
/// register is four planes (the value and the three partials) of the
/// block's lanes, and the common operations run plane by plane in loops the
/// compiler vectorises; every lane computes exactly what [`GradEval`] does.
/// Planes are strided by the block's own length: a brick's few dozen
/// crossings fill a few kilobytes, where zeroing a register file sized for
/// `LANES` lanes for each brick was 11% of all the mesher's instructions
/// (colonnade at depth 6, callgrind).
///
/// [`GradEval`]: crate::eval::GradEval
pub struct BatchGradEval<'t> {
    tape: &'t Tape,
    /// Plane `p` of register `r` at `[(4 r + p) len, (4 r + p + 1) len)`.
    regs: Vec<f64>,
    lanes: Lanes,
    /// Registers of one point, for blocks too short to pay for planes.
    one: Vec<Grad>,
}

/// Blocks shorter than this are evaluated a point at a time: the planes'
/// bookkeeping per instruction outweighs their arithmetic (adaptive
/// output's measures ask a few points per brick).
const PLANES_FROM: usize = 8;

/// Scratch of a block's lanes: slopes, and which side a min or max took.
#[derive(Default)]
struct Lanes {
    ka: Vec<f64>,
    kb: Vec<f64>,
    take_a: Vec<bool>,
}

/// The planes of one block: its length and the register file.
struct Planes<'r> {
    len: usize,
    regs: &'r mut [f64],
}

impl Planes<'_> {
    fn at(&self, r: u32, p: usize) -> usize {
        (4 * r as usize + p) * self.len
    }

    fn plane(&self, r: u32, p: usize) -> &[f64] {
        let o = self.at(r, p);
        &self.regs[o..o + self.len]
    }

    /// Output plane `p` of `out` with the same plane of `a` and `b` (the
    /// tape never gives an output the register of one of its arguments).
    #[inline]
    fn split(&mut self, p: usize, (out, a, b): (u32, u32, u32)) -> (&mut [f64], &[f64], &[f64]) {
        let (o, x, y, len) = (self.at(out, p), self.at(a, p), self.at(b, p), self.len);
        let (before, rest) = self.regs.split_at_mut(o);
        let (dst, after) = rest.split_at_mut(len);
        let pick = |x: usize| -> &[f64] {
            if x < o {
                &before[x..x + len]
            } else {
                &after[x - o - len..x - o]
            }
        };
        (dst, pick(x), pick(y))
    }

    fn lane(&self, r: u32, i: usize) -> Grad {
        Grad {
            v: self.regs[self.at(r, 0) + i],
            d: std::array::from_fn(|k| self.regs[self.at(r, k + 1) + i]),
        }
    }

    fn set_lane(&mut self, r: u32, i: usize, g: Grad) {
        let o = self.at(r, 0);
        self.regs[o + i] = g.v;
        for k in 0..3 {
            let o = self.at(r, k + 1);
            self.regs[o + i] = g.d[k];
        }
    }

    /// The value plane of `out = op(a, b)`.
    fn value(&mut self, op: Binary, regs3: (u32, u32, u32)) {
        let (o, x, y) = self.split(0, regs3);
        macro_rules! each {
            ($f:expr) => {
                for ((o, &a), &b) in o.iter_mut().zip(x).zip(y) {
                    *o = $f(a, b);
                }
            };
        }
        match op {
            Binary::Add => each!(|a: f64, b: f64| a + b),
            Binary::Sub => each!(|a: f64, b: f64| a - b),
            Binary::Mul => each!(|a: f64, b: f64| a * b),
            Binary::Div => each!(|a: f64, b: f64| a / b),
            Binary::Min => each!(f64::min),
            Binary::Max => each!(f64::max),
            _ => each!(|a: f64, b: f64| binary(op, a, b)),
        }
    }

    /// The partial planes of `out = ka a + kb b`, slopes per lane.
    fn linear(&mut self, regs3: (u32, u32, u32), ka: &[f64], kb: &[f64]) {
        for p in 1..4 {
            let (o, x, y) = self.split(p, regs3);
            for ((o, (&x, &y)), (&ka, &kb)) in
                o.iter_mut().zip(x.iter().zip(y)).zip(ka.iter().zip(kb))
            {
                *o = ka * x + kb * y;
            }
        }
    }

    /// The partial planes of `out = a + s b` (`s` is 1 or -1: exactly
    /// `GradEval`'s `1 a + s b`).
    fn sum(&mut self, regs3: (u32, u32, u32), s: f64) {
        for p in 1..4 {
            let (o, x, y) = self.split(p, regs3);
            for ((o, &x), &y) in o.iter_mut().zip(x).zip(y) {
                *o = x + s * y;
            }
        }
    }

    /// The partial planes of the side each lane's min or max took.
    fn select(&mut self, regs3: (u32, u32, u32), take_a: &[bool]) {
        for p in 1..4 {
            let (o, x, y) = self.split(p, regs3);
            for ((o, (&x, &y)), &t) in o.iter_mut().zip(x.iter().zip(y)).zip(take_a) {
                *o = if t { x } else { y };
            }
        }
    }
}

impl<'t> BatchGradEval<'t> {
    pub fn new(tape: &'t Tape) -> BatchGradEval<'t> {
        BatchGradEval {
            tape,
            regs: Vec::new(),
            lanes: Lanes::default(),
            one: Vec::new(),
        }
    }

    /// Evaluates `tape` from now on, keeping the register buffer.
    pub fn set_tape(&mut self, tape: &'t Tape) {
        self.tape = tape;
    }

    /// `out[i]` = value and gradient at `points[i]`.
    pub fn eval(&mut self, points: &[[f64; 3]], out: &mut [Grad]) {
        assert_eq!(points.len(), out.len(), "a result per point");
        for (pts, res) in points.chunks(LANES).zip(out.chunks_mut(LANES)) {
            let len = pts.len();
            if len < PLANES_FROM {
                self.one.resize(self.tape.slots(), Grad::default());
                for (p, r) in pts.iter().zip(res) {
                    *r = grad_at(self.tape, &mut self.one, *p);
                }
                continue;
            }
            // Grown only: a smaller block or tape uses a prefix.
            let need = self.tape.slots() * 4 * len;
            if self.regs.len() < need {
                self.regs.resize(need, 0.0);
            }
            let lanes = &mut self.lanes;
            lanes.ka.resize(len, 0.0);
            lanes.kb.resize(len, 0.0);
            lanes.take_a.resize(len, false);
            let mut planes = Planes {
                len,
                regs: &mut self.regs,
            };
            for ins in self.tape.instrs() {
                lanes.instruction(self.tape, &mut planes, *ins, pts);
            }
            let o = self.tape.output() as u32;
            for (i, r) in res.iter_mut().enumerate() {
                *r = planes.lane(o, i);
            }
        }
    }
}

impl Lanes {
    fn instruction(&mut self, tape: &Tape, planes: &mut Planes, ins: Instr, pts: &[[f64; 3]]) {
        let len = planes.len;
        match ins {
            Instr::Var { out, axis } => {
                let o = planes.at(out, 0);
                for (r, p) in planes.regs[o..o + len].iter_mut().zip(pts) {
                    *r = p[axis as usize];
                }
                for k in 0..3 {
                    let o = planes.at(out, k + 1);
                    planes.regs[o..o + len].fill(if k == axis as usize { 1.0 } else { 0.0 });
                }
            }
            Instr::Const { out, value } => {
                let o = planes.at(out, 0);
                planes.regs[o..o + len].fill(value);
                planes.regs[o + len..o + 4 * len].fill(0.0);
            }
            Instr::Unary { op, out, a } => {
                // The value and slope lane by lane, then the partials scaled.
                let (x, o) = (planes.at(a, 0), planes.at(out, 0));
                for (i, k) in self.ka.iter_mut().enumerate() {
                    let g = grad_unary(
                        op,
                        Grad {
                            v: planes.regs[x + i],
                            d: [1.0, 0.0, 0.0],
                        },
                    );
                    planes.regs[o + i] = g.v;
                    *k = g.d[0];
                }
                for p in 1..4 {
                    let (dst, src, _) = planes.split(p, (out, a, a));
                    for ((d, &s), &k) in dst.iter_mut().zip(src).zip(&self.ka) {
                        *d = s * k;
                    }
                }
            }
            Instr::Binary { op, out, a, b } => self.binary(planes, op, (out, a, b)),
            Instr::Capsules { set, out, x, y, z } => {
                let set = tape.capsule_set(set);
                for i in 0..len {
                    let args = [x, y, z].map(|r| planes.lane(r, i));
                    planes.set_lane(out, i, grad_capsules(set, args));
                }
            }
        }
    }

    /// `out = op(a, b)`: the common operations plane by plane, the rest lane
    /// by lane with `GradEval`'s rule.
    fn binary(&mut self, planes: &mut Planes, op: Binary, regs3: (u32, u32, u32)) {
        let (out, a, b) = regs3;
        match op {
            Binary::Add | Binary::Sub => {
                planes.value(op, regs3);
                planes.sum(regs3, if op == Binary::Add { 1.0 } else { -1.0 });
            }
            Binary::Mul => {
                self.ka.copy_from_slice(planes.plane(b, 0));
                self.kb.copy_from_slice(planes.plane(a, 0));
                planes.value(op, regs3);
                planes.linear(regs3, &self.ka, &self.kb);
            }
            Binary::Div => {
                let (x, y) = (planes.plane(a, 0), planes.plane(b, 0));
                for (((ka, kb), &va), &vb) in self.ka.iter_mut().zip(&mut self.kb).zip(x).zip(y) {
                    *ka = 1.0 / vb;
                    *kb = -va / (vb * vb);
                }
                planes.value(op, regs3);
                planes.linear(regs3, &self.ka, &self.kb);
            }
            Binary::Min | Binary::Max => {
                // The first side on a tie, as `GradEval`.
                let (x, y) = (planes.plane(a, 0), planes.plane(b, 0));
                for ((t, &va), &vb) in self.take_a.iter_mut().zip(x).zip(y) {
                    *t = if op == Binary::Min {
                        va <= vb
                    } else {
                        va >= vb
                    };
                }
                planes.value(op, regs3);
                planes.select(regs3, &self.take_a);
            }
            _ => {
                for i in 0..planes.len {
                    let g = grad_binary(op, planes.lane(a, i), planes.lane(b, i));
                    planes.set_lane(out, i, g);
                }
            }
        }
    }
}
