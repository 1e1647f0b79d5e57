//! Library programs over four points at x = 0..3, each with the value
//! SideFX's reference (or C's printf rules, or analytic math) gives.

use super::*;

const S2: f32 = FRAC_1_SQRT_2;
const C30: f32 = 0.866_025_4;

/// Over four points at x = 0, 1, 2, 3 (no primitives).
#[rustfmt::skip]
pub(super) const CASES: &[(&str, &str, Want)] = &[
    // math.h constants.
    (r#"f@r = M_PI;"#, "r", F(PI)),
    (r#"f@r = PI;"#, "r", F(PI)),
    (r#"f@r = M_E;"#, "r", F(E)),
    (r#"f@r = M_SQRT2;"#, "r", F(SQRT_2)),
    (r#"f@r = M_PI_2;"#, "r", F(FRAC_PI_2)),
    (r#"f@r = M_LN2;"#, "r", F(LN_2)),
    // Math, per component on vectors.
    (r#"v@r = abs({-1, 2, -3});"#, "r", V(&[1.0, 2.0, 3.0])),
    (r#"v@r = floor({1.5, -1.5, 2});"#, "r", V(&[1.0, -2.0, 2.0])),
    (r#"v@r = ceil({1.2, -1.2, 3});"#, "r", V(&[2.0, -1.0, 3.0])),
    (r#"v@r = frac({1.25, -0.25, 3});"#, "r", V(&[0.25, 0.75, 0.0])),
    (r#"v@r = rint({1.4, 1.6, -2.6});"#, "r", V(&[1.0, 2.0, -3.0])),
    (r#"v@r = trunc({1.7, -1.7, 0.2});"#, "r", V(&[1.0, -1.0, 0.0])),
    (r#"v@r = sqrt({4, 9, 16});"#, "r", V(&[2.0, 3.0, 4.0])),
    (r#"f@r = exp(1);"#, "r", F(E)),
    (r#"v@r = exp({0, 1, 2});"#, "r", V(&[1.0, E, 7.389_056])),
    (r#"v@r = log(set(1, exp(1), exp(2)));"#, "r", V(&[0.0, 1.0, 2.0])),
    (r#"f@r = log10(0.01);"#, "r", F(-2.0)),
    (r#"v@r = sin(radians({0, 90, 30}));"#, "r", V(&[0.0, 1.0, 0.5])),
    (r#"f@r = cos(M_PI);"#, "r", F(-1.0)),
    (r#"f@r = tan(radians(-45));"#, "r", F(-1.0)),
    (r#"f@r = asin(0.5);"#, "r", F(PI / 6.0)),
    (r#"f@r = acos(-1);"#, "r", F(PI)),
    (r#"f@r = atan(-1);"#, "r", F(-FRAC_PI_4)),
    // atan2(y, x): the angle of the point (x, y) = (-1, -1).
    (r#"f@r = atan2(-1, -1);"#, "r", F(-3.0 * FRAC_PI_4)),
    (r#"f@r = atan2(0, -1);"#, "r", F(PI)),
    (r#"f@r = atan(1, 0);"#, "r", F(FRAC_PI_2)),
    (r#"f@r = sinh(1);"#, "r", F(1.175_201_2)),
    (r#"f@r = cosh(1);"#, "r", F(1.543_080_6)),
    (r#"f@r = tanh(0.5);"#, "r", F(0.462_117_16)),
    (r#"v@r = radians({180, 90, 0});"#, "r", V(&[PI, FRAC_PI_2, 0.0])),
    (r#"v@r = degrees(set(M_PI, M_PI_2, 0));"#, "r", V(&[180.0, 90.0, 0.0])),
    (r#"v@r = sign({-2, 0, 3});"#, "r", V(&[-1.0, 0.0, 1.0])),
    (r#"v@r = pow({2, 3, 4}, 2);"#, "r", V(&[4.0, 9.0, 16.0])),
    (r#"v@r = pow({2, 2, 2}, {1, 2, 3});"#, "r", V(&[2.0, 4.0, 8.0])),
    (r#"f@r = pow(4, 0.5);"#, "r", F(2.0)),
    (r#"f@r = min({4, -2, 7});"#, "r", F(-2.0)),
    (r#"i@r = min(5, 3, 9);"#, "r", I(3)),
    (r#"v@r = max({1, 5, 3}, {4, 2, 6});"#, "r", V(&[4.0, 5.0, 6.0])),
    (r#"f@r = max(1.5, -2, 0.5);"#, "r", F(1.5)),
    (r#"v@r = clamp({-1, 0.5, 2}, {0, 0, 0}, {1, 1, 1});"#, "r", V(&[0.0, 0.5, 1.0])),
    (r#"i@r = clamp(-4, 0, 10);"#, "r", I(0)),
    (r#"v@r = lerp({0, 0, 0}, {10, 20, 30}, 0.1);"#, "r", V(&[1.0, 2.0, 3.0])),
    // fit: "the value in the range (omin, omax) ... clamped"; ranges may run backwards.
    (r#"f@r = fit(5, 10, 0, 0, 1);"#, "r", F(0.5)),
    (r#"f@r = fit(3, 0, 2, 10, 0);"#, "r", F(0.0)),
    (r#"v@r = fit({0.5, 0.25, 2}, {0, 0, 0}, {1, 1, 1}, {0, 0, 0}, {10, 10, 10});"#, "r", V(&[5.0, 2.5, 10.0])),
    (r#"f@r = efit(-1, 0, 1, 10, 20);"#, "r", F(0.0)),
    (r#"f@r = fit01(2, 0, 4);"#, "r", F(4.0)),
    (r#"f@r = fit10(0, 0, 4);"#, "r", F(4.0)),
    (r#"f@r = fit11(-3, 0, 4);"#, "r", F(0.0)),
    (r#"f@r = smooth(0, 10, 5);"#, "r", F(0.5)),
    (r#"f@r = smooth(1, 3, 1.5);"#, "r", F(0.156_25)),
    (r#"f@r = smooth(0, 1, -1);"#, "r", F(0.0)),
    (r#"f@r = invlerp(15, 10, 20);"#, "r", F(0.5)),
    // invlerp: "If a is outside the range min to max, values greater than 1
    // or less than 0 will be produced. If min and max are equal, the mixing
    // value is 0.5."
    (r#"f@r = invlerp(25, 10, 20);"#, "r", F(1.5)),
    (r#"i@r = isnan(1.5);"#, "r", I(0)),
    (r#"i@r = isfinite(1.5);"#, "r", I(1)),
    // IEEE single precision: exp(1000) overflows to infinity, inf - inf is NaN.
    (r#"i@r = isfinite(exp(1000));"#, "r", I(0)),
    (r#"float inf = exp(1000); i@r = isnan(inf - inf);"#, "r", I(1)),
    // Vectors.
    (r#"f@r = length({1, 2, 2});"#, "r", F(3.0)),
    (r#"f@r = length(set(3, 4));"#, "r", F(5.0)),
    (r#"f@r = length2({1, 2, 2});"#, "r", F(9.0)),
    (r#"f@r = distance({1, 1, 1}, {4, 5, 1});"#, "r", F(5.0)),
    (r#"f@r = distance2({0, 0, 0}, {1, 2, 3});"#, "r", F(14.0)),
    (r#"f@r = dot({1, 0, 0}, {0, 1, 0});"#, "r", F(0.0)),
    (r#"f@r = dot(set(1, 2), set(3, 4));"#, "r", F(11.0)),
    (r#"v@r = cross({0, 0, 1}, {1, 0, 0});"#, "r", V(&[0.0, 1.0, 0.0])),
    (r#"v@r = cross({1, 2, 3}, {4, 5, 6});"#, "r", V(&[-3.0, 6.0, -3.0])),
    (r#"vector4 q = {0, 0, 3, 4}; p@r = normalize(q);"#, "r", V(&[0.0, 0.0, 0.6, 0.8])),
    (r#"u@r = normalize(set(3, 4));"#, "r", V(&[0.6, 0.8])),
    (r#"f@r = avg(1, 2, 6);"#, "r", F(3.0)),
    (r#"v@r = avg({0, 0, 0}, {2, 4, 6});"#, "r", V(&[1.0, 2.0, 3.0])),
    (r#"p@r = set(1, 2, 3, 4);"#, "r", V(&[1.0, 2.0, 3.0, 4.0])),
    (r#"u@r = set(5, 6);"#, "r", V(&[5.0, 6.0])),
    (r#"f@r = getcomp({4, 5, 6}, 2);"#, "r", F(6.0)),
    (r#"matrix3 m = {1, 2, 3, 4, 5, 6, 7, 8, 9}; f@r = getcomp(m, 1, 2);"#, "r", F(6.0)),
    (r#"vector v = {1, 2, 3}; setcomp(v, 9, 0); v@r = v;"#, "r", V(&[9.0, 2.0, 3.0])),
    // Matrices: row vectors, v * m.
    (r#"matrix m = ident(); f@r = determinant(m);"#, "r", F(1.0)),
    (r#"matrix3 m = ident(); v@r = {4, 5, 6} * m;"#, "r", V(&[4.0, 5.0, 6.0])),
    (r#"matrix3 m = {2, 0, 0, 0, 4, 0, 0, 0, 8}; v@r = {1, 1, 1} * invert(m);"#, "r", V(&[0.5, 0.25, 0.125])),
    (r#"matrix m = ident(); translate(m, {1, 2, 3}); rotate(m, radians(90), {0, 0, 1}); v@r = {-2, 1, 3} * invert(m);"#, "r", V(&[0.0, 0.0, 0.0])),
    // The Invert VOP (which calls invert): "Given a float ... computes 1 / input".
    (r#"f@r = invert(4.0);"#, "r", F(0.25)),
    (r#"matrix3 m = {1, 2, 3, 4, 5, 6, 7, 8, 10}; f@r = determinant(m);"#, "r", F(-3.0)),
    (r#"matrix m = ident(); scale(m, {2, 3, 4}); f@r = determinant(m);"#, "r", F(24.0)),
    (r#"matrix3 m = {1, 2, 3, 4, 5, 6, 7, 8, 9}; matrix3 t = transpose(m); v@r = t[0];"#, "r", V(&[1.0, 4.0, 7.0])),
    (r#"matrix m = ident(); translate(m, {1, 2, 3}); matrix t = transpose(m); v@r = set(getcomp(t, 0, 3), getcomp(t, 1, 3), getcomp(t, 2, 3));"#, "r", V(&[1.0, 2.0, 3.0])),
    // rotate applies after what the matrix does, prerotate before ("Applies a pre rotation").
    (r#"matrix3 m = ident(); scale(m, {2, 1, 1}); rotate(m, radians(90), {0, 0, 1}); v@r = {1, 0, 0} * m;"#, "r", V(&[0.0, 2.0, 0.0])),
    (r#"matrix3 m = ident(); scale(m, {2, 1, 1}); prerotate(m, radians(90), {0, 0, 1}); v@r = {1, 0, 0} * m;"#, "r", V(&[0.0, 1.0, 0.0])),
    (r#"matrix m = ident(); translate(m, {1, 0, 0}); rotate(m, radians(90), {0, 0, 1}); v@r = {0, 0, 0} * m;"#, "r", V(&[0.0, 1.0, 0.0])),
    (r#"matrix m = ident(); translate(m, {1, 0, 0}); prerotate(m, radians(90), {0, 0, 1}); v@r = {0, 0, 0} * m;"#, "r", V(&[1.0, 0.0, 0.0])),
    (r#"matrix m = ident(); translate(m, {1, 0, 0}); scale(m, {2, 2, 2}); v@r = {1, 0, 0} * m;"#, "r", V(&[4.0, 0.0, 0.0])),
    (r#"matrix m = ident(); translate(m, {1, 0, 0}); prescale(m, {2, 2, 2}); v@r = {1, 0, 0} * m;"#, "r", V(&[3.0, 0.0, 0.0])),
    (r#"matrix3 m = ident(); rotate(m, radians(90), {0, 0, 1}); prescale(m, {2, 1, 1}); v@r = {1, 0, 0} * m;"#, "r", V(&[0.0, 2.0, 0.0])),
    (r#"matrix m = ident(); scale(m, {2, 2, 2}); pretranslate(m, {1, 0, 0}); v@r = {1, 0, 0} * m;"#, "r", V(&[4.0, 0.0, 0.0])),
    // maketransform(trs, xyz, t, r, s): the order names which of scale,
    // rotate (degrees) and translate applies first.
    (r#"matrix m = maketransform(XFORM_TRS, XFORM_XYZ, {1, 2, 3}, {0, 0, 90}, {2, 2, 2}); v@r = {1, 0, 0} * m;"#, "r", V(&[-4.0, 4.0, 6.0])),
    (r#"matrix m = maketransform(XFORM_SRT, XFORM_XYZ, {1, 2, 3}, {0, 0, 90}, {2, 2, 2}); v@r = {1, 0, 0} * m;"#, "r", V(&[1.0, 4.0, 3.0])),
    (r#"matrix m = maketransform(XFORM_SRT, XFORM_XYZ, {1, 2, 3}, {0, 0, 90}, {2, 3, 4}); v@r = {1, 0, 0} * m;"#, "r", V(&[1.0, 4.0, 3.0])),
    (r#"matrix m = maketransform(XFORM_STR, XFORM_XYZ, {1, 2, 3}, {0, 0, 90}, {2, 3, 4}); v@r = {1, 0, 0} * m;"#, "r", V(&[-2.0, 3.0, 3.0])),
    (r#"matrix m = maketransform(XFORM_RST, XFORM_XYZ, {1, 2, 3}, {0, 0, 90}, {2, 3, 4}); v@r = {1, 0, 0} * m;"#, "r", V(&[1.0, 5.0, 3.0])),
    (r#"matrix m = maketransform(XFORM_RTS, XFORM_XYZ, {1, 2, 3}, {0, 0, 90}, {2, 3, 4}); v@r = {1, 0, 0} * m;"#, "r", V(&[2.0, 9.0, 12.0])),
    (r#"matrix m = maketransform(XFORM_TSR, XFORM_XYZ, {1, 2, 3}, {0, 0, 90}, {2, 3, 4}); v@r = {1, 0, 0} * m;"#, "r", V(&[-6.0, 4.0, 12.0])),
    (r#"matrix m = maketransform(XFORM_TRS, XFORM_XYZ, {1, 2, 3}, {0, 0, 90}, {2, 3, 4}); v@r = {1, 0, 0} * m;"#, "r", V(&[-4.0, 6.0, 12.0])),
    // Rotation orders: XFORM_XYZ "Rotate order X, Y, Z" (eulertoquaternion's table).
    (r#"matrix m = maketransform(XFORM_SRT, XFORM_XYZ, {0, 0, 0}, {90, 0, 90}); v@r = {0, 1, 0} * m;"#, "r", V(&[0.0, 0.0, 1.0])),
    (r#"matrix m = maketransform(XFORM_SRT, XFORM_ZYX, {0, 0, 0}, {90, 0, 90}); v@r = {0, 1, 0} * m;"#, "r", V(&[-1.0, 0.0, 0.0])),
    (r#"matrix m = maketransform(XFORM_SRT, XFORM_XYZ, {0, 0, 0}, {30, 60, 90}); v@r = {0, 1, 0} * m;"#, "r", V(&[-C30, 0.433_012_7, 0.25])),
    (r#"matrix m = maketransform(XFORM_SRT, XFORM_XZY, {0, 0, 0}, {30, 60, 90}); v@r = {0, 1, 0} * m;"#, "r", V(&[0.0, 0.0, 1.0])),
    (r#"matrix m = maketransform(XFORM_SRT, XFORM_YXZ, {0, 0, 0}, {30, 60, 90}); v@r = {0, 1, 0} * m;"#, "r", V(&[-C30, 0.0, 0.5])),
    (r#"matrix m = maketransform(XFORM_SRT, XFORM_YZX, {0, 0, 0}, {30, 60, 90}); v@r = {0, 1, 0} * m;"#, "r", V(&[-1.0, 0.0, 0.0])),
    (r#"matrix m = maketransform(XFORM_SRT, XFORM_ZXY, {0, 0, 0}, {30, 60, 90}); v@r = {0, 1, 0} * m;"#, "r", V(&[-0.5, 0.0, C30])),
    (r#"matrix m = maketransform(XFORM_SRT, XFORM_ZYX, {0, 0, 0}, {30, 60, 90}); v@r = {0, 1, 0} * m;"#, "r", V(&[-0.5, -0.433_012_7, 0.75])),
    // A pivot: rotating (2,0,0) a quarter turn about z around (1,0,0).
    (r#"matrix m = maketransform(XFORM_SRT, XFORM_XYZ, {0, 0, 0}, {0, 0, 90}, {1, 1, 1}, {1, 0, 0}); v@r = {2, 0, 0} * m;"#, "r", V(&[1.0, 1.0, 0.0])),
    // cracktransform: "Depending on the value of c, returns the translate
    // (c=0), rotate (c=1 or c=4), scale (c=2) or shears (c=3) component of
    // the transform (xform). The function uses the given transform and
    // rotation orders (trs and xyz), the given pivot point (pivot) and
    // optional pivot rotation (pr) to calculate the return value": the
    // parts maketransform was given. "Rotation angles (when c=1) are
    // returned in degrees ... For example: vector angles =
    // radians(cracktransform(XFORM_TRS, XFORM_XYZ, 1, {0,0,0}, M));";
    // "Rotation angles (when c=4) are returned in radians."
    (r#"matrix M = maketransform(XFORM_TRS, XFORM_XYZ, {1, 2, 3}, {30, 45, 60}, {2, 2, 2}); vector angles = radians(cracktransform(XFORM_TRS, XFORM_XYZ, 1, {0,0,0}, M)); v@r = angles;"#, "r", V(&[FRAC_PI_6, FRAC_PI_4, FRAC_PI_3])),
    (r#"matrix M = maketransform(XFORM_TRS, XFORM_XYZ, {1, 2, 3}, {30, 45, 60}, {2, 2, 2}); v@r = cracktransform(XFORM_TRS, XFORM_XYZ, 4, {0, 0, 0}, M);"#, "r", V(&[FRAC_PI_6, FRAC_PI_4, FRAC_PI_3])),
    (r#"matrix M = maketransform(XFORM_TRS, XFORM_XYZ, {1, 2, 3}, {30, 45, 60}, {2, 2, 2}); v@r = cracktransform(XFORM_TRS, XFORM_XYZ, 0, {0, 0, 0}, M);"#, "r", V(&[1.0, 2.0, 3.0])),
    (r#"matrix M = maketransform(XFORM_TRS, XFORM_XYZ, {1, 2, 3}, {30, 45, 60}, {2, 3, 4}); v@r = cracktransform(XFORM_TRS, XFORM_XYZ, 2, {0, 0, 0}, M);"#, "r", V(&[2.0, 3.0, 4.0])),
    (r#"matrix M = maketransform(XFORM_RST, XFORM_ZXY, {1, 2, 3}, {30, 45, 60}, {2, 3, 4}, {5, 0, -1}); v@r = cracktransform(XFORM_RST, XFORM_ZXY, 1, {5, 0, -1}, M);"#, "r", V(&[30.0, 45.0, 60.0])),
    (r#"matrix M = maketransform(XFORM_STR, XFORM_YZX, {1, 2, 3}, {30, 45, 60}, {2, 3, 4}, {5, 0, -1}); v@r = cracktransform(XFORM_STR, XFORM_YZX, 0, {5, 0, -1}, {0, 0, 0}, M);"#, "r", V(&[1.0, 2.0, 3.0])),
    // "void cracktransform(int trs, int xyz, vector pivot, matrix xform,
    // vector &t, vector &r, vector &s)": all three at once.
    (r#"matrix M = maketransform(XFORM_RTS, XFORM_ZYX, {1, 2, 3}, {-30, 20, 100}, {2, 3, 4}); vector t, r, s; cracktransform(XFORM_RTS, XFORM_ZYX, {0, 0, 0}, M, t, r, s); v@r = t + r * 1000 + s * 1000000;"#, "r", V(&[1.0 - 30_000.0 + 2_000_000.0, 2.0 + 20_000.0 + 3_000_000.0, 3.0 + 100_000.0 + 4_000_000.0])),
    // "void cracktransform(int trs, int xyz, vector pivot, vector
    // pivot_rotate, matrix xform, vector &t, vector &r, vector &s, vector
    // &shears)": a scale (2, 3, 4) sheared by xy 0.5, xz 0.25, yz 0.75
    // (rows sx (1, 0, 0), sy (xy, 1, 0), sz (xz, yz, 1): geode's shear
    // convention, see docs/wrangle.md), then moved by (5, 6, 7).
    (r#"matrix M = {2, 0, 0, 0, 1.5, 3, 0, 0, 1, 3, 4, 0, 5, 6, 7, 1}; vector t, r, s, sh; cracktransform(XFORM_SRT, XFORM_XYZ, {0, 0, 0}, {0, 0, 0}, M, t, r, s, sh); v@r = sh;"#, "r", V(&[0.5, 0.25, 0.75])),
    (r#"matrix M = {2, 0, 0, 0, 1.5, 3, 0, 0, 1, 3, 4, 0, 5, 6, 7, 1}; vector t, r, s, sh; cracktransform(XFORM_SRT, XFORM_XYZ, {0, 0, 0}, {0, 0, 0}, M, t, r, s, sh); v@r = t * 100 + s + r * 1000;"#, "r", V(&[502.0, 603.0, 704.0])),
    (r#"matrix M = {2, 0, 0, 0, 1.5, 3, 0, 0, 1, 3, 4, 0, 5, 6, 7, 1}; v@r = cracktransform(XFORM_SRT, XFORM_XYZ, 3, {0, 0, 0}, M);"#, "r", V(&[0.5, 0.25, 0.75])),
    // "constructed so that the z-axis will be transformed to the z-axis specified".
    (r#"matrix3 m = maketransform({1, 0, 0}, {0, 1, 0}); v@r = {0, 0, 1} * m;"#, "r", V(&[1.0, 0.0, 0.0])),
    (r#"matrix m = maketransform({0, 0, 1}, {0, 1, 0}, {5, 6, 7}); v@r = {1, 1, 1} * m;"#, "r", V(&[6.0, 7.0, 8.0])),
    // lookat: "orient the negative z-axis along the vector (to-from)"; the up vector sets the roll.
    (r#"matrix3 m = lookat({0, 0, 0}, {1, 0, 0}); v@r = {0, 0, -1} * m;"#, "r", V(&[1.0, 0.0, 0.0])),
    (r#"matrix3 m = lookat({1, 2, 3}, {1, 2, -7}); v@r = {0, 0, -1} * m;"#, "r", V(&[0.0, 0.0, -1.0])),
    (r#"matrix3 m = lookat({0, 0, 0}, {0, -3, 0}, {0, 0, 1}); v@r = {0, 0, -1} * m;"#, "r", V(&[0.0, -1.0, 0.0])),
    (r#"matrix3 m = lookat({0, 0, 0}, {0, -3, 0}, {0, 0, 1}); v@r = {0, 1, 0} * m;"#, "r", V(&[0.0, 0.0, 1.0])),
    // Quaternions ({x, y, z, w}).
    (r#"vector4 q = quaternion(radians(90), {0, 0, 1}); v@r = qrotate(qinvert(q), {0, 1, 0});"#, "r", V(&[1.0, 0.0, 0.0])),
    (r#"vector4 q = quaternion(radians(90), {0, 0, 1}); p@r = qinvert(q);"#, "r", V(&[0.0, 0.0, -S2, S2])),
    (r#"vector4 q = quaternion(radians(60), {0, 1, 0}); p@r = qmultiply(q, qinvert(q));"#, "r", V(&[0.0, 0.0, 0.0, 1.0])),
    // The Hamilton product a*b rotates by b first, then a.
    (r#"vector4 a = quaternion(radians(90), {0, 0, 1}); vector4 b = quaternion(radians(90), {1, 0, 0}); v@r = qrotate(qmultiply(a, b), {0, 1, 0});"#, "r", V(&[0.0, 0.0, 1.0])),
    // qdistance: "the approximate angle, in radians, between two quaternions".
    (r#"f@r = qdistance(quaternion(0, {0, 0, 1}), quaternion(radians(90), {0, 0, 1}));"#, "r", F(FRAC_PI_2)),
    (r#"vector4 q = quaternion(radians(40), {1, 0, 0}); f@r = qdistance(q, q);"#, "r", F(0.0)),
    (r#"vector4 a = quaternion(0, {0, 0, 1}); vector4 b = quaternion(radians(90), {0, 0, 1}); v@r = qrotate(slerp(a, b, 0.5), {1, 0, 0});"#, "r", V(&[S2, S2, 0.0])),
    (r#"vector4 a = quaternion(0, {0, 0, 1}); vector4 b = quaternion(radians(90), {0, 0, 1}); v@r = qrotate(slerp(a, b, 1), {1, 0, 0});"#, "r", V(&[0.0, 1.0, 0.0])),
    (r#"vector4 a = quaternion(0, {0, 0, 1}); vector4 b = quaternion(radians(90), {0, 0, 1}); v@r = qrotate(slerp(a, b, 0), {1, 0, 0});"#, "r", V(&[1.0, 0.0, 0.0])),
    // The slerp VOP: "This interpolation will always be along the shortest arc."
    (r#"vector4 a = {0, 0, 0, 1}; vector4 b = quaternion(radians(90), {0, 0, 1}); b = -b; v@r = qrotate(slerp(a, b, 0.5), {1, 0, 0});"#, "r", V(&[S2, S2, 0.0])),
    (r#"matrix3 a = ident(); matrix3 b = qconvert(quaternion(radians(90), {0, 0, 1})); matrix3 m = slerp(a, b, 0.5); v@r = {1, 0, 0} * m;"#, "r", V(&[S2, S2, 0.0])),
    (r#"vector e = quaterniontoeuler(eulertoquaternion(radians({10, 20, 30}), XFORM_XYZ), XFORM_XYZ); v@r = degrees(e);"#, "r", V(&[10.0, 20.0, 30.0])),
    (r#"vector e = quaterniontoeuler(eulertoquaternion(radians({10, 20, 30}), XFORM_ZYX), XFORM_ZYX); v@r = degrees(e);"#, "r", V(&[10.0, 20.0, 30.0])),
    (r#"vector e = quaterniontoeuler(eulertoquaternion(radians({10, 20, 30}), XFORM_YXZ), XFORM_YXZ); v@r = degrees(e);"#, "r", V(&[10.0, 20.0, 30.0])),
    (r#"v@r = degrees(quaterniontoeuler(quaternion(radians(90), {0, 0, 1}), XFORM_XYZ));"#, "r", V(&[0.0, 0.0, 90.0])),
    (r#"vector4 q = eulertoquaternion(radians({90, 0, 90}), XFORM_ZYX); v@r = qrotate(q, {0, 1, 0});"#, "r", V(&[-1.0, 0.0, 0.0])),
    (r#"vector4 q = eulertoquaternion(radians({90, 90, 0}), XFORM_YXZ); v@r = qrotate(q, {0, 0, 1});"#, "r", V(&[1.0, 0.0, 0.0])),
    (r#"vector4 q = quaternion(set(radians(90), 0, 0)); v@r = qrotate(q, {0, 1, 0});"#, "r", V(&[0.0, 0.0, 1.0])),
    (r#"matrix3 m = qconvert(quaternion(radians(180), {0, 1, 0})); v@r = {1, 0, 0} * m;"#, "r", V(&[-1.0, 0.0, 0.0])),
    (r#"vector4 q = dihedral({0, 0, 1}, {0, 1, 0}); v@r = qrotate(q, {0, 0, 1});"#, "r", V(&[0.0, 1.0, 0.0])),
    // The shortest rotation turns about a x b, which it leaves alone.
    (r#"vector4 q = dihedral({0, 0, 1}, {0, 1, 0}); v@r = qrotate(q, {1, 0, 0});"#, "r", V(&[1.0, 0.0, 0.0])),
    (r#"matrix3 m = dihedral({1, 0, 0}, {0, 0, 1}); v@r = {1, 0, 0} * m;"#, "r", V(&[0.0, 0.0, 1.0])),
    // Random numbers and noise: in range and repeatable.
    // onoise and xnoise are Perlin's original and simplex noise; wnoise
    // "generates Worley (cellular) noise": f1 is the nearest feature point's
    // distance and f2 the second's, so f1 <= f2; curlnoise2d is "divergence
    // free noise in the plane", so its z is 0 and its divergence vanishes.
    (r#"float n = onoise({0.3, 0.7, 0.2}); f@r = abs(n) <= 1 && n == onoise({0.3, 0.7, 0.2});"#, "r", F(1.0)),
    (r#"float n = xnoise({0.3, 0.7, 0.2}); f@r = n >= 0 && n <= 1;"#, "r", F(1.0)),
    (r#"float n = xnoised({0.3, 0.7, 0.2}); f@r = n >= -1 && n <= 1 && n != 0;"#, "r", F(1.0)),
    (r#"int s; float f1, f2; wnoise({0.3, 0.7, 0.2}, s, f1, f2); f@r = f1 <= f2 && f1 >= 0;"#, "r", F(1.0)),
    (r#"int s; float f1, f2; int t; float g1, g2; wnoise({0.3, 0.7, 0.2}, s, f1, f2); wnoise({0.3001, 0.7, 0.2}, t, g1, g2); i@r = s == t;"#, "r", I(1)),
    (r#"vector c = curlnoise2d(set(0.3, 0.7)); f@r = c.z;"#, "r", F(0.0)),
    (r#"vector2 p = {0.3, 0.7}; float h = 0.01; float d = (curlnoise2d(p + set(h, 0)).x - curlnoise2d(p - set(h, 0)).x) / (2 * h) + (curlnoise2d(p + set(0, h)).y - curlnoise2d(p - set(0, h)).y) / (2 * h); vector c = curlnoise2d(p); f@r = abs(d) < 0.05 * (abs(c.x) + abs(c.y)) + 0.01;"#, "r", F(1.0)),
    (r#"float x = random(7); f@r = x >= 0 && x < 1;"#, "r", F(1.0)),
    (r#"vector v = rand(5); f@r = v.x >= 0 && v.x < 1 && v.y >= 0 && v.y < 1 && v.z >= 0 && v.z < 1;"#, "r", F(1.0)),
    (r#"f@r = rand(1, 2) == rand(1, 2);"#, "r", F(1.0)),
    (r#"vector n = noise({0.3, 0.7, 0.2}); f@r = n.x != n.y;"#, "r", F(1.0)),
    (r#"float n = snoise({0.3, 0.2, 0.7}); f@r = abs(n) < 1.5 && n != 0;"#, "r", F(1.0)),
    // curlnoise "Computes divergence free noise": central differences of the
    // field sum to (nearly) zero.
    (r#"vector p = {0.3, 0.7, 0.2}; float h = 0.01; float dx = (curlnoise(p + set(h, 0, 0)).x - curlnoise(p - set(h, 0, 0)).x) / (2 * h); float dy = (curlnoise(p + set(0, h, 0)).y - curlnoise(p - set(0, h, 0)).y) / (2 * h); float dz = (curlnoise(p + set(0, 0, h)).z - curlnoise(p - set(0, 0, h)).z) / (2 * h); f@r = abs(dx + dy + dz) < 0.05 * (abs(dx) + abs(dy) + abs(dz)) + 0.001;"#, "r", F(1.0)),
    // The node's parameters (see common::conformance_channel).
    (r#"f@r = ch("f");"#, "r", F(2.5)),
    (r#"f@r = chf("f");"#, "r", F(2.5)),
    (r#"f@r = chf("f", 10);"#, "r", F(2.5)),
    (r#"i@r = chi("i");"#, "r", I(7)),
    (r#"v@r = chv("v");"#, "r", V(&[1.0, 2.0, 3.0])),
    (r#"s@r = chs("s");"#, "r", S("text")),
    (r#"u@r = chu("u");"#, "r", V(&[4.0, 5.0])),
    (r#"p@r = chp("p");"#, "r", V(&[1.0, 2.0, 3.0, 4.0])),
    // sprintf: C's printf conversions.
    (r#"s@r = sprintf("%x", 255);"#, "r", S("ff")),
    (r#"s@r = sprintf("%X", 255);"#, "r", S("FF")),
    (r#"s@r = sprintf("%#x", 255);"#, "r", S("0xff")),
    (r#"s@r = sprintf("%o", 8);"#, "r", S("10")),
    (r#"s@r = sprintf("%#o", 8);"#, "r", S("010")),
    (r#"s@r = sprintf("%i|%u", 42, 7);"#, "r", S("42|7")),
    (r#"s@r = sprintf("%+d % d", 5, 5);"#, "r", S("+5  5")),
    (r#"s@r = sprintf("%03d|%-3d|", 7, -7);"#, "r", S("007|-7 |")),
    (r#"s@r = sprintf("%08.3f", -3.14159);"#, "r", S("-003.142")),
    (r#"s@r = sprintf("%5.2f|%.0f", 3.14159, 2.7);"#, "r", S(" 3.14|3")),
    (r#"s@r = sprintf("%e", 12345.678);"#, "r", S("1.234568e+04")),
    (r#"s@r = sprintf("%.2E", 0.000123);"#, "r", S("1.23E-04")),
    (r#"s@r = sprintf("%g|%g", 100000.0, 1000000.0);"#, "r", S("100000|1e+06")),
    (r#"s@r = sprintf("%g|%g", 0.0001, 0.00001);"#, "r", S("0.0001|1e-05")),
    (r#"s@r = sprintf("%.3g", 3.14159);"#, "r", S("3.14")),
    (r#"s@r = sprintf("%5s|%-5s|", "ab", "ab");"#, "r", S("   ab|ab   |")),
    (r#"s@r = sprintf("%.2s", "abcdef");"#, "r", S("ab")),
    (r#"s@r = sprintf("%c", 65);"#, "r", S("A")),
    (r#"s@r = sprintf("%d%%", 50);"#, "r", S("50%")),
    // Strings.
    (r#"s@r = toupper("abC1");"#, "r", S("ABC1")),
    (r#"s@r = tolower("AbC1");"#, "r", S("abc1")),
    (r#"s@r = strip("  ab c \t");"#, "r", S("ab c")),
    (r#"s@r = strip("xxabxx", "x");"#, "r", S("ab")),
    (r#"s@r = lstrip("  ab ");"#, "r", S("ab ")),
    (r#"s@r = lstrip("xyab", "yx");"#, "r", S("ab")),
    (r#"s@r = rstrip("  ab ");"#, "r", S("  ab")),
    (r#"s@r = rstrip("abxyx", "xy");"#, "r", S("ab")),
    (r#"s@r = replace("a-b-c", "-", "+");"#, "r", S("a+b+c")),
    (r#"s@r = replace("a-b-c", "-", "+", 1);"#, "r", S("a+b-c")),
    (r#"s@r = replace("aaa", "a", "bb");"#, "r", S("bbbbbb")),
    (r#"s@r = replace("abc", "x", "y");"#, "r", S("abc")),
    (r#"i@r = strlen("");"#, "r", I(0)),
    (r#"s@r = concat("a", "b", "c", "d");"#, "r", S("abcd")),
    (r#"i@r = endswith("hello", "llo") * 10 + startswith("hello", "llo");"#, "r", I(10)),
    (r#"s@r = chr(65);"#, "r", S("A")),
    (r#"i@r = ord("a");"#, "r", I(97)),
    // find on strings: "the first substring that starts at or after a start
    // position, and at or before an end position"; "a negative number if
    // the substring is not found".
    (r#"i@r = find("hello", "l");"#, "r", I(2)),
    (r#"i@r = find("hello", "l", 3);"#, "r", I(3)),
    (r#"i@r = find("hello", "z") < 0;"#, "r", I(1)),
    (r#"i@r = find("abcabc", "abc", 1);"#, "r", I(3)),
    (r#"i@r = find("abcabc", "bc", 2, 6);"#, "r", I(4)),
    (r#"i@r = find("abcabc", "c", 3, 4) < 0;"#, "r", I(1)),
    // "int [] find(string haystack, string needle) Returns a list of positions of occurrences".
    (r#"int w[] = find("abcabc", "bc"); i@r = len(w) * 100 + w[0] * 10 + w[1];"#, "r", I(214)),
    // split: "repeated separators ... will be merged"; maxsplits peels off tokens.
    (r#"string p[] = split("a,b,,c", ","); i@r = len(p);"#, "r", I(3)),
    (r#"string p[] = split("a b c d", " ", 1); s@r = p[1];"#, "r", S("b c d")),
    (r#"string p[] = split("a b c d", " ", 1); i@r = len(p);"#, "r", I(2)),
    (r#"string p[] = split("  a  b "); s@r = join(p, "|");"#, "r", S("a|b")),
    (r#"string a[] = {"a", "b", "c"}; s@r = join(a, ", ");"#, "r", S("a, b, c")),
    (r#"string a[]; s@r = join(a, ",");"#, "r", S("")),
    // match: glob patterns.
    (r#"i@r = match("a*c", "abbc");"#, "r", I(1)),
    (r#"i@r = match("a?c", "abbc");"#, "r", I(0)),
    (r#"i@r = match("*.bgeo", "x.bgeo");"#, "r", I(1)),
    // Regular expressions. re_match: the entire input must match.
    (r#"i@r = re_match("a.c", "abc");"#, "r", I(1)),
    (r#"i@r = re_match("b", "abc");"#, "r", I(0)),
    (r#"i@r = re_match("[0-9]+", "2024");"#, "r", I(1)),
    (r#"s@r = re_find("[0-9]+", "ab12cd345");"#, "r", S("12")),
    (r#"s@r = re_find("[0-9]+", "abc");"#, "r", S("")),
    (r#"string a[] = re_findall("[0-9]+", "a1b22c333"); s@r = join(a, ",");"#, "r", S("1,22,333")),
    // re_replace: "each non-overlapping match ... $1 syntax"; "maxreplace ... the maximum number of replacements".
    (r#"s@r = re_replace("([a-z]+)@([a-z]+)", "$2 at $1", "me@home");"#, "r", S("home at me")),
    (r#"s@r = re_replace("a", "x", "banana", 2);"#, "r", S("bxnxna")),
    (r#"s@r = re_replace("[0-9]", "_", "a1b2");"#, "r", S("a_b_")),
    (r#"string a[] = re_split("[,;]", "a,b;c"); s@r = join(a, "|");"#, "r", S("a|b|c")),
    // String indexing and slicing (Python's rules).
    (r#"string s = "hello"; s@r = s[1:3];"#, "r", S("el")),
    (r#"string s = "hello"; s@r = s[-1];"#, "r", S("o")),
    (r#"string s = "hello"; s@r = s[-3:];"#, "r", S("llo")),
    (r#"string s = "hello"; s@r = s[:2];"#, "r", S("he")),
    (r#"string s = "hello"; s@r = s[::-1];"#, "r", S("olleh")),
    (r#"string s = "hello"; s@r = s[::2];"#, "r", S("hlo")),
    (r#"string s = "hello"; s@r = s[10:];"#, "r", S("")),
    (r#"string s = "hello"; s@r = s[1:-1];"#, "r", S("ell")),
    (r#"s@r = reverse("abc");"#, "r", S("cba")),
    // Array slicing.
    (r#"int a[] = {1, 2, 3, 4, 5}; int b[] = a[-2:]; i@r = len(b) * 100 + b[0] * 10 + b[1];"#, "r", I(245)),
    (r#"int a[] = {1, 2, 3, 4, 5}; int b[] = a[::-1]; i@r = b[0] * 10000 + b[1] * 1000 + b[2] * 100 + b[3] * 10 + b[4];"#, "r", I(54321)),
    (r#"int a[] = {1, 2, 3, 4, 5}; int b[] = a[1:4:2]; i@r = len(b) * 100 + b[0] * 10 + b[1];"#, "r", I(224)),
    (r#"int a[] = {1, 2, 3, 4, 5}; int b[] = a[:-1]; i@r = len(b);"#, "r", I(4)),
    (r#"int a[] = {1, 2, 3, 4, 5}; int b[] = a[3:1]; i@r = len(b);"#, "r", I(0)),
    (r#"int a[] = {1, 2, 3, 4, 5}; int b[] = a[3:1:-1]; i@r = len(b) * 100 + b[0] * 10 + b[1];"#, "r", I(243)),
    (r#"int a[] = {1, 2, 3, 4, 5}; int b[] = a[100:]; i@r = len(b);"#, "r", I(0)),
    // Arrays. pop(array, index): "A negative index counts from the end".
    (r#"int a[] = {10, 20, 30, 40}; int x = pop(a, 1); i@r = x * 10 + len(a);"#, "r", I(203)),
    (r#"int a[] = {10, 20, 30, 40}; pop(a, 1); i@r = a[1];"#, "r", I(30)),
    (r#"int a[] = {10, 20, 30, 40}; int x = pop(a, -2); i@r = x * 10 + len(a);"#, "r", I(303)),
    // removevalue's own example: nums becomes {0, 1, 3, 1, 2, 3}.
    (r#"float nums[] = {0, 1, 2, 3, 1, 2, 3}; int r = removevalue(nums, 2); i@r = r * 100 + len(nums) * 10 + int(nums[2]);"#, "r", I(163)),
    (r#"int a[] = {1, 2}; i@r = removevalue(a, 9) * 10 + len(a);"#, "r", I(2)),
    (r#"int a[] = {1, 2, 3, 4}; int x = removeindex(a, -2); i@r = x * 10 + len(a);"#, "r", I(33)),
    // isvalidindex: "equivalent to index < len(array) && index >= -len(array)".
    (r#"int a[] = {1, 2, 3}; i@r = isvalidindex(a, 2) * 1000 + isvalidindex(a, 3) * 100 + isvalidindex(a, -3) * 10 + isvalidindex(a, -4);"#, "r", I(1010)),
    (r#"i@r = isvalidindex("abc", 2) * 10 + isvalidindex("abc", 3);"#, "r", I(10)),
    // argsort's own example: colours by the length of their names.
    (r#"string colors[] = {"Red", "Green", "Blue", "Orange", "Violet", "Indigo"}; int lengths[] = {}; foreach (string name; colors) push(lengths, len(name)); int ordering[] = argsort(lengths); s@r = join(reorder(colors, ordering), " ");"#, "r", S("Red Blue Green Orange Violet Indigo")),
    (r#"float f[] = {0.5, -1, 2}; int o[] = argsort(f); i@r = o[0] * 100 + o[1] * 10 + o[2];"#, "r", I(102)),
    (r#"int a[] = {1, 2, 3}; int o[] = {2, 0, 1}; int b[] = reorder(a, o); i@r = b[0] * 100 + b[1] * 10 + b[2];"#, "r", I(312)),
    (r#"int a[] = {1, 2, 3}; i@r = sum(a);"#, "r", I(6)),
    (r#"float f[] = {0.5, 1.5}; f@r = sum(f);"#, "r", F(2.0)),
    (r#"vector v[] = {{1, 2, 3}, {4, 5, 6}}; v@r = sum(v);"#, "r", V(&[5.0, 7.0, 9.0])),
    (r#"float e[]; f@r = sum(e);"#, "r", F(0.0)),
    (r#"int a[] = {1, 2}; upush(a, 5); i@r = len(a) * 10 + a[2];"#, "r", I(35)),
    // insert: past the end "fill the gaps with uninitialized values (for example, 0 ...)".
    (r#"int a[] = {1, 2}; insert(a, 5, 9); i@r = len(a) * 100 + a[5] * 10 + a[3];"#, "r", I(690)),
    (r#"int a[] = {1, 4}; int b[] = {2, 3}; insert(a, 1, b); i@r = a[0] * 1000 + a[1] * 100 + a[2] * 10 + a[3];"#, "r", I(1234)),
    (r#"string s = "held"; insert(s, 2, "llo wor"); s@r = s;"#, "r", S("hello world")),
    // "If index is greater than the length of the string, the value will simply be appended".
    (r#"string s = "ab"; insert(s, 10, "c"); s@r = s;"#, "r", S("abc")),
    (r#"int a[] = {1, 2, 3}; resize(a, 1); i@r = len(a);"#, "r", I(1)),
    (r#"int a[] = {1}; int b[] = {2, 3}; push(a, b); i@r = len(a) * 10 + a[2];"#, "r", I(33)),
    (r#"int a[] = {1}; int b[] = {2, 3}; append(a, b); i@r = len(a) * 10 + a[1];"#, "r", I(32)),
    (r#"float f[] = {3, -1, 2}; float s[] = sort(f); f@r = s[0] * 100 + s[2];"#, "r", F(-97.0)),
    (r#"vector v[] = array({1, 2, 3}, {4, 5, 6}); v@r = v[1];"#, "r", V(&[4.0, 5.0, 6.0])),
    (r#"int a[] = array(); i@r = len(a);"#, "r", I(0)),
    (r#"i@r = len({1, 2, 3});"#, "r", I(3)),
    // find on arrays: from a start index; every match when an array is wanted.
    (r#"string a[] = {"a", "b"}; i@r = find(a, "b");"#, "r", I(1)),
    (r#"int a[] = {1, 2, 3, 2}; int w[] = find(a, 2); i@r = len(w) * 100 + w[0] * 10 + w[1];"#, "r", I(213)),
    // Conversion.
    (r#"s@r = itoa(-17);"#, "r", S("-17")),
    (r#"f@r = atof("-0.25");"#, "r", F(-0.25)),
    // atoi: "If a base between 2 and 36 inclusive is supplied, the string is converted in base base."
    (r#"i@r = atoi("ff", 16);"#, "r", I(255)),
    (r#"i@r = atoi("101", 2);"#, "r", I(5)),
    (r#"i@r = atoi("z", 36);"#, "r", I(35)),
    // Geometry reads on points alone.
    (r#"i@r = pointvertex(0, 1);"#, "r", I(-1)),
    (r#"i@r = pointhedge(0, 1);"#, "r", I(-1)),
    (r#"i@r = nvertices(0);"#, "r", I(0)),
    (r#"vector r = relpointbbox(0, {1.5, 0, 0}); f@r = r.x;"#, "r", F(0.5)),
    (r#"int n[] = sort(nearpoints(0, {2.2, 0, 0}, 10, 2)); i@r = len(n) * 100 + n[0] * 10 + n[1];"#, "r", I(223)),
    (r#"int n[] = nearpoints(0, {0, 0, 0}, 1.5); i@r = len(n);"#, "r", I(2)),
    // pcfind: "Only the maxpoints closest points within the given radius will be returned."
    (r#"int n[] = sort(pcfind(0, "P", {0.9, 0, 0}, 1.5, 10)); i@r = len(n) * 1000 + n[0] * 100 + n[1] * 10 + n[2];"#, "r", I(3012)),
    (r#"int n[] = pcfind(0, "P", {0.9, 0, 0}, 1.5, 1); i@r = len(n) * 10 + n[0];"#, "r", I(11)),
    (r#"int h = pcopen(0, "P", {0, 0, 0}, 1.5, 10); i@r = pcnumfound(h);"#, "r", I(2)),
    (r#"int h = pcopen(0, "P", {0, 0, 0}, 10, 3); i@r = pcnumfound(h);"#, "r", I(3)),
    // pcopen: "points will be sorted from nearest to farthest" for pciterate;
    // pcimport's point.number and point.distance.
    (r#"int h = pcopen(0, "P", {2.2, 0, 0}, 10, 4); int s = 0; while (pciterate(h)) { int n; pcimport(h, "point.number", n); s = s * 10 + n; } i@r = s;"#, "r", I(2310)),
    (r#"int h = pcopen(0, "P", {2.2, 0, 0}, 10, 4); float s = 0; while (pciterate(h)) { float d; pcimport(h, "point.distance", d); s += d; } f@r = s;"#, "r", F(4.4)),
    (r#"int h = pcopen(0, "P", {1.2, 0, 0}, 10, 1); vector p; int ok = 0; while (pciterate(h)) ok = pcimport(h, "P", p); pcclose(h); v@r = p * ok;"#, "r", V(&[1.0, 0.0, 0.0])),
    // pcfilter: w_i = 1 - smooth(0, maxd * 1.1, d_i), maxd the farthest found point.
    (r#"int h = pcopen(0, "P", {0, 0, 0}, 10, 3); vector v = pcfilter(h, "P"); f@r = v.x;"#, "r", F(0.386_213_4)),
    (r#"int h = pcopen(0, "P", {1.2, 0, 0}, 10, 4); vector v = pcfilter(h, "P"); f@r = v.x;"#, "r", F(1.174_455_4)),
    // Geometry writes, read back by a second wrangle.
    (r#"setpointattrib(0, "a", 2, 7); ||| i@r = point(0, "a", 2) * 10 + point(0, "a", 1);"#, "r", I(70)),
    (r#"setpointattrib(0, "P", 1, {0, 5, 0}, "add"); ||| v@r = point(0, "P", 1);"#, "r", V(&[1.0, 5.0, 0.0])),
    (r#"setattrib(0, "point", "a", 3, -1, 5); ||| i@r = point(0, "a", 3);"#, "r", I(5)),
    (r#"setdetailattrib(0, "r", 4.5);"#, "r", F(4.5)),
    (r#"setdetailattrib(0, "r", 3); setdetailattrib(0, "r", 7, "max"); setdetailattrib(0, "r", 5, "max");"#, "r", I(7)),
    (r#"i@r = addpoint(0, {5, 6, 7});"#, "r", I(4)),
    (r#"addpoint(0, {5, 6, 7}); ||| i@r = npoints(0);"#, "r", I(5)),
    (r#"addpoint(0, {5, 6, 7}); ||| v@r = point(0, "P", 4);"#, "r", V(&[5.0, 6.0, 7.0])),
    (r#"addpoint(0, 2); ||| v@r = point(0, "P", 4);"#, "r", V(&[2.0, 0.0, 0.0])),
    (r#"i@r = addprim(0, "poly", 0, 1, 2);"#, "r", I(0)),
    (r#"addprim(0, "poly", 0, 1, 2); ||| i@r = nprimitives(0) * 10 + primvertexcount(0, 0);"#, "r", I(13)),
    (r#"int pts[] = {3, 2, 1, 0}; addprim(0, "polyline", pts); ||| i@r = primpoint(0, 0, 0) * 10 + nvertices(0);"#, "r", I(34)),
    (r#"int pr = addprim(0, "polyline"); addvertex(0, pr, 3); addvertex(0, pr, 1); ||| i@r = primpoint(0, 0, 0) * 10 + primpoint(0, 0, 1);"#, "r", I(31)),
    (r#"addprim(0, "polyline", 0, 1); ||| i@r = primintrinsic(0, "closed", 0);"#, "r", I(0)),
    (r#"removepoint(0, 1); ||| i@r = npoints(0) * 10 + int(point(0, "P", 1).x);"#, "r", I(32)),
    (r#"setpointgroup(0, "g", 2, 1); ||| i@r = inpointgroup(0, "g", 2) * 10 + npointsgroup(0, "g");"#, "r", I(11)),
    // nearpoints: "ptgroup ... an ad-hoc group pattern like @Cd.x>0.5";
    // group syntax: "@attribute==value" selects by an attribute's value.
    (r#"int a[] = expandpointgroup(0, "@P.x>1"); i@r = len(a) * 1000 + a[0] * 100 + a[1] * 10;"#, "r", I(2230)),
    (r#"int a[] = nearpoints(0, "@P.x>0", {0, 0, 0}, 10); i@r = len(a) * 1000 + a[0] * 100 + a[1] * 10 + a[2];"#, "r", I(3123)),
    (r#"int a[] = expandpointgroup(0, "@P[0]<=1 @P.x==3"); i@r = len(a) * 1000 + a[0] * 100 + a[1] * 10 + a[2];"#, "r", I(3013)),
    (r#"setpointattrib(0, "name", 1, "piece1"); setpointattrib(0, "name", 3, "rock"); ||| int a[] = expandpointgroup(0, "@name=pie*"); i@r = len(a) * 1000 + a[0];"#, "r", I(1001)),
    (r#"int a[] = expandpointgroup(0, "@nosuch>0 @P.x>9"); i@r = len(a);"#, "r", I(0)),
    // slice: "slice(nums, 1, 3) == {20, 30}; // nums[1:3]"; "If hasstart
    // is 0, it ignores start and uses 0. If hasend is 0 it ignores end and
    // uses the length of the array. If hasstep is 0 it ignores step and
    // uses 1"; "start or end ... negative count from the end".
    (r#"int n[] = {10, 20, 30, 40, 50, 60}; int a[] = slice(n, 1, 3); i@r = len(a) * 1000 + a[0] + a[1];"#, "r", I(2050)),
    (r#"int n[] = {10, 20, 30, 40, 50, 60}; int a[] = slice(n, 0, 9, 0, 9, 1, 2); i@r = len(a) * 1000 + a[0] + a[1] + a[2];"#, "r", I(3090)),
    (r#"int n[] = {10, 20, 30, 40, 50, 60}; int a[] = slice(n, 1, -1, 2); i@r = len(a) * 1000 + a[0] + a[1];"#, "r", I(2060)),
    (r#"s@r = slice("houdini", 1, -2);"#, "r", S("oudi")),
    (r#"s@r = slice("houdini", 0, 0, 0, 0, 1, -1);"#, "r", S("iniduoh")),
    // setpointattrib: "within a VEX program only one type may be written
    // to a single attribute ... a literal like 1 will be an integer write
    // so be ignored if floats were previously written."
    (r#"setpointattrib(0, "foo", 0, 1); setpointattrib(0, "foo", 1, 2.5); ||| i@r = point(0, "foo", 0) * 10 + point(0, "foo", 1);"#, "r", I(10)),
    (r#"setpointattrib(0, "bar", 0, 1.5); setpointattrib(0, "bar", 1, 2); ||| f@r = point(0, "bar", 0) + point(0, "bar", 1);"#, "r", F(1.5)),
];
