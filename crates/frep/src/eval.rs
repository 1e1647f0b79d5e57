//! Tape evaluators: single point (f64), batches laid out for SIMD (f32 lanes),
//! intervals over a box (with min/max choices), and exact gradients (forward
//! automatic differentiation).

use crate::field::{binary, unary, Binary, Unary};
use crate::interval::{self, Interval};
use std::cell::RefCell;
use std::sync::Arc;

use crate::dataset::Dataset;
use crate::tape::{Choice, Choices, Instr, Tape};

mod batch_grad;
pub use batch_grad::BatchGradEval;

/// Evaluates one point at a time, reusing its registers.
pub struct PointEval<'t> {
    tape: &'t Tape,
    regs: Vec<f64>,
}

impl<'t> PointEval<'t> {
    pub fn new(tape: &'t Tape) -> PointEval<'t> {
        PointEval {
            tape,
            regs: spare_file(&SPARE_POINT_REGS, tape.slots()),
        }
    }

    pub fn eval(&mut self, p: [f64; 3]) -> f64 {
        let r = &mut self.regs;
        for ins in self.tape.instrs() {
            match *ins {
                Instr::Var { out, axis } => r[out as usize] = p[axis as usize],
                Instr::Const { out, value } => r[out as usize] = value,
                Instr::Unary { op, out, a } => r[out as usize] = unary(op, r[a as usize]),
                Instr::Binary { op, out, a, b } => {
                    r[out as usize] = binary(op, r[a as usize], r[b as usize])
                }
                Instr::Dataset { set, out, x, y, z } => {
                    let p = [r[x as usize], r[y as usize], r[z as usize]];
                    r[out as usize] = self.tape.dataset(set).value(p)
                }
            }
        }
        r[self.tape.output()]
    }
}

/// Lanes evaluated together: each instruction runs over this many values in
/// a tight loop the compiler vectorises.
pub const LANES: usize = 256;

/// Lanes of one AVX2 vector of `f32`: [`BatchEval`]'s loops run whole
/// vectors of them (`LANES` is a multiple).
const STEP: usize = 8;

/// Evaluates many points: one instruction at a time over blocks of [`LANES`].
pub struct BatchEval<'t> {
    tape: &'t Tape,
    regs: Vec<f32>,
}

#[inline(always)]
fn lane_unary(op: Unary, a: &[f32], o: &mut [f32]) {
    macro_rules! each {
        ($f:expr) => {
            for (o, a) in o.chunks_exact_mut(STEP).zip(a.chunks_exact(STEP)) {
                for i in 0..STEP {
                    o[i] = $f(a[i]);
                }
            }
        };
    }
    match op {
        Unary::Neg => each!(|a: f32| -a),
        Unary::Abs => each!(f32::abs),
        Unary::Sqrt => each!(f32::sqrt),
        Unary::Square => each!(|a: f32| a * a),
        Unary::Sin => each!(f32::sin),
        Unary::Cos => each!(f32::cos),
        Unary::Tan => each!(f32::tan),
        Unary::Asin => each!(f32::asin),
        Unary::Acos => each!(f32::acos),
        Unary::Atan => each!(f32::atan),
        Unary::Exp => each!(f32::exp),
        Unary::Ln => each!(f32::ln),
        Unary::Floor => each!(f32::floor),
        Unary::Ceil => each!(f32::ceil),
        Unary::Round => each!(f32::round),
        Unary::Not => each!(|a: f32| (a == 0.0) as u8 as f32),
    }
}

#[inline(always)]
fn lane_binary(op: Binary, a: &[f32], b: &[f32], o: &mut [f32]) {
    macro_rules! each {
        ($f:expr) => {
            for ((o, a), b) in o
                .chunks_exact_mut(STEP)
                .zip(a.chunks_exact(STEP))
                .zip(b.chunks_exact(STEP))
            {
                for i in 0..STEP {
                    o[i] = $f(a[i], b[i]);
                }
            }
        };
    }
    match op {
        Binary::Add => each!(|a: f32, b: f32| a + b),
        Binary::Sub => each!(|a: f32, b: f32| a - b),
        Binary::Mul => each!(|a: f32, b: f32| a * b),
        Binary::Div => each!(|a: f32, b: f32| a / b),
        Binary::Min => each!(f32::min),
        Binary::Max => each!(f32::max),
        Binary::Atan2 => each!(f32::atan2),
        Binary::Mod => each!(f32::rem_euclid),
        Binary::Compare => {
            each!(|a: f32, b: f32| binary(Binary::Compare, a as f64, b as f64) as f32)
        }
        Binary::And => each!(|a: f32, b: f32| if a == 0.0 { a } else { b }),
        Binary::Or => each!(|a: f32, b: f32| if a != 0.0 { a } else { b }),
    }
}

impl<'t> BatchEval<'t> {
    pub fn new(tape: &'t Tape) -> BatchEval<'t> {
        BatchEval {
            tape,
            regs: spare_file(&SPARE_REGS, tape.slots() * LANES),
        }
    }

    /// `out[i] = f(xs[i], ys[i], zs[i])` for any number of points.
    pub fn eval(&mut self, xs: &[f32], ys: &[f32], zs: &[f32], out: &mut [f32]) {
        let n = xs.len();

        assert!(
            ys.len() == n && zs.len() == n && out.len() == n,
            "coordinate slices of equal length"
        );
        let mut start = 0;
        while start < n {
            let len = (n - start).min(LANES);
            let axes = [
                &xs[start..start + len],
                &ys[start..start + len],
                &zs[start..start + len],
            ];
            self.block(axes, len);
            let o = self.tape.output() * LANES;
            out[start..start + len].copy_from_slice(&self.regs[o..o + len]);
            start += len;
        }
    }

    fn block(&mut self, axes: [&[f32]; 3], len: usize) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2, checked just above.
            return unsafe { self.block_avx2(axes, len) };
        }
        self.block_any(axes, len)
    }

    /// [`BatchEval::block`] compiled for AVX2 (see [`BatchGradEval::eval_avx2`]).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn block_avx2(&mut self, axes: [&[f32]; 3], len: usize) {
        self.block_any(axes, len)
    }

    #[inline(always)]
    fn block_any(&mut self, axes: [&[f32]; 3], len: usize) {
        let regs = &mut self.regs;
        // Whole vectors: lanes past `len` repeat the last point (their
        // values are never read), so no loop has a scalar tail.
        let width = len.next_multiple_of(STEP);
        for ins in self.tape.instrs() {
            match *ins {
                Instr::Var { out, axis } => {
                    let o = out as usize * LANES;
                    let axis = axes[axis as usize];
                    regs[o..o + len].copy_from_slice(axis);
                    regs[o + len..o + width].fill(axis[len - 1]);
                }
                Instr::Const { out, value } => {
                    let o = out as usize * LANES;
                    regs[o..o + width].fill(value as f32);
                }
                Instr::Unary { op, out, a } => {
                    let (dst, before, after) = carve(regs, out as usize * LANES);
                    let o = out as usize * LANES;
                    lane_unary(
                        op,
                        arg(before, after, o, a as usize * LANES, width),
                        &mut dst[..width],
                    );
                }
                Instr::Binary { op, out, a, b } => {
                    let (dst, before, after) = carve(regs, out as usize * LANES);
                    let o = out as usize * LANES;
                    let (a, b) = (
                        arg(before, after, o, a as usize * LANES, width),
                        arg(before, after, o, b as usize * LANES, width),
                    );
                    lane_binary(op, a, b, &mut dst[..width]);
                }
                Instr::Dataset { set, out, x, y, z } => {
                    let set = self.tape.dataset(set);
                    let [x, y, z] = [x, y, z].map(|r| r as usize * LANES);
                    let mut values = [0f32; LANES];
                    set.values(
                        &regs[x..x + width],
                        &regs[y..y + width],
                        &regs[z..z + width],
                        &mut values[..width],
                    );
                    let o = out as usize * LANES;
                    regs[o..o + width].copy_from_slice(&values[..width]);
                }
            }
        }
    }
}

/// The output block and the registers before and after it (the tape never
/// gives an output the register of one of its arguments).
fn carve<T>(regs: &mut [T], o: usize) -> (&mut [T], &[T], &[T]) {
    let (before, rest) = regs.split_at_mut(o);
    let (dst, after) = rest.split_at_mut(LANES);
    (dst, before, after)
}

/// An argument block, found on its side of the output block.
fn arg<'a, T>(before: &'a [T], after: &'a [T], o: usize, x: usize, len: usize) -> &'a [T] {
    if x < o {
        &before[x..x + len]
    } else {
        &after[x - o - LANES..x - o - LANES + len]
    }
}

/// Evaluates over a box, recording for every instruction which `min`/`max`
/// argument decides (see [`Tape::simplify`]).
pub struct IntervalEval<'t> {
    tape: &'t Tape,
    regs: Vec<Interval>,
    choices: Choices,
}

impl<'t> IntervalEval<'t> {
    pub fn new(tape: &'t Tape) -> IntervalEval<'t> {
        IntervalEval {
            tape,
            regs: vec![Interval::point(0.0); tape.slots()],
            choices: Choices {
                per_instr: vec![Choice::Both; tape.len()],
                narrowed: Vec::new(),
            },
        }
    }

    pub fn eval(&mut self, x: Interval, y: Interval, z: Interval) -> Interval {
        let axes = [x, y, z];
        let r = &mut self.regs;
        self.choices.narrowed.clear();
        for (i, ins) in self.tape.instrs().iter().enumerate() {
            match *ins {
                Instr::Var { out, axis } => r[out as usize] = axes[axis as usize],
                Instr::Const { out, value } => r[out as usize] = Interval::point(value),
                Instr::Unary { op, out, a } => r[out as usize] = interval::unary(op, r[a as usize]),
                Instr::Binary { op, out, a, b } => {
                    let (v, c) = interval::binary(op, r[a as usize], r[b as usize]);
                    r[out as usize] = v;
                    self.choices.per_instr[i] = c;
                }
                Instr::Dataset { set, out, x, y, z } => {
                    let set = self.tape.dataset(set);
                    let (v, narrowed) = set.interval(r[x as usize], r[y as usize], r[z as usize]);
                    r[out as usize] = v;
                    if let Some(n) = narrowed {
                        self.choices.narrowed.push((i as u32, Arc::new(n)));
                    }
                }
            }
        }
        r[self.tape.output()]
    }

    /// What the last evaluation proved (see [`Tape::simplify`]).
    pub fn choices(&self) -> &Choices {
        &self.choices
    }
}

/// A value with its gradient.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Grad {
    pub v: f64,
    pub d: [f64; 3],
}

impl Grad {
    fn scale(self, k: f64, v: f64) -> Grad {
        Grad {
            v,
            d: self.d.map(|x| x * k),
        }
    }
}

#[inline(always)]
fn grad_unary(op: Unary, a: Grad) -> Grad {
    let v = unary(op, a.v);
    a.scale(unary_slope(op, a.v, v), v)
}

/// The slope of `op` at `x`, where its value is `v`: the chain rule's
/// factor for the argument's gradient.
#[inline(always)]
fn unary_slope(op: Unary, x: f64, v: f64) -> f64 {
    match op {
        Unary::Neg => -1.0,
        Unary::Abs => {
            if x < 0.0 {
                -1.0
            } else {
                1.0
            }
        }
        // At 0 the slope is infinite; when the argument is a sum of squares
        // its own gradient is 0 there, and 0 (a subgradient) keeps the
        // product finite instead of inf * 0 = NaN.
        Unary::Sqrt => {
            if v == 0.0 {
                0.0
            } else {
                0.5 / v
            }
        }
        Unary::Square => 2.0 * x,
        Unary::Sin => x.cos(),
        Unary::Cos => -x.sin(),
        Unary::Tan => 1.0 + v * v,
        Unary::Asin => 1.0 / (1.0 - x * x).sqrt(),
        Unary::Acos => -1.0 / (1.0 - x * x).sqrt(),
        Unary::Atan => 1.0 / (1.0 + x * x),
        Unary::Exp => v,
        Unary::Ln => 1.0 / x,
        Unary::Floor | Unary::Ceil | Unary::Round | Unary::Not => 0.0,
    }
}

#[inline(always)]
fn grad_binary(op: Binary, a: Grad, b: Grad) -> Grad {
    let v = binary(op, a.v, b.v);
    let lin = |ka: f64, kb: f64| Grad {
        v,
        d: std::array::from_fn(|i| ka * a.d[i] + kb * b.d[i]),
    };
    match op {
        Binary::Add => lin(1.0, 1.0),
        Binary::Sub => lin(1.0, -1.0),
        Binary::Mul => lin(b.v, a.v),
        Binary::Div => lin(1.0 / b.v, -a.v / (b.v * b.v)),
        Binary::Min => {
            if a.v <= b.v {
                Grad { v, ..a }
            } else {
                Grad { v, ..b }
            }
        }
        Binary::Max => {
            if a.v >= b.v {
                Grad { v, ..a }
            } else {
                Grad { v, ..b }
            }
        }
        Binary::Atan2 => {
            let r2 = a.v * a.v + b.v * b.v;
            lin(b.v / r2, -a.v / r2)
        }
        Binary::Mod => lin(1.0, -(a.v / b.v).floor()),
        Binary::Compare => Grad { v, d: [0.0; 3] },
        Binary::And => {
            if a.v == 0.0 {
                Grad { v, ..a }
            } else {
                Grad { v, ..b }
            }
        }
        Binary::Or => {
            if a.v != 0.0 {
                Grad { v, ..a }
            } else {
                Grad { v, ..b }
            }
        }
    }
}

/// A dataset at space-mapped arguments: its gradient by the chain rule.
fn grad_dataset(set: &Dataset, args: [Grad; 3]) -> Grad {
    let (v, g) = set.value_gradient(args.map(|a| a.v));
    Grad {
        v,
        d: std::array::from_fn(|k| (0..3).map(|j| g[j] * args[j].d[k]).sum()),
    }
}

/// Evaluates value and exact gradient (forward-mode automatic differentiation).
pub struct GradEval<'t> {
    tape: &'t Tape,
    regs: Vec<Grad>,
}

impl<'t> GradEval<'t> {
    pub fn new(tape: &'t Tape) -> GradEval<'t> {
        GradEval {
            tape,
            regs: spare_file(&SPARE_POINT_GRAD_REGS, tape.slots()),
        }
    }

    pub fn eval(&mut self, p: [f64; 3]) -> Grad {
        let r = &mut self.regs;
        for ins in self.tape.instrs() {
            match *ins {
                Instr::Var { out, axis } => {
                    let mut d = [0.0; 3];
                    d[axis as usize] = 1.0;
                    r[out as usize] = Grad {
                        v: p[axis as usize],
                        d,
                    };
                }
                Instr::Const { out, value } => {
                    r[out as usize] = Grad {
                        v: value,
                        d: [0.0; 3],
                    }
                }
                Instr::Unary { op, out, a } => r[out as usize] = grad_unary(op, r[a as usize]),
                Instr::Binary { op, out, a, b } => {
                    r[out as usize] = grad_binary(op, r[a as usize], r[b as usize])
                }
                Instr::Dataset { set, out, x, y, z } => {
                    let args = [r[x as usize], r[y as usize], r[z as usize]];
                    r[out as usize] = grad_dataset(self.tape.dataset(set), args)
                }
            }
        }
        r[self.tape.output()]
    }
}

thread_local! {
    /// Register files of dropped batch evaluators, for the next ones made
    /// on this thread: the mesher makes several per brick, and zeroing a
    /// fresh file of `LANES` lanes per register for a few dozen crossings
    /// was 13% of all its instructions (colonnade at depth 6, callgrind). A
    /// file's old contents are never read: a tape writes each register
    /// before it reads it.
    static SPARE_REGS: RefCell<Vec<Vec<f32>>> = const { RefCell::new(Vec::new()) };
    static SPARE_GRAD_REGS: RefCell<Vec<Vec<batch_grad::Block>>> = const { RefCell::new(Vec::new()) };
    /// Likewise for the one-point evaluators: the mesher makes one per
    /// leaf it fits and per feature it recovers, each a fresh allocation
    /// before.
    static SPARE_POINT_REGS: RefCell<Vec<Vec<f64>>> = const { RefCell::new(Vec::new()) };
    static SPARE_POINT_GRAD_REGS: RefCell<Vec<Vec<Grad>>> = const { RefCell::new(Vec::new()) };
}

/// Spare register files kept per thread and kind (evaluators alive at
/// once: a brick's and its feature recovery's), each of at most
/// `SPARE_BYTES` (a brick's tape needs far less; a whole large tape's file
/// is not worth holding on to).
const SPARE_FILES: usize = 4;
const SPARE_BYTES: usize = 1 << 20;

pub(crate) type Spares<T> = std::thread::LocalKey<RefCell<Vec<Vec<T>>>>;

/// A spare register file of this thread (or a new one), of at least `need`.
pub(crate) fn spare_file<T: Clone + Default>(spares: &'static Spares<T>, need: usize) -> Vec<T> {
    let mut regs = spares.with(|s| s.borrow_mut().pop()).unwrap_or_default();
    grow_file(&mut regs, need);
    regs
}

/// Grows a register file to at least `need` (never shrinks: a smaller tape
/// uses a prefix).
fn grow_file<T: Clone + Default>(regs: &mut Vec<T>, need: usize) {
    if regs.len() < need {
        regs.resize(need, T::default());
    }
}

/// Keeps a dropped evaluator's register file for the next one.
pub(crate) fn keep_file<T>(spares: &'static Spares<T>, regs: Vec<T>) {
    spares.with(|s| {
        let mut s = s.borrow_mut();
        if s.len() < SPARE_FILES && std::mem::size_of_val(regs.as_slice()) <= SPARE_BYTES {
            s.push(regs);
        }
    });
}

impl Drop for PointEval<'_> {
    fn drop(&mut self) {
        keep_file(&SPARE_POINT_REGS, std::mem::take(&mut self.regs));
    }
}

impl Drop for GradEval<'_> {
    fn drop(&mut self) {
        keep_file(&SPARE_POINT_GRAD_REGS, std::mem::take(&mut self.regs));
    }
}

impl Drop for BatchEval<'_> {
    fn drop(&mut self) {
        keep_file(&SPARE_REGS, std::mem::take(&mut self.regs));
    }
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;
    use crate::field::Field;

    /// Every operation on an argument that sweeps its domain.
    fn tapes() -> Vec<Tape> {
        let (x, y, z) = (Field::x(), Field::y(), Field::z());
        let smooth = &x * 0.7 + &y * 0.3 - &z * 0.2;
        let unary = Unary::ALL.map(|op| smooth.unary(op));
        let binary = Binary::ALL.map(|op| smooth.binary(op, &y - &z * 0.5));
        unary.iter().chain(&binary).map(Tape::compile).collect()
    }

    /// Seeded points in [-2, 2]^3, with zeros and halves among them (where
    /// rounding, signs and steps decide).
    fn points(n: usize) -> Vec<[f64; 3]> {
        let mut s: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let t = (s >> 11) as f64 / (1u64 << 53) as f64 * 4.0 - 2.0;
            if s.is_multiple_of(7) {
                (t * 2.0).round() * 0.5
            } else {
                t
            }
        };
        (0..n).map(|_| [next(), next(), next()]).collect()
    }

    /// The AVX2 build of each batch evaluator gives the baseline's bits
    /// (blocks of 1, 37 and a full block and a half).
    #[test]
    fn avx2_and_baseline_agree_bit_for_bit() {
        if !std::arch::is_x86_feature_detected!("avx2") {
            return;
        }
        let pts = points(LANES + LANES / 2);
        let [xs, ys, zs] = [0, 1, 2].map(|k| pts.iter().map(|p| p[k] as f32).collect::<Vec<_>>());
        for tape in tapes() {
            for n in [1, 37, pts.len()] {
                let (mut any, mut avx) = (BatchEval::new(&tape), BatchEval::new(&tape));
                let len = n.min(LANES);
                let axes = [&xs[..len], &ys[..len], &zs[..len]];
                any.block_any(axes, len);
                // SAFETY: the CPU has AVX2, checked above.
                unsafe { avx.block_avx2(axes, len) };
                let o = tape.output() * LANES;
                let bits = |e: &BatchEval| {
                    e.regs[o..o + len]
                        .iter()
                        .map(|v| v.to_bits())
                        .collect::<Vec<_>>()
                };
                assert_eq!(bits(&any), bits(&avx), "values, {n} points");

                let mut g_any = vec![Grad::default(); n];
                let mut g_avx = vec![Grad::default(); n];
                BatchGradEval::new(&tape).eval_any(&pts[..n], &mut g_any);
                // SAFETY: as above.
                unsafe { BatchGradEval::new(&tape).eval_avx2(&pts[..n], &mut g_avx) };
                let bits = |g: &[Grad]| {
                    g.iter()
                        .flat_map(|g| [g.v, g.d[0], g.d[1], g.d[2]].map(f64::to_bits))
                        .collect::<Vec<_>>()
                };
                assert_eq!(bits(&g_any), bits(&g_avx), "gradients, {n} points");
            }
        }
    }
}
