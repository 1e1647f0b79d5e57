//! The batch interpreter: runs a program's instructions over `LANES`
//! elements at a time. Every instruction is a tight loop over the lanes of
//! its registers; the lowering guarantees a destination never aliases its
//! sources, so each loop borrows one mutable and some shared registers.

use super::call;
use super::rules::{compare, fbin1, fun1, ibin1, iun1};
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
    /// Each call site's arguments for one lane, kept from call to call
    /// (a literal argument stays in place).
    pub args: Vec<Vec<crate::value::Val>>,
}

impl Frame {
    pub fn new(p: &Program) -> Frame {
        let c = &p.counts;
        let mut fr = Frame {
            n: 0,
            w: 0,
            f: vec![0.0; c.f as usize * LANES],
            i: vec![0; c.i as usize * LANES],
            s: vec![String::new(); c.s as usize * LANES],
            af: vec![Vec::new(); c.af as usize * LANES],
            ai: vec![Vec::new(); c.ai as usize * LANES],
            as_: vec![Vec::new(); c.as_ as usize * LANES],
            held: 0,
            args: vec![Vec::new(); p.calls.len()],
        };
        // The constant pool, set once: nothing writes its registers.
        let (f0, floats) = &p.constants.floats;
        for (k, v) in floats.iter().enumerate() {
            fr.f[(*f0 as usize + k) * LANES..][..LANES].fill(*v);
        }
        let (i0, ints) = &p.constants.ints;
        for (k, v) in ints.iter().enumerate() {
            fr.i[(*i0 as usize + k) * LANES..][..LANES].fill(*v);
        }
        fr
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
        ($op:expr) => {
            for ((o, &p), &q) in x.iter_mut().zip(a).zip(b) {
                *o = fbin1($op, p, q);
            }
        };
    }
    match op {
        FBinOp::Add => each!(FBinOp::Add),
        FBinOp::Sub => each!(FBinOp::Sub),
        FBinOp::Mul => each!(FBinOp::Mul),
        FBinOp::Div => each!(FBinOp::Div),
        FBinOp::Mod => each!(FBinOp::Mod),
        FBinOp::Pow => each!(FBinOp::Pow),
        FBinOp::Min => each!(FBinOp::Min),
        FBinOp::Max => each!(FBinOp::Max),
        FBinOp::Atan2 => each!(FBinOp::Atan2),
    }
}

fn fun(op: FUnOp, x: &mut [f32], a: &[f32]) {
    // Transcendental loops do not vectorise; the arms that do are the
    // cheap ones, each with its operator constant.
    macro_rules! each {
        ($op:expr) => {
            for (o, &p) in x.iter_mut().zip(a) {
                *o = fun1($op, p);
            }
        };
    }
    match op {
        FUnOp::Neg => each!(FUnOp::Neg),
        FUnOp::Abs => each!(FUnOp::Abs),
        FUnOp::Sqrt => each!(FUnOp::Sqrt),
        FUnOp::Floor => each!(FUnOp::Floor),
        FUnOp::Ceil => each!(FUnOp::Ceil),
        FUnOp::Frac => each!(FUnOp::Frac),
        FUnOp::Rint => each!(FUnOp::Rint),
        FUnOp::Trunc => each!(FUnOp::Trunc),
        FUnOp::Sign => each!(FUnOp::Sign),
        FUnOp::Radians => each!(FUnOp::Radians),
        FUnOp::Degrees => each!(FUnOp::Degrees),
        other => each!(other),
    }
}

fn ibin(op: IBinOp, x: &mut [i32], a: &[i32], b: &[i32]) {
    macro_rules! each {
        ($op:expr) => {
            for ((o, &p), &q) in x.iter_mut().zip(a).zip(b) {
                *o = ibin1($op, p, q);
            }
        };
    }
    match op {
        IBinOp::Add => each!(IBinOp::Add),
        IBinOp::Sub => each!(IBinOp::Sub),
        IBinOp::Mul => each!(IBinOp::Mul),
        IBinOp::LAnd => each!(IBinOp::LAnd),
        IBinOp::LOr => each!(IBinOp::LOr),
        IBinOp::AndNot => each!(IBinOp::AndNot),
        IBinOp::And => each!(IBinOp::And),
        IBinOp::Or => each!(IBinOp::Or),
        other => each!(other),
    }
}

fn iun(op: IUnOp, x: &mut [i32], a: &[i32]) {
    for (o, &p) in x.iter_mut().zip(a) {
        *o = iun1(op, p);
    }
}

/// Whether `a op b` holds on any of the batch's `n` lanes (at least one).
fn any_lane<T: PartialOrd>(op: Cmp, file: &[T], a: Reg, b: Reg, n: usize) -> bool {
    let lanes = |r: Reg| &file[r as usize * LANES..][..n.max(1)];
    lanes(a)
        .iter()
        .zip(lanes(b))
        .any(|(p, q)| compare(op, p, q) != 0)
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

/// Interpreter state that outlives one instruction.
pub(super) struct Exec {
    /// Loop back edges taken (every 64th polls cancellation).
    pub polls: u32,
    /// A mask's lanes, copied out of the register file it selects in.
    masks: [i32; LANES],
}

/// Runs `p` on the batch in `fr`. `world` holds the geometry the library
/// reads and the effects it queues. A batch of one lane (a detail run, a
/// parameter expression) runs its numeric instructions and jumps on the
/// one-lane path, with the same rules.
pub fn run(p: &Program, fr: &mut Frame, world: &mut World) -> Result<(), RunError> {
    debug_assert!(!p.uniform || fr.w == 1, "a uniform program runs one lane");
    let mut st = Exec {
        polls: 0,
        masks: [0; LANES],
    };
    let mut pc = 0usize;
    let one_lane = fr.w == 1;
    while pc < p.ops.len() {
        if one_lane {
            pc = super::scalar::run_until_batch(&p.ops, pc, &mut fr.f, &mut fr.i, &mut st.polls);
            if pc >= p.ops.len() {
                break;
            }
        }
        pc = step(p, pc, fr, world, &mut st)?;
    }
    Ok(())
}

/// Runs the instruction at `pc` over the batch's lanes; returns the next.
pub(super) fn step(
    p: &Program,
    pc: usize,
    fr: &mut Frame,
    world: &mut World,
    st: &mut Exec,
) -> Result<usize, RunError> {
    let op = &p.ops[pc];
    let w = fr.w;
    let masks = &mut st.masks;
    match op {
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
        Op::Call { call } => call::call(p, *call as usize, fr, world)?,
        Op::Jump { to } => return Ok(*to as usize),
        Op::JumpIfNone { m, to } => {
            if !fr.il(*m)[..fr.n].iter().any(|&k| k != 0) {
                return Ok(*to as usize);
            }
        }
        Op::JumpUnlessI { op, a, b, to } => {
            if !any_lane(*op, &fr.i, *a, *b, fr.n) {
                return Ok(*to as usize);
            }
        }
        Op::JumpUnlessF { op, a, b, to } => {
            if !any_lane(*op, &fr.f, *a, *b, fr.n) {
                return Ok(*to as usize);
            }
        }
        Op::Back { to } => {
            st.polls = st.polls.wrapping_add(1);
            if st.polls.is_multiple_of(64) {
                if (world.cancel)() {
                    return Err(RunError::Cancelled);
                }
                super::budget::true_up(&world.shared.budget, fr);
            }
            return Ok(*to as usize);
        }
    }
    Ok(pc + 1)
}
