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
    /// A loop's back edge: polls cancellation.
    Poll,
}

/// A value's registers: floats from `reg` on (`ty.floats()` of them), or
/// one int, string or array register.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Loc {
    pub ty: crate::ty::Ty,
    pub reg: Reg,
}
