//! The typed batch IR: every instruction applies to all lanes of a batch
//! (`LANES` elements at once) over register files of floats, ints, strings
//! and arrays. Control flow is masks (int registers of 0/1) and jumps taken
//! when no lane is left, so a batch runs in lockstep.

/// Elements per batch: large enough that dispatch vanishes, small enough
/// that a snippet's registers stay in cache.
pub const LANES: usize = 256;

/// Register index in one file.
pub type Reg = u32;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FBinOp {
    Add,
    Sub,
    Mul,
    /// Division; VEX gives 0 for a zero divisor.
    Div,
    /// `%` on floats: C's fmod.
    Mod,
    Pow,
    Min,
    Max,
    Atan2,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FUnOp {
    Neg,
    Abs,
    Sqrt,
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
    Exp,
    Log,
    Log10,
    Floor,
    Ceil,
    Frac,
    Rint,
    Trunc,
    Sign,
    Radians,
    Degrees,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IBinOp {
    Add,
    Sub,
    Mul,
    Div,
    Mod,
    And,
    Or,
    Xor,
    Shl,
    Shr,
    Min,
    Max,
    /// Logical and/or on 0/1 masks and truth values.
    LAnd,
    LOr,
    /// `a & !b`: lanes of `a` not in `b`.
    AndNot,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IUnOp {
    Neg,
    Not,
    BitNot,
    Abs,
    /// 1 where non-zero.
    Truth,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cmp {
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
}

/// Which array file an array register lives in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArrFile {
    /// Float-based elements, flattened (`width` floats each).
    F,
    I,
    S,
}

#[derive(Clone, Debug)]
pub enum Op {
    FConst {
        d: Reg,
        v: f32,
    },
    IConst {
        d: Reg,
        v: i32,
    },
    SConst {
        d: Reg,
        s: u32,
    },
    FMov {
        d: Reg,
        s: Reg,
    },
    IMov {
        d: Reg,
        s: Reg,
    },
    SMov {
        d: Reg,
        s: Reg,
    },
    AMov {
        file: ArrFile,
        d: Reg,
        s: Reg,
    },
    /// `d = m ? s : d` per lane.
    FSel {
        d: Reg,
        s: Reg,
        m: Reg,
    },
    ISel {
        d: Reg,
        s: Reg,
        m: Reg,
    },
    SSel {
        d: Reg,
        s: Reg,
        m: Reg,
    },
    ASel {
        file: ArrFile,
        d: Reg,
        s: Reg,
        m: Reg,
    },
    FBin {
        op: FBinOp,
        d: Reg,
        a: Reg,
        b: Reg,
    },
    FUn {
        op: FUnOp,
        d: Reg,
        a: Reg,
    },
    IBin {
        op: IBinOp,
        d: Reg,
        a: Reg,
        b: Reg,
    },
    IUn {
        op: IUnOp,
        d: Reg,
        a: Reg,
    },
    FCmp {
        op: Cmp,
        d: Reg,
        a: Reg,
        b: Reg,
    },
    ICmp {
        op: Cmp,
        d: Reg,
        a: Reg,
        b: Reg,
    },
    SCmp {
        op: Cmp,
        d: Reg,
        a: Reg,
        b: Reg,
    },
    IToF {
        d: Reg,
        s: Reg,
    },
    /// Truncation toward zero, as VEX's int().
    FToI {
        d: Reg,
        s: Reg,
    },
    /// A library function over the batch (arguments and results in
    /// `Program::calls[call]`).
    Call {
        call: u32,
    },
    Jump {
        to: u32,
    },
    /// Jumps when no lane of mask `m` is set.
    JumpIfNone {
        m: Reg,
        to: u32,
    },
    /// `if (!(a op b)) goto to` on a one-lane program's ints: a branch's
    /// comparison and jump in one instruction.
    JumpUnlessI {
        op: Cmp,
        a: Reg,
        b: Reg,
        to: u32,
    },
    /// The same on floats.
    JumpUnlessF {
        op: Cmp,
        a: Reg,
        b: Reg,
        to: u32,
    },
    /// A loop's back edge: polls cancellation, then jumps to the loop's top.
    Back {
        to: u32,
    },
}

impl Op {
    /// Calls `f` on every register the instruction names (of any file),
    /// for passes that renumber registers.
    pub fn for_each_reg(&mut self, mut f: impl FnMut(&mut Reg)) {
        match self {
            Op::FConst { d, .. } | Op::IConst { d, .. } | Op::SConst { d, .. } => f(d),
            Op::FMov { d, s }
            | Op::IMov { d, s }
            | Op::SMov { d, s }
            | Op::AMov { d, s, .. }
            | Op::IToF { d, s }
            | Op::FToI { d, s } => {
                f(d);
                f(s);
            }
            Op::FSel { d, s, m }
            | Op::ISel { d, s, m }
            | Op::SSel { d, s, m }
            | Op::ASel { d, s, m, .. } => {
                f(d);
                f(s);
                f(m);
            }
            Op::FBin { d, a, b, .. }
            | Op::IBin { d, a, b, .. }
            | Op::FCmp { d, a, b, .. }
            | Op::ICmp { d, a, b, .. }
            | Op::SCmp { d, a, b, .. } => {
                f(d);
                f(a);
                f(b);
            }
            Op::FUn { d, a, .. } | Op::IUn { d, a, .. } => {
                f(d);
                f(a);
            }
            Op::JumpIfNone { m, .. } => f(m),
            Op::JumpUnlessI { a, b, .. } | Op::JumpUnlessF { a, b, .. } => {
                f(a);
                f(b);
            }
            Op::Call { .. } | Op::Jump { .. } | Op::Back { .. } => {}
        }
    }

    /// The register the instruction writes, if it writes one.
    pub fn dest(&self) -> Option<Reg> {
        match *self {
            Op::FConst { d, .. }
            | Op::IConst { d, .. }
            | Op::SConst { d, .. }
            | Op::FMov { d, .. }
            | Op::IMov { d, .. }
            | Op::SMov { d, .. }
            | Op::AMov { d, .. }
            | Op::FSel { d, .. }
            | Op::ISel { d, .. }
            | Op::SSel { d, .. }
            | Op::ASel { d, .. }
            | Op::FBin { d, .. }
            | Op::FUn { d, .. }
            | Op::IBin { d, .. }
            | Op::IUn { d, .. }
            | Op::FCmp { d, .. }
            | Op::ICmp { d, .. }
            | Op::SCmp { d, .. }
            | Op::IToF { d, .. }
            | Op::FToI { d, .. } => Some(d),
            Op::Call { .. }
            | Op::Jump { .. }
            | Op::JumpIfNone { .. }
            | Op::JumpUnlessI { .. }
            | Op::JumpUnlessF { .. }
            | Op::Back { .. } => None,
        }
    }

    /// The jump target, for passes that patch jumps.
    pub fn target_mut(&mut self) -> Option<&mut u32> {
        match self {
            Op::Jump { to }
            | Op::JumpIfNone { to, .. }
            | Op::JumpUnlessI { to, .. }
            | Op::JumpUnlessF { to, .. }
            | Op::Back { to } => Some(to),
            _ => None,
        }
    }
}

/// A value's registers: floats from `reg` on (`ty.floats()` of them), or
/// one int, string or array register.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Loc {
    pub ty: crate::ty::Ty,
    pub reg: Reg,
}
