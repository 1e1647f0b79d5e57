//! The per-point maps of each projection, in the frame's own space.

use std::f32::consts::{FRAC_1_PI, PI};

use geode_geo::glam::Vec3;

use super::{Axis, Projection};

/// One point's projected coordinates; `on_axis` when u is meaningless
/// (the point lies on a cylinder's or sphere's axis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Mapped {
    pub u: f32,
    pub v: f32,
    pub on_axis: bool,
}

/// A point (in frame space) mapped by a planar, cylindrical or spherical
/// projection. Box projection needs the primitive: see [`box_face`].
pub(super) fn map_point(projection: Projection, p: Vec3) -> Mapped {
    match projection {
        Projection::Planar { axis } => {
            let (u, v) = planar(axis, p);
            Mapped {
                u: u + 0.5,
                v: v + 0.5,
                on_axis: false,
            }
        }
        Projection::Cylindrical { axis } => {
            let q = axis_up(axis, p);
            let (u, on_axis) = longitude(q);
            Mapped {
                u,
                v: q.y + 0.5,
                on_axis,
            }
        }
        Projection::Spherical { axis } => {
            let q = axis_up(axis, p);
            let (u, on_axis) = longitude(q);
            let radial = (q.x * q.x + q.z * q.z).sqrt();
            let v = if q == Vec3::ZERO {
                0.5
            } else {
                q.y.atan2(radial) * FRAC_1_PI + 0.5
            };
            Mapped { u, v, on_axis }
        }
        Projection::Box => {
            let (u, v) = box_face(FACE_POS_Z, p);
            Mapped {
                u,
                v,
                on_axis: false,
            }
        }
    }
}

/// Planar coordinates along `axis`, seen from its positive side.
fn planar(axis: Axis, p: Vec3) -> (f32, f32) {
    match axis {
        Axis::Z => (p.x, p.y),
        Axis::X => (-p.z, p.y),
        Axis::Y => (p.x, -p.z),
    }
}

/// The point with `axis` turned onto Y by an even (rotating) permutation
/// of the coordinates: Y stays, Z becomes (y, z, x), X becomes (z, x, y).
fn axis_up(axis: Axis, p: Vec3) -> Vec3 {
    match axis {
        Axis::Y => p,
        Axis::Z => Vec3::new(p.y, p.z, p.x),
        Axis::X => Vec3::new(p.z, p.x, p.y),
    }
}

/// The angle around Y over a full turn in [0, 1): 0 on +X, a quarter on
/// -Z. Points within a relative 1e-5 of the axis are flagged.
fn longitude(q: Vec3) -> (f32, bool) {
    let radial = (q.x * q.x + q.z * q.z).sqrt();
    let on_axis = radial <= 1e-5 * q.y.abs() || radial == 0.0;
    let turn = (-q.z).atan2(q.x) / (2.0 * PI);
    let u = if turn < 0.0 { turn + 1.0 } else { turn };
    // atan2 rounding can give exactly 1.0 after the shift.
    (if u >= 1.0 { 0.0 } else { u }, on_axis)
}

const FACE_POS_X: u8 = 0;
const FACE_NEG_X: u8 = 1;
const FACE_POS_Y: u8 = 2;
const FACE_NEG_Y: u8 = 3;
const FACE_POS_Z: u8 = 4;
const FACE_NEG_Z: u8 = 5;

/// The box face of a normal: its largest component's axis and sign (ties
/// go to X, then Y; a zero normal to +Z).
pub(super) fn dominant_face(n: Vec3) -> u8 {
    let a = n.abs();
    if n == Vec3::ZERO || !n.is_finite() {
        FACE_POS_Z
    } else if a.x >= a.y && a.x >= a.z {
        if n.x >= 0.0 {
            FACE_POS_X
        } else {
            FACE_NEG_X
        }
    } else if a.y >= a.z {
        if n.y >= 0.0 {
            FACE_POS_Y
        } else {
            FACE_NEG_Y
        }
    } else if n.z >= 0.0 {
        FACE_POS_Z
    } else {
        FACE_NEG_Z
    }
}

/// A frame-space point projected on box face `face`, seen from outside.
pub(super) fn box_face(face: u8, p: Vec3) -> (f32, f32) {
    let (u, v) = match face {
        FACE_POS_X => (-p.z, p.y),
        FACE_NEG_X => (p.z, p.y),
        FACE_POS_Y => (p.x, -p.z),
        FACE_NEG_Y => (p.x, p.z),
        FACE_NEG_Z => (-p.x, p.y),
        _ => (p.x, p.y),
    };
    (u + 0.5, v + 0.5)
}

/// Newell's normal of a polygon given by its corner positions (not
/// normalised; zero when degenerate).
pub(super) fn newell_normal(corners: &[Vec3]) -> Vec3 {
    let n = corners.len();
    let mut normal = Vec3::ZERO;
    for i in 0..n {
        let a = corners[i];
        let b = corners[(i + 1) % n];
        normal += Vec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    normal
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_up_is_a_rotation() {
        for axis in [Axis::X, Axis::Y, Axis::Z] {
            let e = [Vec3::X, Vec3::Y, Vec3::Z].map(|v| axis_up(axis, v));
            assert_eq!(e[0].cross(e[1]), e[2], "{axis:?}");
        }
        assert_eq!(axis_up(Axis::Z, Vec3::Z), Vec3::Y);
        assert_eq!(axis_up(Axis::X, Vec3::X), Vec3::Y);
    }

    #[test]
    fn longitude_quarter_turns() {
        assert_eq!(longitude(Vec3::X).0, 0.0);
        assert!((longitude(-Vec3::Z).0 - 0.25).abs() < 1e-7);
        assert!((longitude(-Vec3::X).0 - 0.5).abs() < 1e-7);
        assert!((longitude(Vec3::Z).0 - 0.75).abs() < 1e-7);
        assert!(longitude(Vec3::Y).1);
    }

    #[test]
    fn dominant_faces() {
        assert_eq!(dominant_face(Vec3::new(0.1, -0.9, 0.2)), FACE_NEG_Y);
        assert_eq!(dominant_face(Vec3::new(-3.0, 1.0, 2.0)), FACE_NEG_X);
        assert_eq!(dominant_face(Vec3::ZERO), FACE_POS_Z);
    }
}
