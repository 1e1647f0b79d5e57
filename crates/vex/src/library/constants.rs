//! The constants of SideFX's `math.h`, which VEX snippets see without an
//! include: `M_PI`, `PI`, the transform and rotation order codes
//! (`XFORM_SRT`, `XFORM_XYZ`) that `maketransform` and friends take.

/// A named constant's value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Constant {
    Float(f64),
    Int(i32),
}

/// Every constant, for docs and completion.
pub const CONSTANTS: &[(&str, Constant)] = &[
    ("M_PI", Constant::Float(std::f64::consts::PI)),
    ("PI", Constant::Float(std::f64::consts::PI)),
    ("M_TWO_PI", Constant::Float(std::f64::consts::TAU)),
    ("M_PI_2", Constant::Float(std::f64::consts::FRAC_PI_2)),
    ("M_PI_4", Constant::Float(std::f64::consts::FRAC_PI_4)),
    ("M_1_PI", Constant::Float(std::f64::consts::FRAC_1_PI)),
    ("M_2_PI", Constant::Float(std::f64::consts::FRAC_2_PI)),
    (
        "M_2_SQRTPI",
        Constant::Float(std::f64::consts::FRAC_2_SQRT_PI),
    ),
    ("M_E", Constant::Float(std::f64::consts::E)),
    ("M_LN2", Constant::Float(std::f64::consts::LN_2)),
    ("M_LN10", Constant::Float(std::f64::consts::LN_10)),
    ("M_LOG2E", Constant::Float(std::f64::consts::LOG2_E)),
    ("M_LOG10E", Constant::Float(std::f64::consts::LOG10_E)),
    ("M_SQRT2", Constant::Float(std::f64::consts::SQRT_2)),
    (
        "M_SQRT1_2",
        Constant::Float(std::f64::consts::FRAC_1_SQRT_2),
    ),
    ("M_TOLERANCE", Constant::Float(1e-4)),
    ("XFORM_SRT", Constant::Int(0)),
    ("XFORM_STR", Constant::Int(1)),
    ("XFORM_RST", Constant::Int(2)),
    ("XFORM_RTS", Constant::Int(3)),
    ("XFORM_TSR", Constant::Int(4)),
    ("XFORM_TRS", Constant::Int(5)),
    ("XFORM_XYZ", Constant::Int(0)),
    ("XFORM_XZY", Constant::Int(1)),
    ("XFORM_YXZ", Constant::Int(2)),
    ("XFORM_YZX", Constant::Int(3)),
    ("XFORM_ZXY", Constant::Int(4)),
    ("XFORM_ZYX", Constant::Int(5)),
    ("PRIMPOLY", Constant::Int(1)),
];

/// The constant called `name`, if any.
pub fn constant(name: &str) -> Option<Constant> {
    CONSTANTS.iter().find(|(n, _)| *n == name).map(|(_, c)| *c)
}
