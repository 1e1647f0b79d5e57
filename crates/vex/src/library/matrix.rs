//! Matrices, transforms and quaternions (SideFX's "Matrices" and
//! "Quaternions" categories) and the products lowered to calls. VEX
//! multiplies row vectors (`v * m` applies `m`); a transform built from
//! steps applies them left to right (`maketransform(XFORM_SRT, ...)` is
//! `S * R * T`), which in glam's column convention is the reverse product.

use geode_geo::glam::{Mat3, Mat4, Quat, Vec3, Vec4};

use super::crack::{compose, crack, Parts, Pivot};
use super::support::{euler_of, euler_quat, m3, m4, of_mat, of_quat, q, v3};
use super::{a, form, lane, out, Category, Function, Ret, F, I, M3, M4, V, V4};
use crate::program::{Lane, Stop};
use crate::ty::Ty;
use crate::value::Val;

const C: Category = Category::Matrices;
const Q: Category = Category::Quaternions;
const M: Ret = Ret::Context(&[Ty::Mat4, Ty::Mat3]);
const VEC: Ret = Ret::Is(Ty::Vec3);

#[rustfmt::skip]
pub const FUNCTIONS: &[Function] = &[
    lane("ident", C, "The identity matrix (a matrix3 or matrix, from the context).", &[
        form(M, &[], ident),
    ]),
    lane("invert", C, "The inverse of a matrix (unchanged if singular), or 1/x.", &[
        form(Ret::Is(Ty::Mat4), &[a(M4, "m")], invert),
        form(Ret::Is(Ty::Mat3), &[a(M3, "m")], invert),
        form(Ret::Is(Ty::Float), &[a(F, "x")], invert),
    ]),
    lane("transpose", C, "The transposed matrix.", &[
        form(Ret::Is(Ty::Mat4), &[a(M4, "m")], transpose),
        form(Ret::Is(Ty::Mat3), &[a(M3, "m")], transpose),
    ]),
    lane("determinant", C, "The determinant of a matrix.", &[
        form(Ret::Is(Ty::Float), &[a(M4, "m")], determinant),
        form(Ret::Is(Ty::Float), &[a(M3, "m")], determinant),
    ]),
    lane("rotate", C, "Rotates a matrix variable by angle (radians) about axis, after what it does.", &[
        form(Ret::Is(Ty::Void), &[out(M4, "m"), a(F, "angle"), a(V, "axis")], rotate),
        form(Ret::Is(Ty::Void), &[out(M3, "m"), a(F, "angle"), a(V, "axis")], rotate),
    ]),
    lane("prerotate", C, "Rotates a matrix variable by angle (radians) about axis, before what it does.", &[
        form(Ret::Is(Ty::Void), &[out(M4, "m"), a(F, "angle"), a(V, "axis")], prerotate),
        form(Ret::Is(Ty::Void), &[out(M3, "m"), a(F, "angle"), a(V, "axis")], prerotate),
    ]),
    lane("scale", C, "Scales a matrix variable, after what it does.", &[
        form(Ret::Is(Ty::Void), &[out(M4, "m"), a(V, "scale")], scale),
        form(Ret::Is(Ty::Void), &[out(M3, "m"), a(V, "scale")], scale),
    ]),
    lane("prescale", C, "Scales a matrix variable, before what it does.", &[
        form(Ret::Is(Ty::Void), &[out(M4, "m"), a(V, "scale")], prescale),
        form(Ret::Is(Ty::Void), &[out(M3, "m"), a(V, "scale")], prescale),
    ]),
    lane("translate", C, "Translates a matrix variable, after what it does.", &[
        form(Ret::Is(Ty::Void), &[out(M4, "m"), a(V, "offset")], translate),
    ]),
    lane("pretranslate", C, "Translates a matrix variable, before what it does.", &[
        form(Ret::Is(Ty::Void), &[out(M4, "m"), a(V, "offset")], pretranslate),
    ]),
    lane("maketransform", C, "A transform from translate, rotate (degrees) and scale in the order trs (XFORM_SRT...) and rotation order xyz (XFORM_XYZ...), about a pivot; or from z and y axes and a position.", &[
        form(M, &[a(I, "trs"), a(I, "xyz"), a(V, "t"), a(V, "r"), a(V, "s"), a(V, "p")], make_trs).opt(2),
        form(M, &[a(V, "zaxis"), a(V, "yaxis"), a(V, "translate")], make_axes).opt(1),
    ]),
    lane("cracktransform", C, "The translate (c 0), rotate (1: degrees, 4: radians), scale (2) or shears (3: xy, xz, yz) that maketransform's order trs and rotation order xyz would make xform from, about a pivot (and a pivot rotation, degrees); or all of them into t, r (degrees), s and shears.", &[
        form(VEC, &[a(I, "trs"), a(I, "xyz"), a(I, "c"), a(V, "pivot"), a(V, "pivot_rotate"), a(M4, "xform")], crack_one),
        form(VEC, &[a(I, "trs"), a(I, "xyz"), a(I, "c"), a(V, "pivot"), a(M4, "xform")], crack_one),
        form(Ret::Is(Ty::Void), &[a(I, "trs"), a(I, "xyz"), a(V, "pivot"), a(V, "pivot_rotate"), a(M4, "xform"), out(V, "t"), out(V, "r"), out(V, "s"), out(V, "shears")], crack_all),
        form(Ret::Is(Ty::Void), &[a(I, "trs"), a(I, "xyz"), a(V, "pivot"), a(M4, "xform"), out(V, "t"), out(V, "r"), out(V, "s")], crack_all),
    ]),
    lane("lookat", C, "The rotation that points -z from `from` towards `to`, with y towards up.", &[
        form(Ret::Is(Ty::Mat3), &[a(V, "from"), a(V, "to"), a(V, "up")], lookat).opt(1),
    ]),
    lane("qconvert", Q, "The rotation matrix of a quaternion.", &[
        form(Ret::Is(Ty::Mat3), &[a(V4, "q")], qconvert),
    ]),
    lane("quaternion", Q, "A quaternion from a rotation matrix, an angle (radians) and axis, or a rotation vector (axis times angle).", &[
        form(Ret::Is(Ty::Vec4), &[a(M3, "m")], quaternion),
        form(Ret::Is(Ty::Vec4), &[a(F, "angle"), a(V, "axis")], quaternion_axis),
        form(Ret::Is(Ty::Vec4), &[a(V, "rotation")], quaternion),
    ]),
    lane("qmultiply", Q, "The product of two quaternions (q2 applied first).", &[
        form(Ret::Is(Ty::Vec4), &[a(V4, "q1"), a(V4, "q2")], qmultiply),
    ]),
    lane("qrotate", Q, "A vector rotated by a quaternion.", &[
        form(Ret::Is(Ty::Vec3), &[a(V4, "q"), a(V, "v")], qrotate),
    ]),
    lane("qinvert", Q, "The inverse rotation of a quaternion.", &[
        form(Ret::Is(Ty::Vec4), &[a(V4, "q")], qinvert),
    ]),
    lane("qdistance", Q, "The angle (radians) between two rotations.", &[
        form(Ret::Is(Ty::Float), &[a(V4, "q1"), a(V4, "q2")], qdistance),
    ]),
    lane("slerp", Q, "Spherical interpolation between two rotations (quaternions or matrices) by bias in [0, 1].", &[
        form(Ret::Is(Ty::Vec4), &[a(V4, "q1"), a(V4, "q2"), a(F, "bias")], slerp),
        form(Ret::Is(Ty::Mat3), &[a(M3, "m1"), a(M3, "m2"), a(F, "bias")], slerp),
        form(Ret::Is(Ty::Mat4), &[a(M4, "m1"), a(M4, "m2"), a(F, "bias")], slerp),
    ]),
    lane("eulertoquaternion", Q, "The quaternion of Euler angles (radians) in a rotation order (XFORM_XYZ...).", &[
        form(Ret::Is(Ty::Vec4), &[a(V, "rotations"), a(I, "order")], eulertoquaternion),
    ]),
    lane("quaterniontoeuler", Q, "Euler angles (radians) in a rotation order (XFORM_XYZ...) of a quaternion.", &[
        form(Ret::Is(Ty::Vec3), &[a(V4, "q"), a(I, "order")], quaterniontoeuler),
    ]),
    lane("dihedral", Q, "The shortest rotation taking direction a to direction b (a quaternion, or a matrix3 from the context).", &[
        form(Ret::Context(&[Ty::Vec4, Ty::Mat3]), &[a(V, "a"), a(V, "b")], dihedral),
    ]),
];

/// The products lowered to calls.
pub mod intrinsics {
    use super::super::Callee;

    pub const MATMUL: Callee = Callee {
        name: "*",
        lane: super::matmul,
        bytes: None,
    };
    pub const VECMAT: Callee = Callee {
        name: "*",
        lane: super::vecmat,
        bytes: None,
    };
    pub const TRANSPOSE: Callee = Callee {
        name: "transpose",
        lane: super::transpose,
        bytes: None,
    };
    pub const IDENT: Callee = Callee {
        name: "ident",
        lane: super::ident,
        bytes: None,
    };
}

fn ident(lane: &mut Lane, _: &mut [Val]) -> Result<Val, Stop> {
    Ok(of_mat(lane.out, Mat4::IDENTITY))
}

/// VEX `a * b` (a applied first).
fn matmul(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let (x, y) = (m4(&a[0]), m4(&a[1]));
    Ok(of_mat(lane.out, y * x))
}

/// VEX `v * m`: a vector3 through a matrix3, a point through a matrix, a
/// vector4 through a matrix as is.
fn vecmat(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let v = a[0].floats();
    Ok(match a[1].floats().len() {
        9 => Val::vec(&(m3(&a[1]) * v3(&a[0])).to_array()),
        _ if v.len() == 4 => Val::vec(&(m4(&a[1]) * Vec4::from_slice(v)).to_array()),
        _ => Val::vec(&m4(&a[1]).transform_point3(v3(&a[0])).to_array()),
    })
}

fn invert(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(match lane.out {
        Ty::Float => Val::float(if a[0].f() == 0.0 { 0.0 } else { 1.0 / a[0].f() }),
        Ty::Mat3 => {
            let m = m3(&a[0]);
            if m.determinant() == 0.0 {
                a[0].clone()
            } else {
                Val::vec(&m.inverse().to_cols_array())
            }
        }
        _ => {
            let m = m4(&a[0]);
            if m.determinant() == 0.0 {
                a[0].clone()
            } else {
                Val::vec(&m.inverse().to_cols_array())
            }
        }
    })
}

fn transpose(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(match lane.out {
        Ty::Mat3 => Val::vec(&m3(&a[0]).transpose().to_cols_array()),
        _ => Val::vec(&m4(&a[0]).transpose().to_cols_array()),
    })
}

fn determinant(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::float(if a[0].floats().len() == 9 {
        m3(&a[0]).determinant()
    } else {
        m4(&a[0]).determinant()
    }))
}

/// The matrix argument's type, for writing it back.
fn mat_ty(v: &Val) -> Ty {
    if v.floats().len() == 9 {
        Ty::Mat3
    } else {
        Ty::Mat4
    }
}

/// `m = m * step` (VEX), the step applied after the matrix.
fn after(a: &mut [Val], step: Mat4) {
    let ty = mat_ty(&a[0]);
    a[0] = of_mat(ty, step * m4(&a[0]));
}

/// `m = step * m` (VEX), the step applied before the matrix.
fn before(a: &mut [Val], step: Mat4) {
    let ty = mat_ty(&a[0]);
    a[0] = of_mat(ty, m4(&a[0]) * step);
}

fn axis_rotation(angle: f32, axis: Vec3) -> Mat4 {
    Mat4::from_axis_angle(axis.normalize_or_zero(), angle)
}

fn rotate(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let r = axis_rotation(a[1].f(), v3(&a[2]));
    after(a, r);
    Ok(Val::I(0))
}

fn prerotate(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let r = axis_rotation(a[1].f(), v3(&a[2]));
    before(a, r);
    Ok(Val::I(0))
}

fn scale(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let s = Mat4::from_scale(v3(&a[1]));
    after(a, s);
    Ok(Val::I(0))
}

fn prescale(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let s = Mat4::from_scale(v3(&a[1]));
    before(a, s);
    Ok(Val::I(0))
}

fn translate(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let t = Mat4::from_translation(v3(&a[1]));
    after(a, t);
    Ok(Val::I(0))
}

fn pretranslate(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let t = Mat4::from_translation(v3(&a[1]));
    before(a, t);
    Ok(Val::I(0))
}

/// `maketransform(trs, xyz, t, r, s[, p])`: the steps in the order the
/// `trs` code names (`XFORM_SRT` = 0, STR, RST, RTS, TSR, TRS = 5), the
/// rotation (degrees) in the order `xyz` names, all about the pivot `p`.
fn make_trs(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let parts = Parts {
        t: v3(&a[2]),
        r: v3(&a[3]) * std::f32::consts::PI / 180.0,
        s: a.get(4).map_or(Vec3::ONE, v3),
        shear: Vec3::ZERO,
    };
    let pivot = a.get(5).map(|p| Pivot {
        at: v3(p),
        rotate: Vec3::ZERO,
    });
    Ok(of_mat(lane.out, compose(a[0].i(), a[1].i(), parts, pivot)))
}

/// `cracktransform(trs, xyz, c, pivot, [pivot_rotate,] xform)`: one part
/// of the transform, as `c` picks it.
fn crack_one(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let rotate = if a.len() == 6 { v3(&a[4]) } else { Vec3::ZERO };
    let pivot = Pivot {
        at: v3(&a[3]),
        rotate: rotate * std::f32::consts::PI / 180.0,
    };
    let parts = crack(a[0].i(), a[1].i(), m4(&a[a.len() - 1]), pivot);
    let part = match a[2].i() {
        0 => parts.t,
        1 => parts.r * 180.0 / std::f32::consts::PI,
        2 => parts.s,
        3 => parts.shear,
        4 => parts.r,
        other => {
            return Err(Stop::Msg(format!(
                "cracktransform: c is 0 (translate), 1 (rotate, degrees), 2 (scale), 3 (shears) or 4 (rotate, radians), not {other}"
            )))
        }
    };
    Ok(Val::vec(&part.to_array()))
}

/// `cracktransform(trs, xyz, pivot, [pivot_rotate,] xform, &t, &r, &s[,
/// &shears])`: every part at once (rotation in degrees).
fn crack_all(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    // (trs, xyz, pivot, pivot_rotate, xform, t, r, s, shears) or
    // (trs, xyz, pivot, xform, t, r, s).
    let with_rotate = a.len() == 9;
    let rotate = if with_rotate { v3(&a[3]) } else { Vec3::ZERO };
    let pivot = Pivot {
        at: v3(&a[2]),
        rotate: rotate * std::f32::consts::PI / 180.0,
    };
    let at = if with_rotate { 4 } else { 3 };
    let parts = crack(a[0].i(), a[1].i(), m4(&a[at]), pivot);
    a[at + 1] = Val::vec(&parts.t.to_array());
    a[at + 2] = Val::vec(&(parts.r * 180.0 / std::f32::consts::PI).to_array());
    a[at + 3] = Val::vec(&parts.s.to_array());
    if with_rotate {
        a[at + 4] = Val::vec(&parts.shear.to_array());
    }
    Ok(Val::I(0))
}

/// `maketransform(zaxis, yaxis[, translate])`: an orthonormal frame with
/// z along zaxis and y as close to yaxis as z allows.
fn make_axes(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let z = v3(&a[0]).normalize_or_zero();
    let x = v3(&a[1]).cross(z).normalize_or_zero();
    let y = z.cross(x);
    let mut m = Mat4::from_mat3(Mat3::from_cols(x, y, z));
    if let Some(t) = a.get(2) {
        m.w_axis = v3(t).extend(1.0);
    }
    Ok(of_mat(lane.out, m))
}

fn lookat(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let (from, to) = (v3(&a[0]), v3(&a[1]));
    let up = a.get(2).map_or(Vec3::Y, v3);
    let z = (from - to).normalize_or_zero();
    let x = up.cross(z).normalize_or_zero();
    let y = z.cross(x);
    Ok(of_mat(lane.out, Mat4::from_mat3(Mat3::from_cols(x, y, z))))
}

fn qconvert(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::vec(
        &Mat3::from_quat(q(&a[0]).normalize()).to_cols_array(),
    ))
}

fn quaternion(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(if a[0].floats().len() >= 9 {
        of_quat(Quat::from_mat3(&m3(&a[0])).normalize())
    } else {
        // A rotation vector: axis times angle in radians.
        let v = v3(&a[0]);
        let angle = v.length();
        of_quat(if angle == 0.0 {
            Quat::IDENTITY
        } else {
            Quat::from_axis_angle(v / angle, angle)
        })
    })
}

fn quaternion_axis(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let axis = v3(&a[1]).normalize_or_zero();
    Ok(of_quat(if axis == Vec3::ZERO {
        Quat::IDENTITY
    } else {
        Quat::from_axis_angle(axis, a[0].f())
    }))
}

fn qmultiply(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(of_quat(q(&a[0]) * q(&a[1])))
}

fn qrotate(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::vec(&(q(&a[0]) * v3(&a[1])).to_array()))
}

fn qinvert(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let r = q(&a[0]);
    let n = r.length_squared();
    Ok(of_quat(if n == 0.0 { r } else { r.conjugate() / n }))
}

fn qdistance(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let (x, y) = (q(&a[0]).normalize(), q(&a[1]).normalize());
    Ok(Val::float(x.angle_between(y)))
}

fn slerp(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let t = a[2].f();
    Ok(match lane.out {
        Ty::Vec4 => of_quat(q(&a[0]).normalize().slerp(q(&a[1]).normalize(), t)),
        out => {
            // Rotations interpolate spherically; scale and translation
            // linearly.
            let (s0, r0, t0) = m4(&a[0]).to_scale_rotation_translation();
            let (s1, r1, t1) = m4(&a[1]).to_scale_rotation_translation();
            let m = Mat4::from_scale_rotation_translation(
                s0.lerp(s1, t),
                r0.slerp(r1, t),
                t0.lerp(t1, t),
            );
            of_mat(out, m)
        }
    })
}

fn eulertoquaternion(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(of_quat(euler_quat(v3(&a[0]), a[1].i())))
}

fn quaterniontoeuler(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::vec(&euler_of(q(&a[0]), a[1].i()).to_array()))
}

fn dihedral(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let (x, y) = (v3(&a[0]).normalize_or_zero(), v3(&a[1]).normalize_or_zero());
    let r = Quat::from_rotation_arc(x, y);
    Ok(if lane.out == Ty::Mat3 {
        Val::vec(&Mat3::from_quat(r).to_cols_array())
    } else {
        of_quat(r)
    })
}
