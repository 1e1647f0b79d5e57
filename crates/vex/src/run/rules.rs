//! One lane of each numeric instruction: the rules the batch loops and
//! the one-lane path share, so both compute the same bits.

use crate::ir::*;

/// One lane of a float operation: the rule the batch loops and the scalar
/// path share.
#[inline(always)]
pub(super) fn fbin1(op: FBinOp, p: f32, q: f32) -> f32 {
    match op {
        FBinOp::Add => p + q,
        FBinOp::Sub => p - q,
        FBinOp::Mul => p * q,
        FBinOp::Div => {
            if q == 0.0 {
                0.0
            } else {
                p / q
            }
        }
        FBinOp::Mod => {
            if q == 0.0 {
                0.0
            } else {
                p % q
            }
        }
        FBinOp::Pow => p.powf(q),
        FBinOp::Min => p.min(q),
        FBinOp::Max => p.max(q),
        FBinOp::Atan2 => p.atan2(q),
    }
}

#[inline(always)]
pub(super) fn fun1(op: FUnOp, p: f32) -> f32 {
    match op {
        FUnOp::Neg => -p,
        FUnOp::Abs => p.abs(),
        FUnOp::Sqrt => {
            if p > 0.0 {
                p.sqrt()
            } else {
                0.0
            }
        }
        FUnOp::Sin => p.sin(),
        FUnOp::Cos => p.cos(),
        FUnOp::Tan => p.tan(),
        FUnOp::Asin => p.clamp(-1.0, 1.0).asin(),
        FUnOp::Acos => p.clamp(-1.0, 1.0).acos(),
        FUnOp::Atan => p.atan(),
        FUnOp::Sinh => p.sinh(),
        FUnOp::Cosh => p.cosh(),
        FUnOp::Tanh => p.tanh(),
        FUnOp::Exp => p.exp(),
        FUnOp::Log => {
            if p > 0.0 {
                p.ln()
            } else {
                0.0
            }
        }
        FUnOp::Log10 => {
            if p > 0.0 {
                p.log10()
            } else {
                0.0
            }
        }
        FUnOp::Floor => p.floor(),
        FUnOp::Ceil => p.ceil(),
        FUnOp::Frac => p - p.floor(),
        FUnOp::Rint => p.round(),
        FUnOp::Trunc => p.trunc(),
        FUnOp::Sign => {
            if p > 0.0 {
                1.0
            } else if p < 0.0 {
                -1.0
            } else {
                0.0
            }
        }
        FUnOp::Radians => p.to_radians(),
        FUnOp::Degrees => p.to_degrees(),
    }
}

#[inline(always)]
pub(super) fn ibin1(op: IBinOp, p: i32, q: i32) -> i32 {
    match op {
        IBinOp::Add => p.wrapping_add(q),
        IBinOp::Sub => p.wrapping_sub(q),
        IBinOp::Mul => p.wrapping_mul(q),
        IBinOp::Div => {
            if q == 0 {
                0
            } else {
                p.wrapping_div(q)
            }
        }
        IBinOp::Mod => {
            if q == 0 {
                0
            } else {
                p.wrapping_rem(q)
            }
        }
        IBinOp::And => p & q,
        IBinOp::Or => p | q,
        IBinOp::Xor => p ^ q,
        IBinOp::Shl => p.wrapping_shl(q as u32),
        IBinOp::Shr => p.wrapping_shr(q as u32),
        IBinOp::Min => p.min(q),
        IBinOp::Max => p.max(q),
        IBinOp::LAnd => i32::from(p != 0 && q != 0),
        IBinOp::LOr => i32::from(p != 0 || q != 0),
        IBinOp::AndNot => i32::from(p != 0 && q == 0),
    }
}

#[inline(always)]
pub(super) fn iun1(op: IUnOp, p: i32) -> i32 {
    match op {
        IUnOp::Neg => p.wrapping_neg(),
        IUnOp::Not => i32::from(p == 0),
        IUnOp::BitNot => !p,
        IUnOp::Abs => p.wrapping_abs(),
        IUnOp::Truth => i32::from(p != 0),
    }
}

#[inline(always)]
pub(super) fn compare<T: PartialOrd>(op: Cmp, a: &T, b: &T) -> i32 {
    i32::from(match op {
        Cmp::Lt => a < b,
        Cmp::Le => a <= b,
        Cmp::Gt => a > b,
        Cmp::Ge => a >= b,
        Cmp::Eq => a == b,
        Cmp::Ne => a != b,
    })
}
