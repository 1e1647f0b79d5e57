//! Affine transform of a geometry, each attribute treated by its type-info tag.

use glam::{Mat3, Mat4, Quat, Vec3, Vec4};
use rayon::prelude::*;

use crate::attrib::{AttribTable, TypeInfo};
use crate::geometry::Geometry;

/// The linear part of `m` as a 4x4 matrix with no translation.
fn linear_part(m: &Mat4) -> Mat4 {
    Mat4::from_mat3(Mat3::from_mat4(*m))
}

fn transform_table(t: &mut AttribTable, m: &Mat4, normal_m: &Mat3, rot: &Quat) {
    let linear = linear_part(m);
    for (_, a) in t.iter_mut() {
        let info = a.type_info;
        match info {
            TypeInfo::Position => {
                if let Some(v) = a.as_vec3_mut() {
                    v.par_iter_mut().for_each(|p| *p = m.transform_point3(*p));
                }
            }
            TypeInfo::Vector => {
                if let Some(v) = a.as_vec3_mut() {
                    v.par_iter_mut().for_each(|p| *p = m.transform_vector3(*p));
                }
            }
            TypeInfo::Normal => {
                if let Some(v) = a.as_vec3_mut() {
                    v.par_iter_mut().for_each(|n| {
                        let len = n.length();
                        if len > 0.0 {
                            *n = (*normal_m * *n).normalize_or_zero() * len;
                        }
                    });
                }
            }
            TypeInfo::Quaternion => {
                if let Some(v) = a.as_quat_mut() {
                    v.par_iter_mut().for_each(|q| *q = (*rot * *q).normalize());
                } else if let Some(v) = a.as_vec4_mut() {
                    v.par_iter_mut().for_each(|q| {
                        let r = (*rot * Quat::from_vec4(*q)).normalize();
                        *q = Vec4::from(r);
                    });
                }
            }
            TypeInfo::Transform => {
                if let Some(v) = a.as_mat4_mut() {
                    v.par_iter_mut().for_each(|x| *x = linear * *x);
                }
            }
            TypeInfo::None | TypeInfo::Color | TypeInfo::TexCoord => {}
        }
    }
}

/// Applies `m` to the geometry: positions fully, vectors by the linear part,
/// normals by the inverse transpose (keeping their length), quaternions by the
/// rotation part, local transforms and packed instances by the linear part
/// (their translation comes from their point).
pub fn transform(g: &mut Geometry, m: Mat4) {
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
    g.invalidate_content();
    transform_table(&mut g.points, &m, &normal_m, &rot);
    transform_table(&mut g.vertices, &m, &normal_m, &rot);
    transform_table(&mut g.prims, &m, &normal_m, &rot);
    transform_table(&mut g.detail, &m, &normal_m, &rot);
    let linear = linear_part(&m);
    for inst in g.packed.iter_mut() {
        inst.transform = linear * inst.transform;
    }
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
