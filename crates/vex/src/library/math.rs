//! Math and vector functions (SideFX's "Math" and "Vectors" categories).
//! Most are component-wise and become batch instructions (the compiler
//! lowers them: `compile/lower/inline.rs`); the rest run per lane.

use super::{a, compiler, form, lane, shape, Category, Function, Ret, F, I, T, V};
use crate::program::{Lane, Stop};
use crate::ty::Ty;
use crate::value::Val;

const M: Category = Category::Math;
const VC: Category = Category::Vectors;
const N: Ret = Ret::Num;

/// `<float|vector> name(<float|vector> x)`, component-wise.
macro_rules! unary {
    ($name:literal, $arg:literal, $summary:literal) => {
        compiler($name, M, $summary, &[shape(N, &[a(T::Num, $arg)])])
    };
}

#[rustfmt::skip]
pub const FUNCTIONS: &[Function] = &[
    compiler("abs", M, "Absolute value; ints stay ints, vectors per component.", &[
        shape(Ret::Is(Ty::Int), &[a(I, "x")]),
        shape(N, &[a(T::Num, "x")]),
    ]),
    unary!("floor", "x", "Largest integer not above x (per component)."),
    unary!("ceil", "x", "Smallest integer not below x (per component)."),
    unary!("frac", "x", "Fractional part, x - floor(x) (per component)."),
    unary!("rint", "x", "Rounds to the nearest integer (per component)."),
    unary!("trunc", "x", "Drops the fractional part, towards zero (per component)."),
    unary!("sqrt", "x", "Square root (per component)."),
    unary!("exp", "x", "e raised to x (per component)."),
    unary!("log", "x", "Natural logarithm (per component)."),
    unary!("log10", "x", "Base-10 logarithm (per component)."),
    unary!("sin", "radians", "Sine (per component)."),
    unary!("cos", "radians", "Cosine (per component)."),
    unary!("tan", "radians", "Tangent (per component)."),
    unary!("asin", "x", "Arc sine, in radians (per component)."),
    unary!("acos", "x", "Arc cosine, in radians (per component)."),
    compiler("atan", M, "Arc tangent in radians; with two arguments the angle of the point (x, y), as atan2.", &[
        shape(N, &[a(T::Num, "x")]),
        shape(Ret::Is(Ty::Float), &[a(F, "y"), a(F, "x")]),
    ]),
    compiler("atan2", M, "The angle of the point (x, y), in radians.", &[
        shape(Ret::Is(Ty::Float), &[a(F, "y"), a(F, "x")]),
    ]),
    unary!("sinh", "x", "Hyperbolic sine (per component)."),
    unary!("cosh", "x", "Hyperbolic cosine (per component)."),
    unary!("tanh", "x", "Hyperbolic tangent (per component)."),
    unary!("radians", "degrees", "Degrees to radians (per component)."),
    unary!("degrees", "radians", "Radians to degrees (per component)."),
    unary!("sign", "x", "-1, 0 or 1 by the sign of x (per component)."),
    compiler("pow", M, "base raised to exponent; a vector base takes a float or a vector exponent.", &[
        shape(N, &[a(T::Num, "base"), a(T::Num, "exponent")]),
    ]),
    compiler("min", M, "The smallest argument (ints stay ints, vectors per component), or a vector's smallest component.", &[
        shape(N, &[a(T::Num, "a"), a(T::Num, "b")]).many(),
        shape(Ret::Is(Ty::Float), &[a(T::Vector, "v")]),
    ]),
    compiler("max", M, "The largest argument (ints stay ints, vectors per component), or a vector's largest component.", &[
        shape(N, &[a(T::Num, "a"), a(T::Num, "b")]).many(),
        shape(Ret::Is(Ty::Float), &[a(T::Vector, "v")]),
    ]),
    compiler("clamp", M, "x limited to [lo, hi] (ints stay ints, vectors per component).", &[
        shape(N, &[a(T::Num, "x"), a(T::Num, "lo"), a(T::Num, "hi")]),
    ]),
    compiler("lerp", M, "Linear blend: a at t = 0, b at t = 1.", &[
        shape(N, &[a(T::Num, "a"), a(T::Num, "b"), a(F, "t")]),
    ]),
    compiler("fit", M, "x mapped from [omin, omax] to [nmin, nmax], clamped.", &[
        shape(N, &[a(T::Num, "x"), a(T::Num, "omin"), a(T::Num, "omax"), a(T::Num, "nmin"), a(T::Num, "nmax")]),
    ]),
    compiler("efit", M, "x mapped from [omin, omax] to [nmin, nmax], not clamped.", &[
        shape(N, &[a(T::Num, "x"), a(T::Num, "omin"), a(T::Num, "omax"), a(T::Num, "nmin"), a(T::Num, "nmax")]),
    ]),
    compiler("fit01", M, "x mapped from [0, 1] to [nmin, nmax], clamped.", &[
        shape(N, &[a(T::Num, "x"), a(T::Num, "nmin"), a(T::Num, "nmax")]),
    ]),
    compiler("fit10", M, "x mapped from [1, 0] to [nmin, nmax], clamped.", &[
        shape(N, &[a(T::Num, "x"), a(T::Num, "nmin"), a(T::Num, "nmax")]),
    ]),
    compiler("fit11", M, "x mapped from [-1, 1] to [nmin, nmax], clamped.", &[
        shape(N, &[a(T::Num, "x"), a(T::Num, "nmin"), a(T::Num, "nmax")]),
    ]),
    compiler("smooth", M, "Smooth step: 0 below lo, 1 above hi, a cubic between.", &[
        shape(Ret::Is(Ty::Float), &[a(F, "lo"), a(F, "hi"), a(F, "x")]),
    ]),
    lane("invlerp", M, "Where x sits between a and b: 0 at a, 1 at b (not clamped).", &[
        form(Ret::Is(Ty::Float), &[a(F, "x"), a(F, "a"), a(F, "b")], invlerp),
    ]),
    lane("isnan", M, "1 if x is not a number.", &[form(Ret::Is(Ty::Int), &[a(F, "x")], isnan)]),
    lane("isfinite", M, "1 if x is neither infinite nor not a number.", &[form(Ret::Is(Ty::Int), &[a(F, "x")], isfinite)]),
    compiler("length", VC, "Length of a vector.", &[shape(Ret::Is(Ty::Float), &[a(T::Vector, "v")])]),
    compiler("length2", VC, "Squared length of a vector.", &[shape(Ret::Is(Ty::Float), &[a(T::Vector, "v")])]),
    compiler("distance", VC, "Distance between two points.", &[shape(Ret::Is(Ty::Float), &[a(T::Vector, "a"), a(T::Vector, "b")])]),
    compiler("distance2", VC, "Squared distance between two points.", &[shape(Ret::Is(Ty::Float), &[a(T::Vector, "a"), a(T::Vector, "b")])]),
    compiler("dot", VC, "Dot product.", &[shape(Ret::Is(Ty::Float), &[a(T::Vector, "a"), a(T::Vector, "b")])]),
    compiler("cross", VC, "Cross product.", &[shape(Ret::Is(Ty::Vec3), &[a(V, "a"), a(V, "b")])]),
    compiler("normalize", VC, "The vector scaled to length 1 (zero stays zero).", &[
        shape(Ret::Is(Ty::Vec3), &[a(V, "v")]),
        shape(Ret::Is(Ty::Vec2), &[a(T::Is(Ty::Vec2), "v")]),
        shape(Ret::Is(Ty::Vec4), &[a(T::Is(Ty::Vec4), "v")]),
    ]),
    compiler("avg", VC, "Average of a vector's components, or of the arguments.", &[
        shape(Ret::Is(Ty::Float), &[a(T::Vector, "v")]),
        shape(N, &[a(T::Num, "a"), a(T::Num, "b")]).many(),
    ]),
    compiler("set", VC, "A vector from components: 2, 3 or 4 floats give a vector2, vector or vector4; one value converts to the declared type.", &[
        shape(Ret::Is(Ty::Vec3), &[a(F, "x"), a(F, "y"), a(F, "z")]),
    ]),
    compiler("getcomp", VC, "Component index (a constant) of a vector; with a column, of a matrix.", &[
        shape(Ret::Is(Ty::Float), &[a(T::Vector, "v"), a(I, "index")]),
    ]),
    compiler("setcomp", VC, "Sets component index (a constant) of a vector variable.", &[
        shape(Ret::Is(Ty::Void), &[super::out(T::Vector, "v"), a(F, "value"), a(I, "index")]),
    ]),
];

fn invlerp(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let (x, lo, hi) = (a[0].f(), a[1].f(), a[2].f());
    // "If min and max are equal, the mixing value is 0.5."
    Ok(Val::float(if hi == lo {
        0.5
    } else {
        (x - lo) / (hi - lo)
    }))
}

fn isnan(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(i32::from(a[0].f().is_nan())))
}

fn isfinite(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(i32::from(a[0].f().is_finite())))
}
