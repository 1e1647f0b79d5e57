//! Affine transform of a geometry, each attribute treated by its type-info tag.

use glam::{Mat3, Mat4, Quat, Vec3, Vec4};
use rayon::prelude::*;

use crate::attrib::{AttribData, AttribTable, TypeInfo};
use crate::geometry::Geometry;

/// What an affine map does to each kind of attribute, written once for the
/// in-place and the copying transform.
struct Affine {
    m: Mat4,
    /// The linear part as a 4x4 matrix with no translation.
    linear: Mat4,
    /// Inverse transpose of the linear part (its own self when singular).
    normal_m: Mat3,
    /// When the linear part is a rotation times a uniform scale: `normal_m`
    /// divided by that scale, which turns a normal keeping its length with
    /// no square root (the common case, and the fast one).
    similar: Option<Mat3>,
    /// The rotation part.
    rot: Quat,
}

impl Affine {
    fn new(m: Mat4) -> Affine {
        let lin = Mat3::from_mat4(m);
        let normal_m = if lin.determinant().abs() > f32::MIN_POSITIVE {
            lin.inverse().transpose()
        } else {
            lin
        };
        let (_, rot, _) = Mat4::from_mat3(lin).to_scale_rotation_translation();
        let rot = if rot.is_finite() {
            rot.normalize()
        } else {
            Quat::IDENTITY
        };
        let scale = normal_m.x_axis.length();
        let (x, y, z) = (normal_m.x_axis, normal_m.y_axis, normal_m.z_axis);
        let tol = 1e-6 * scale * scale;
        let similar = (scale > 0.0
            && (y.length_squared() - scale * scale).abs() <= tol
            && (z.length_squared() - scale * scale).abs() <= tol
            && x.dot(y).abs() <= tol
            && y.dot(z).abs() <= tol
            && z.dot(x).abs() <= tol)
            .then(|| normal_m * (1.0 / scale));
        Affine {
            m,
            linear: Mat4::from_mat3(lin),
            normal_m,
            similar,
            rot,
        }
    }

    fn normal(&self, n: Vec3) -> Vec3 {
        if let Some(r) = &self.similar {
            return *r * n;
        }
        let len = n.length();
        if len > 0.0 {
            (self.normal_m * n).normalize_or_zero() * len
        } else {
            n
        }
    }

    fn quat(&self, q: Quat) -> Quat {
        (self.rot * q).normalize()
    }

    /// The column `info` says changes, changed (`None`: it stays as it is):
    /// the one rule of both the in-place and the copying transform.
    fn map(&self, info: TypeInfo, data: &AttribData) -> Option<AttribData> {
        Some(match (info, data) {
            (TypeInfo::Position, AttribData::Vec3(v)) => {
                AttribData::Vec3(par_map(v, |p| self.m.transform_point3(p)))
            }
            (TypeInfo::Vector, AttribData::Vec3(v)) => {
                AttribData::Vec3(par_map(v, |p| self.m.transform_vector3(p)))
            }
            (TypeInfo::Normal, AttribData::Vec3(v)) => {
                AttribData::Vec3(par_map(v, |n| self.normal(n)))
            }
            (TypeInfo::Quaternion, AttribData::Quat(v)) => {
                AttribData::Quat(par_map(v, |q| self.quat(q)))
            }
            (TypeInfo::Quaternion, AttribData::Vec4(v)) => {
                AttribData::Vec4(par_map(v, |q| Vec4::from(self.quat(Quat::from_vec4(q)))))
            }
            (TypeInfo::Transform, AttribData::Mat4(v)) => {
                AttribData::Mat4(par_map(v, |x| self.linear * x))
            }
            _ => return None,
        })
    }

    /// Packed instances turn by the linear part (their translation comes
    /// from their point).
    fn turn_instances(&self, g: &mut Geometry) {
        if g.packed.is_empty() {
            return;
        }
        for inst in g.packed.make_mut().iter_mut() {
            inst.transform = self.linear * inst.transform;
        }
    }
}

/// Elements per parallel task (below it, waking threads costs more).
const CHUNK: usize = 1 << 14;

fn par_map<T: Copy + Send + Sync>(v: &[T], f: impl Fn(T) -> T + Sync) -> Vec<T> {
    let mut out = Vec::with_capacity(v.len());
    v.par_iter()
        .with_min_len(CHUNK)
        .map(|x| f(*x))
        .collect_into_vec(&mut out);
    out
}

fn mapped_table(t: &AttribTable, xf: &Affine) -> AttribTable {
    t.map_columns(|a| xf.map(a.type_info, a.data()))
}

/// Applies `m` to the geometry: positions fully, vectors by the linear part,
/// normals by the inverse transpose (keeping their length), quaternions by the
/// rotation part, local transforms and packed instances by the linear part
/// (their translation comes from their point).
pub fn transform(g: &mut Geometry, m: Mat4) {
    let xf = Affine::new(m);
    g.invalidate_content();
    for t in [&mut g.points, &mut g.vertices, &mut g.prims, &mut g.detail] {
        for (_, a) in t.iter_mut() {
            if let Some(data) = xf.map(a.type_info, a.data()) {
                *a = a.with_data(data);
            }
        }
    }
    xf.turn_instances(g);
}

/// `transform` of a copy: each changed column is read once and written once
/// (no copy first), the rest copied.
pub fn transformed(g: &Geometry, m: Mat4) -> Geometry {
    let xf = Affine::new(m);
    let mut out = g.clone_with_tables(|t| mapped_table(t, &xf));
    xf.turn_instances(&mut out);
    out
}

/// Convenience: a transform from translate, rotate (Euler XYZ, radians) and scale.
pub fn trs(translate: Vec3, rotate: Vec3, scale: Vec3) -> Mat4 {
    Mat4::from_scale_rotation_translation(
        scale,
        Quat::from_euler(glam::EulerRot::XYZ, rotate.x, rotate.y, rotate.z),
        translate,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attrib::{AttribClass, AttribData, AttribValue, Attribute};
    use crate::primitives::cube;
    use std::sync::Arc;

    #[test]
    fn each_tag_transforms_its_own_way() {
        let mut g = Geometry::new();
        g.add_point(Vec3::new(1.0, 0.0, 0.0));
        let set = |g: &mut Geometry, name: &str, v: AttribValue, info| {
            g.set_attrib(AttribClass::Point, name, Attribute::new(v, info, 1))
                .unwrap();
        };
        let n = Vec3::new(1.0, 1.0, 0.0).normalize();
        set(&mut g, "N", AttribValue::Vec3(n), TypeInfo::Normal);
        set(
            &mut g,
            "v",
            AttribValue::Vec3(Vec3::new(1.0, 1.0, 0.0)),
            TypeInfo::Vector,
        );
        set(&mut g, "Cd", AttribValue::Vec3(Vec3::ONE), TypeInfo::Color);
        set(
            &mut g,
            "orient",
            AttribValue::Quat(Quat::IDENTITY),
            TypeInfo::Quaternion,
        );
        // Non-uniform scale x2 in X, then translate.
        let m = Mat4::from_translation(Vec3::Z) * Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0));
        transform(&mut g, m);
        let get = |name: &str| g.attrib(AttribClass::Point, name).unwrap().data().get(0);
        assert_eq!(get("P"), AttribValue::Vec3(Vec3::new(2.0, 0.0, 1.0)));
        assert_eq!(get("v"), AttribValue::Vec3(Vec3::new(2.0, 1.0, 0.0)));
        assert_eq!(get("Cd"), AttribValue::Vec3(Vec3::ONE));
        // Inverse transpose of diag(2,1,1) is diag(0.5,1,1): (0.5,1,0) normalised.
        let AttribValue::Vec3(nn) = get("N") else {
            panic!()
        };
        assert!((nn - Vec3::new(0.5, 1.0, 0.0).normalize()).length() < 1e-6);
        // Normals stay perpendicular to a transformed tangent.
        let tangent = Vec3::new(1.0, -1.0, 0.0);
        assert!(nn.dot(m.transform_vector3(tangent)).abs() < 1e-6);

        let mut r = Geometry::new();
        r.add_point(Vec3::ZERO);
        r.set_attrib(
            AttribClass::Point,
            "orient",
            Attribute::from_data(AttribData::Quat(vec![Quat::IDENTITY]), TypeInfo::Quaternion),
        )
        .unwrap();
        let rot = Quat::from_rotation_y(0.7);
        transform(
            &mut r,
            Mat4::from_quat(rot) * Mat4::from_scale(Vec3::splat(3.0)),
        );
        let q = r
            .attrib(AttribClass::Point, "orient")
            .unwrap()
            .as_quat()
            .unwrap()[0];
        assert!(q.angle_between(rot) < 1e-5);
    }

    #[test]
    fn the_copying_transform_equals_the_in_place_one() {
        let mut g = crate::primitives::uv_sphere(1.0, 12, 8);
        let n: Vec<Vec3> = g.positions().to_vec();
        g.set_attrib(
            AttribClass::Point,
            "N",
            Attribute::from_data(AttribData::Vec3(n), TypeInfo::Normal),
        )
        .unwrap();
        g.set_attrib(
            AttribClass::Point,
            "orient",
            Attribute::new(
                AttribValue::Quat(Quat::IDENTITY),
                TypeInfo::Quaternion,
                g.num_points(),
            ),
        )
        .unwrap();
        let turn = Mat4::from_rotation_y(0.4) * Mat4::from_rotation_x(1.1);
        for m in [
            // A similarity (rotation, uniform scale): normals without a square root.
            Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0))
                * turn
                * Mat4::from_scale(Vec3::splat(3.0)),
            // A non-uniform scale: the general inverse transpose.
            turn * Mat4::from_scale(Vec3::new(2.0, 0.5, 1.0)),
        ] {
            let copied = transformed(&g, m);
            let mut moved = g.clone();
            transform(&mut moved, m);
            assert_eq!(copied.content_hash(), moved.content_hash());
            // Unit normals stay unit and perpendicular to moved tangents.
            let normals = copied
                .attrib(AttribClass::Point, "N")
                .unwrap()
                .as_vec3()
                .unwrap();
            let before = g
                .attrib(AttribClass::Point, "N")
                .unwrap()
                .as_vec3()
                .unwrap();
            for (a, b) in normals.iter().zip(before) {
                assert!((a.length() - b.length()).abs() < 1e-5);
                let tangent = b.any_orthonormal_vector();
                assert!(
                    a.dot(m.transform_vector3(tangent)).abs()
                        < 1e-4 * m.transform_vector3(tangent).length()
                );
            }
        }
    }

    #[test]
    fn packed_instances_follow() {
        let src = Arc::new(cube(1.0));
        let mut g = Geometry::new();
        let p = g.add_point(Vec3::X);
        g.add_packed(p, src, Mat4::IDENTITY).unwrap();
        let m = Mat4::from_rotation_z(std::f32::consts::FRAC_PI_2);
        transform(&mut g, m);
        let world = g.packed_world_transform(0).unwrap();
        let corner = Vec3::splat(0.5);
        let expect = m.transform_point3(Vec3::X + corner);
        assert!((world.transform_point3(corner) - expect).length() < 1e-6);
    }
}
