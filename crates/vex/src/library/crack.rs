//! Transforms as steps and back, for `maketransform` and `cracktransform`.
//!
//! `compose` makes translate, rotate and scale (with shears) into one
//! matrix in a transform order about a pivot; `crack` takes such a matrix
//! apart again.
//!
//! In glam's column convention (the same 16 slots as VEX's row-vector
//! matrix, see `support`), the steps of order `trs` multiply right to left
//! (`XFORM_SRT` is `T * R * U`), all inside the pivot's frame:
//! `T(pivot) * PR * steps * PR^-1 * T(-pivot)`, PR the pivot rotation
//! (taken in the rotation order `xyz`: SideFX's pages do not say).
//!
//! The scale step U is scale then shear: in VEX's row-vector form `S * H`
//! with H the rows (1, 0, 0), (xy, 1, 0), (xz, yz, 1) (the classic
//! decomposition of Thomas, "Decomposing a matrix into simple
//! transformations", Graphics Gems II; SideFX's pages do not spell the
//! shear matrix out). In glam's form it is the upper triangular
//! `[[sx, xy sy, xz sz], [0, sy, yz sz], [0, 0, sz]]` (rows), so cracking
//! the linear part is a QR decomposition: `R * U` when scale comes before
//! rotate, `U * R` when after.

use geode_geo::glam::{Mat3, Mat4, Quat, Vec3};

use super::support::{euler_of, euler_quat};

/// What a transform is made of: rotation in radians; shears (xy, xz, yz).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Parts {
    pub t: Vec3,
    pub r: Vec3,
    pub s: Vec3,
    pub shear: Vec3,
}

/// The pivot frame: its origin and its rotation (radians).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pivot {
    pub at: Vec3,
    pub rotate: Vec3,
}

/// Whether the order scales before it rotates (`XFORM_SRT`, `XFORM_STR`,
/// `XFORM_TSR`); codes past the six read as `XFORM_SRT`, as
/// `maketransform` reads them.
fn scales_first(trs: i32) -> bool {
    !matches!(trs, 2 | 3 | 5)
}

/// The scale step: scale, then shear (see the module's notes).
pub fn scale_shear(s: Vec3, shear: Vec3) -> Mat3 {
    Mat3::from_cols(
        Vec3::new(s.x, 0.0, 0.0),
        Vec3::new(shear.x * s.y, s.y, 0.0),
        Vec3::new(shear.y * s.z, shear.z * s.z, s.z),
    )
}

/// The transform of `parts` in order `trs` and rotation order `xyz`,
/// about `pivot` when one is given.
pub fn compose(trs: i32, xyz: i32, parts: Parts, pivot: Option<Pivot>) -> Mat4 {
    let t = Mat4::from_translation(parts.t);
    let r = Mat4::from_quat(euler_quat(parts.r, xyz));
    let s = if parts.shear == Vec3::ZERO {
        Mat4::from_scale(parts.s)
    } else {
        Mat4::from_mat3(scale_shear(parts.s, parts.shear))
    };
    let steps = match trs {
        1 => [s, t, r],
        2 => [r, s, t],
        3 => [r, t, s],
        4 => [t, s, r],
        5 => [t, r, s],
        _ => [s, r, t],
    };
    // The first step applies first: glam's product is reversed.
    let mut m = steps[2] * steps[1] * steps[0];
    if let Some(p) = pivot {
        if p.rotate != Vec3::ZERO {
            let pr = euler_quat(p.rotate, xyz);
            m = Mat4::from_quat(pr) * m * Mat4::from_quat(pr.inverse());
        }
        m = Mat4::from_translation(p.at) * m * Mat4::from_translation(-p.at);
    }
    m
}

/// The parts `compose` would make `m` from (in order `trs`, rotation
/// order `xyz`, about `pivot`). A singular matrix gives zero scales where
/// it is flat, its rotation completed to a right-handed one.
pub fn crack(trs: i32, xyz: i32, m: Mat4, pivot: Pivot) -> Parts {
    let x = unpivot(m, xyz, pivot);
    let l = Mat3::from_mat4(x);
    let (rot, s, shear) = if scales_first(trs) {
        rotate_then_scale(l)
    } else {
        scale_then_rotate(l)
    };
    let t = translation(trs, x.w_axis.truncate(), l, rot, scale_shear(s, shear));
    Parts {
        t,
        r: euler_of(Quat::from_mat3(&rot), xyz),
        s,
        shear,
    }
}

/// The steps' matrix inside the pivot frame: `PR^-1 T(-p) m T(p) PR`.
fn unpivot(m: Mat4, xyz: i32, pivot: Pivot) -> Mat4 {
    let pr = euler_quat(pivot.rotate, xyz);
    Mat4::from_quat(pr.inverse())
        * Mat4::from_translation(-pivot.at)
        * m
        * Mat4::from_translation(pivot.at)
        * Mat4::from_quat(pr)
}

/// The translate step's own value from the transform's translation `x`:
/// what the steps after it (`R`, `U`, or both: the linear part `l`) did
/// to it undone.
fn translation(trs: i32, x: Vec3, l: Mat3, rot: Mat3, u: Mat3) -> Vec3 {
    let undo = |m: Mat3| {
        if m.determinant().abs() > f32::MIN_POSITIVE {
            m.inverse() * x
        } else {
            x
        }
    };
    match trs {
        // STR: R T U: the rotation moved it.
        1 => rot.transpose() * x,
        // RTS: U T R: the scale moved it.
        3 => undo(u),
        // TSR, TRS: both did.
        4 | 5 => undo(l),
        _ => x,
    }
}

/// `l = R * U` (scale, then rotate): Gram-Schmidt down the columns.
fn rotate_then_scale(l: Mat3) -> (Mat3, Vec3, Vec3) {
    let g = orthonormalise([l.x_axis, l.y_axis, l.z_axis]);
    let s = Vec3::new(g.len[0], g.len[1], g.len[2]);
    let shear = Vec3::new(
        ratio(g.dot[0], g.len[1]),
        ratio(g.dot[1], g.len[2]),
        ratio(g.dot[2], g.len[2]),
    );
    let rot = Mat3::from_cols(g.unit[0], g.unit[1], g.unit[2]);
    right_handed(rot, s, shear)
}

/// `l = U * R` (rotate, then scale): Gram-Schmidt up the rows.
fn scale_then_rotate(l: Mat3) -> (Mat3, Vec3, Vec3) {
    let rows = l.transpose();
    let g = orthonormalise([rows.z_axis, rows.y_axis, rows.x_axis]);
    let s = Vec3::new(g.len[2], g.len[1], g.len[0]);
    // Row 1 is sy r1 + yz sz r2; row 0 is sx r0 + xy sy r1 + xz sz r2.
    let shear = Vec3::new(
        ratio(g.dot[2], g.len[1]),
        ratio(g.dot[1], g.len[0]),
        ratio(g.dot[0], g.len[0]),
    );
    let rot = Mat3::from_cols(g.unit[2], g.unit[1], g.unit[0]).transpose();
    right_handed(rot, s, shear)
}

/// A reflection is a negative scale: `-R * -U` is the same product.
fn right_handed(rot: Mat3, s: Vec3, shear: Vec3) -> (Mat3, Vec3, Vec3) {
    if rot.determinant() < 0.0 {
        (-rot, -s, shear)
    } else {
        (rot, s, shear)
    }
}

fn ratio(a: f32, b: f32) -> f32 {
    if b.abs() > f32::MIN_POSITIVE {
        a / b
    } else {
        0.0
    }
}

/// Three vectors made orthonormal in order: each one's length after the
/// earlier ones' parts are taken out, and those parts (`dot`: a1 on e0,
/// a2 on e0, a2 on e1).
struct Orthonormal {
    unit: [Vec3; 3],
    len: [f32; 3],
    dot: [f32; 3],
}

fn orthonormalise(a: [Vec3; 3]) -> Orthonormal {
    // Below this a direction is lost in rounding: the axis is flat.
    const FLAT: f32 = 1e-12;
    let unit = |v: Vec3| {
        let n = v.length();
        (n > FLAT)
            .then(|| v / n)
            .map_or((None, 0.0), |u| (Some(u), n))
    };
    let (e0, n0) = unit(a[0]);
    let on = |v: Vec3, e: Option<Vec3>| e.map_or(0.0, |e| v.dot(e));
    let d10 = on(a[1], e0);
    let (e1, n1) = unit(a[1] - d10 * e0.unwrap_or(Vec3::ZERO));
    let (d20, d21) = (on(a[2], e0), on(a[2], e1));
    let rest = a[2] - d20 * e0.unwrap_or(Vec3::ZERO) - d21 * e1.unwrap_or(Vec3::ZERO);
    let (e2, n2) = unit(rest);
    Orthonormal {
        unit: complete([e0, e1, e2]),
        len: [n0, n1, n2],
        dot: [d10, d20, d21],
    }
}

/// The missing axes of a frame, right-handed where the others allow.
fn complete(e: [Option<Vec3>; 3]) -> [Vec3; 3] {
    match e {
        [Some(a), Some(b), Some(c)] => [a, b, c],
        [None, Some(b), Some(c)] => [b.cross(c), b, c],
        [Some(a), None, Some(c)] => [a, c.cross(a), c],
        [Some(a), Some(b), None] => [a, b, a.cross(b)],
        [Some(a), None, None] => {
            let b = a.any_orthonormal_vector();
            [a, b, a.cross(b)]
        }
        [None, Some(b), None] => {
            let c = b.any_orthonormal_vector();
            [b.cross(c), b, c]
        }
        [None, None, Some(c)] => {
            let a = c.any_orthonormal_vector();
            [a, c.cross(a), c]
        }
        [None, None, None] => [Vec3::X, Vec3::Y, Vec3::Z],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).abs().max_element() < 1e-4
    }

    /// Parts with every kind of step; of the angles, the one about the
    /// rotation order's middle axis inside (-90, 90) degrees and the
    /// others beyond, so they are the only angles for the rotation.
    fn parts(xyz: i32, shear: Vec3) -> Parts {
        let mut r = Vec3::new(120.0, 160.0, -150.0);
        let middle = match xyz {
            2 | 4 => 0,
            1 | 3 => 2,
            _ => 1,
        };
        r[middle] = -35.0;
        Parts {
            t: Vec3::new(1.0, -2.0, 3.5),
            r: r * std::f32::consts::PI / 180.0,
            s: Vec3::new(2.0, 0.5, 3.0),
            shear,
        }
    }

    #[test]
    fn cracking_what_compose_made_gives_its_parts_in_every_order() {
        let pivots = [
            Pivot::default(),
            Pivot {
                at: Vec3::new(0.5, 4.0, -1.0),
                rotate: Vec3::new(0.3, -0.2, 1.1),
            },
        ];
        for shear in [Vec3::ZERO, Vec3::new(0.5, -0.25, 0.75)] {
            for pivot in pivots {
                for trs in 0..6 {
                    for xyz in 0..6 {
                        let want = parts(xyz, shear);
                        let m = compose(trs, xyz, want, Some(pivot));
                        let got = crack(trs, xyz, m, pivot);
                        let ok = close(got.t, want.t)
                            && close(got.r, want.r)
                            && close(got.s, want.s)
                            && close(got.shear, want.shear);
                        assert!(ok, "trs {trs} xyz {xyz} {pivot:?}: {got:?} != {want:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn a_mirror_is_a_negative_scale_and_a_flat_axis_a_zero_one() {
        let mirror = Mat4::from_scale(Vec3::new(-1.0, -2.0, -3.0));
        let got = crack(0, 0, mirror, Pivot::default());
        assert!(close(
            compose(0, 0, got, None).transform_point3(Vec3::ONE),
            Vec3::new(-1.0, -2.0, -3.0)
        ));
        let flat = crack(
            0,
            0,
            Mat4::from_scale(Vec3::new(2.0, 0.0, 1.0)),
            Pivot::default(),
        );
        assert!(close(flat.s, Vec3::new(2.0, 0.0, 1.0)), "{flat:?}");
        assert!(close(flat.r, Vec3::ZERO), "{flat:?}");
        let zero = crack(5, 3, Mat4::ZERO, Pivot::default());
        assert!([zero.t, zero.r, zero.s, zero.shear]
            .iter()
            .all(|v| v.is_finite()));
    }
}
