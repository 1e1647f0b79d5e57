//! The batch interpreter: runs a program's instructions over `LANES`
//! elements at a time. Every instruction is a tight loop over the lanes of
//! its registers; the lowering guarantees a destination never aliases its
//! sources, so each loop borrows one mutable and some shared registers.

use super::call;
use super::world::World;
use crate::error::RunError;
use crate::ir::*;
use crate::program::Program;

/// One batch's registers.
pub struct Frame {
    /// Lanes holding elements (the rest compute but are never stored).
    pub n: usize,
    /// Lanes each instruction computes: the elements' lanes, so a detail
    /// run (one element) computes one lane, not a whole batch.
    pub w: usize,
    pub f: Vec<f32>,
    pub i: Vec<i32>,
    pub s: Vec<String>,
    pub af: Vec<Vec<f32>>,
    pub ai: Vec<Vec<i32>>,
    pub as_: Vec<Vec<String>>,
    /// Bytes this frame has charged to the run's memory budget.
    pub held: u64,
}

impl Frame {
    pub fn new(p: &Program) -> Frame {
        let c = &p.counts;
        Frame {
            n: 0,
            w: 0,
            f: vec![0.0; c.f as usize * LANES],
            i: vec![0; c.i as usize * LANES],
            s: vec![String::new(); c.s as usize * LANES],
            af: vec![Vec::new(); c.af as usize * LANES],
            ai: vec![Vec::new(); c.ai as usize * LANES],
            as_: vec![Vec::new(); c.as_ as usize * LANES],
            held: 0,
        }
    }

    pub fn il(&self, r: Reg) -> &[i32] {
        &self.i[r as usize * LANES..][..self.w]
    }

    /// Sets the number of elements the batch holds.
    pub fn set_lanes(&mut self, n: usize) {
        self.n = n;
        self.w = n.clamp(1, LANES);
    }
}

/// The destination register mutably and any other register shared.
struct Split<'a, T> {
    lo: &'a [T],
    hi: &'a [T],
    d: usize,
    w: usize,
}

impl<'a, T> Split<'a, T> {
    fn new(file: &'a mut [T], d: Reg, w: usize) -> (&'a mut [T], Split<'a, T>) {
        let d = d as usize;
        let (lo, rest) = file.split_at_mut(d * LANES);
        let (dst, hi) = rest.split_at_mut(LANES);
        (&mut dst[..w], Split { lo, hi, d, w })
    }

    fn get(&self, r: Reg) -> &'a [T] {
        let r = r as usize;
        debug_assert_ne!(r, self.d, "a destination aliases a source");
        if r < self.d {
            &self.lo[r * LANES..][..self.w]
        } else {
            &self.hi[(r - self.d - 1) * LANES..][..self.w]
        }
    }
}

fn fbin(op: FBinOp, x: &mut [f32], a: &[f32], b: &[f32]) {
    macro_rules! each {
        ($f:expr) => {
            for ((o, &p), &q) in x.iter_mut().zip(a).zip(b) {
                *o = $f(p, q);
            }
        };
    }
    match op {
        FBinOp::Add => each!(|p: f32, q: f32| p + q),
        FBinOp::Sub => each!(|p: f32, q: f32| p - q),
        FBinOp::Mul => each!(|p: f32, q: f32| p * q),
        FBinOp::Div => each!(|p: f32, q: f32| if q == 0.0 { 0.0 } else { p / q }),
        FBinOp::Mod => each!(|p: f32, q: f32| if q == 0.0 { 0.0 } else { p % q }),
        FBinOp::Pow => each!(|p: f32, q: f32| p.powf(q)),
        FBinOp::Min => each!(|p: f32, q: f32| p.min(q)),
        FBinOp::Max => each!(|p: f32, q: f32| p.max(q)),
        FBinOp::Atan2 => each!(|p: f32, q: f32| p.atan2(q)),
    }
}

fn fun(op: FUnOp, x: &mut [f32], a: &[f32]) {
    macro_rules! each {
        ($f:expr) => {
            for (o, &p) in x.iter_mut().zip(a) {
                *o = $f(p);
            }
        };
    }
    match op {
        FUnOp::Neg => each!(|p: f32| -p),
        FUnOp::Abs => each!(f32::abs),
        FUnOp::Sqrt => each!(|p: f32| if p > 0.0 { p.sqrt() } else { 0.0 }),
        FUnOp::Sin => each!(f32::sin),
        FUnOp::Cos => each!(f32::cos),
        FUnOp::Tan => each!(f32::tan),
        FUnOp::Asin => each!(|p: f32| p.clamp(-1.0, 1.0).asin()),
        FUnOp::Acos => each!(|p: f32| p.clamp(-1.0, 1.0).acos()),
        FUnOp::Atan => each!(f32::atan),
        FUnOp::Sinh => each!(f32::sinh),
        FUnOp::Cosh => each!(f32::cosh),
        FUnOp::Tanh => each!(f32::tanh),
        FUnOp::Exp => each!(f32::exp),
        FUnOp::Log => each!(|p: f32| if p > 0.0 { p.ln() } else { 0.0 }),
        FUnOp::Log10 => each!(|p: f32| if p > 0.0 { p.log10() } else { 0.0 }),
        FUnOp::Floor => each!(f32::floor),
        FUnOp::Ceil => each!(f32::ceil),
        FUnOp::Frac => each!(|p: f32| p - p.floor()),
        FUnOp::Rint => each!(|p: f32| p.round()),
        FUnOp::Trunc => each!(f32::trunc),
        FUnOp::Sign => each!(|p: f32| if p > 0.0 {
            1.0
        } else if p < 0.0 {
            -1.0
        } else {
            0.0
        }),
        FUnOp::Radians => each!(f32::to_radians),
        FUnOp::Degrees => each!(f32::to_degrees),
    }
}

fn ibin(op: IBinOp, x: &mut [i32], a: &[i32], b: &[i32]) {
    macro_rules! each {
        ($f:expr) => {
            for ((o, &p), &q) in x.iter_mut().zip(a).zip(b) {
                *o = $f(p, q);
            }
        };
    }
    match op {
        IBinOp::Add => each!(|p: i32, q: i32| p.wrapping_add(q)),
        IBinOp::Sub => each!(|p: i32, q: i32| p.wrapping_sub(q)),
        IBinOp::Mul => each!(|p: i32, q: i32| p.wrapping_mul(q)),
        IBinOp::Div => each!(|p: i32, q: i32| if q == 0 { 0 } else { p.wrapping_div(q) }),
        IBinOp::Mod => each!(|p: i32, q: i32| if q == 0 { 0 } else { p.wrapping_rem(q) }),
        IBinOp::And => each!(|p: i32, q: i32| p & q),
        IBinOp::Or => each!(|p: i32, q: i32| p | q),
        IBinOp::Xor => each!(|p: i32, q: i32| p ^ q),
        IBinOp::Shl => each!(|p: i32, q: i32| p.wrapping_shl(q as u32)),
        IBinOp::Shr => each!(|p: i32, q: i32| p.wrapping_shr(q as u32)),
        IBinOp::Min => each!(|p: i32, q: i32| p.min(q)),
        IBinOp::Max => each!(|p: i32, q: i32| p.max(q)),
        IBinOp::LAnd => each!(|p: i32, q: i32| i32::from(p != 0 && q != 0)),
        IBinOp::LOr => each!(|p: i32, q: i32| i32::from(p != 0 || q != 0)),
        IBinOp::AndNot => each!(|p: i32, q: i32| i32::from(p != 0 && q == 0)),
    }
}

fn iun(op: IUnOp, x: &mut [i32], a: &[i32]) {
    for (o, &p) in x.iter_mut().zip(a) {
        *o = match op {
            IUnOp::Neg => p.wrapping_neg(),
            IUnOp::Not => i32::from(p == 0),
            IUnOp::BitNot => !p,
            IUnOp::Abs => p.wrapping_abs(),
            IUnOp::Truth => i32::from(p != 0),
        };
    }
}

fn compare<T: PartialOrd>(op: Cmp, a: &T, b: &T) -> i32 {
    i32::from(match op {
        Cmp::Lt => a < b,
        Cmp::Le => a <= b,
        Cmp::Gt => a > b,
        Cmp::Ge => a >= b,
        Cmp::Eq => a == b,
        Cmp::Ne => a != b,
    })
}

fn sel<T: Clone>(file: &mut [T], d: Reg, s: Reg, m: &[i32]) {
    let (x, src) = Split::new(file, d, m.len());
    for ((o, v), &k) in x.iter_mut().zip(src.get(s)).zip(m) {
        if k != 0 {
            o.clone_from(v);
        }
    }
}

fn mov<T: Clone>(file: &mut [T], d: Reg, s: Reg, w: usize) {
    let (x, src) = Split::new(file, d, w);
    x.clone_from_slice(src.get(s));
}

/// A register file whose values live on the heap.
#[derive(Clone, Copy)]
enum Heap {
    S,
    A(ArrFile),
}

/// Bytes register `r` of `file` holds on the heap over the batch's lanes.
fn reg_bytes(fr: &Frame, file: Heap, r: Reg) -> u64 {
    use super::budget::slots_bytes;
    let lanes = r as usize * LANES..r as usize * LANES + fr.w;
    match file {
        Heap::S => slots_bytes(&fr.s[lanes]),
        Heap::A(ArrFile::F) => slots_bytes(&fr.af[lanes]),
        Heap::A(ArrFile::I) => slots_bytes(&fr.ai[lanes]),
        Heap::A(ArrFile::S) => slots_bytes(&fr.as_[lanes]),
    }
}

/// Copies register `s` of a heap file into `d` with `copy`, reserving
/// the copy against the budget first (refused at the statement that makes
/// it) and charging what the destination gains.
#[allow(clippy::too_many_arguments)]
fn copy_charged(
    p: &Program,
    pc: usize,
    fr: &mut Frame,
    world: &World,
    file: Heap,
    d: Reg,
    s: Reg,
    copy: impl FnOnce(&mut Frame),
) -> Result<(), RunError> {
    let budget = &world.shared.budget;
    let before = reg_bytes(fr, file, d);
    let copied = reg_bytes(fr, file, s);
    if !super::budget::reserve(budget, fr, copied) {
        return Err(RunError::OverBudget {
            elem: world.elem_of(0),
            pos: p.op_pos.get(pc).copied().unwrap_or_default(),
            msg: budget.refusal("copying a value", copied),
        });
    }
    copy(fr);
    let after = reg_bytes(fr, file, d);
    super::budget::charge_write(budget, fr, before, after);
    Ok(())
}

/// Runs `p` on the batch in `fr`. `world` holds the geometry the library
/// reads and the effects it queues.
pub fn run(p: &Program, fr: &mut Frame, world: &mut World) -> Result<(), RunError> {
    let mut pc = 0usize;
    let mut polls = 0u32;
    let mut masks = [0i32; LANES];
    let w = fr.w;
    while pc < p.ops.len() {
        match &p.ops[pc] {
            Op::FConst { d, v } => fr.f[*d as usize * LANES..][..w].fill(*v),
            Op::IConst { d, v } => fr.i[*d as usize * LANES..][..w].fill(*v),
            Op::SConst { d, s } => {
                for o in &mut fr.s[*d as usize * LANES..][..w] {
                    o.clone_from(&p.strings[*s as usize]);
                }
            }
            Op::FMov { d, s } => mov(&mut fr.f, *d, *s, w),
            Op::IMov { d, s } => mov(&mut fr.i, *d, *s, w),
            Op::SMov { d, s } => copy_charged(p, pc, fr, world, Heap::S, *d, *s, |fr| {
                mov(&mut fr.s, *d, *s, w)
            })?,
            Op::AMov { file, d, s } => {
                copy_charged(p, pc, fr, world, Heap::A(*file), *d, *s, |fr| match file {
                    ArrFile::F => mov(&mut fr.af, *d, *s, w),
                    ArrFile::I => mov(&mut fr.ai, *d, *s, w),
                    ArrFile::S => mov(&mut fr.as_, *d, *s, w),
                })?
            }
            Op::FSel { d, s, m } => {
                masks[..w].copy_from_slice(fr.il(*m));
                sel(&mut fr.f, *d, *s, &masks[..w]);
            }
            Op::ISel { d, s, m } => {
                masks[..w].copy_from_slice(fr.il(*m));
                sel(&mut fr.i, *d, *s, &masks[..w]);
            }
            Op::SSel { d, s, m } => {
                masks[..w].copy_from_slice(fr.il(*m));
                copy_charged(p, pc, fr, world, Heap::S, *d, *s, |fr| {
                    sel(&mut fr.s, *d, *s, &masks[..w])
                })?;
            }
            Op::ASel { file, d, s, m } => {
                masks[..w].copy_from_slice(fr.il(*m));
                copy_charged(p, pc, fr, world, Heap::A(*file), *d, *s, |fr| match file {
                    ArrFile::F => sel(&mut fr.af, *d, *s, &masks[..w]),
                    ArrFile::I => sel(&mut fr.ai, *d, *s, &masks[..w]),
                    ArrFile::S => sel(&mut fr.as_, *d, *s, &masks[..w]),
                })?;
            }
            Op::FBin { op, d, a, b } => {
                let (x, src) = Split::new(&mut fr.f, *d, w);
                fbin(*op, x, src.get(*a), src.get(*b));
            }
            Op::FUn { op, d, a } => {
                let (x, src) = Split::new(&mut fr.f, *d, w);
                fun(*op, x, src.get(*a));
            }
            Op::IBin { op, d, a, b } => {
                let (x, src) = Split::new(&mut fr.i, *d, w);
                ibin(*op, x, src.get(*a), src.get(*b));
            }
            Op::IUn { op, d, a } => {
                let (x, src) = Split::new(&mut fr.i, *d, w);
                iun(*op, x, src.get(*a));
            }
            Op::FCmp { op, d, a, b } => {
                let (a, b) = (
                    &fr.f[*a as usize * LANES..][..w],
                    &fr.f[*b as usize * LANES..][..w],
                );
                let x = &mut fr.i[*d as usize * LANES..][..w];
                for l in 0..w {
                    x[l] = compare(*op, &a[l], &b[l]);
                }
            }
            Op::ICmp { op, d, a, b } => {
                let (x, src) = Split::new(&mut fr.i, *d, w);
                let (a, b) = (src.get(*a), src.get(*b));
                for l in 0..w {
                    x[l] = compare(*op, &a[l], &b[l]);
                }
            }
            Op::SCmp { op, d, a, b } => {
                let x = &mut fr.i[*d as usize * LANES..][..w];
                let (a, b) = (
                    &fr.s[*a as usize * LANES..][..w],
                    &fr.s[*b as usize * LANES..][..w],
                );
                for l in 0..w {
                    x[l] = compare(*op, &a[l], &b[l]);
                }
            }
            Op::IToF { d, s } => {
                let a = &fr.i[*s as usize * LANES..][..w];
                let x = &mut fr.f[*d as usize * LANES..][..w];
                for l in 0..w {
                    x[l] = a[l] as f32;
                }
            }
            Op::FToI { d, s } => {
                let a = &fr.f[*s as usize * LANES..][..w];
                let x = &mut fr.i[*d as usize * LANES..][..w];
                for l in 0..w {
                    x[l] = a[l] as i32;
                }
            }
            Op::Call { call } => call::call(p, &p.calls[*call as usize], fr, world)?,
            Op::Jump { to } => {
                pc = *to as usize;
                continue;
            }
            Op::JumpIfNone { m, to } => {
                if !fr.il(*m)[..fr.n].iter().any(|&k| k != 0) {
                    pc = *to as usize;
                    continue;
                }
            }
            Op::Poll => {
                polls = polls.wrapping_add(1);
                if polls.is_multiple_of(64) {
                    if (world.cancel)() {
                        return Err(RunError::Cancelled);
                    }
                    super::budget::true_up(&world.shared.budget, fr);
                }
            }
        }
        pc += 1;
    }
    Ok(())
}
