//! Houdini's instance attributes turned into one transform per point
//! (shared by copy-to-points and the FRep instancer).

use glam::{Mat3, Mat4, Quat, Vec3};
use rayon::prelude::*;

use crate::attrib::AttribClass;
use crate::geometry::Geometry;

/// Houdini's instance attributes of a geometry's points, read once:
/// `P`, `trans` (added to P), `pivot`, `pscale` (uniform) and `scale`
/// (per axis), and the rotation from `orient` (quaternion) if present, else
/// from `N` (the instance's +Z) and `up` (default +Y); `rot` (quaternion)
/// turns the copy before that rotation. In column-vector form:
/// `M = T(P + trans) * R_orient * R_rot * S(pscale * scale) * T(-pivot)`.
/// A `transform` matrix (its linear part) replaces rotation and scale
/// alike, as in Houdini: `M = T(P + trans) * transform * T(-pivot)`.
pub struct InstanceAttribs<'a> {
    p: &'a [Vec3],
    orient: Option<&'a [Quat]>,
    rot: Option<&'a [Quat]>,
    normal: Option<&'a [Vec3]>,
    up: Option<&'a [Vec3]>,
    trans: Option<&'a [Vec3]>,
    pivot: Option<&'a [Vec3]>,
    scale: Option<&'a [Vec3]>,
    pscale: Option<&'a [f32]>,
    xform: Option<&'a [Mat4]>,
}

impl<'a> InstanceAttribs<'a> {
    pub fn new(g: &'a Geometry) -> InstanceAttribs<'a> {
        let a = |name: &str| g.attrib(AttribClass::Point, name);
        let vec3 = |name: &str| a(name).and_then(|x| x.as_vec3());
        let quat = |name: &str| a(name).and_then(|x| x.as_quat());
        InstanceAttribs {
            p: g.positions(),
            orient: quat("orient"),
            rot: quat("rot"),
            normal: vec3("N"),
            up: vec3("up"),
            trans: vec3("trans"),
            pivot: vec3("pivot"),
            scale: vec3("scale"),
            pscale: a("pscale").and_then(|x| x.as_f32()),
            xform: a("transform").and_then(|x| x.as_mat4()),
        }
    }

    /// Point `i`'s instance transform.
    pub fn at(&self, i: usize) -> Mat4 {
        let t = self.p[i] + self.trans.map_or(Vec3::ZERO, |t| t[i]);
        let pv = self.pivot.map_or(Vec3::ZERO, |v| v[i]);
        let linear = match self.xform {
            Some(m) => Mat3::from_mat4(m[i]),
            None => {
                let r_main = match (self.orient, self.normal) {
                    (Some(o), _) => o[i].normalize(),
                    (None, Some(nv)) => look_along(nv[i], self.up.map_or(Vec3::Y, |u| u[i])),
                    (None, None) => Quat::IDENTITY,
                };
                let r = r_main * self.rot.map_or(Quat::IDENTITY, |r| r[i].normalize());
                let s = self.scale.map_or(Vec3::ONE, |s| s[i]) * self.pscale.map_or(1.0, |s| s[i]);
                Mat3::from_quat(r) * Mat3::from_diagonal(s)
            }
        };
        // T(t) * linear * T(-pivot), composed directly.
        Mat4::from_cols(
            linear.x_axis.extend(0.0),
            linear.y_axis.extend(0.0),
            linear.z_axis.extend(0.0),
            (t - linear * pv).extend(1.0),
        )
    }
}

/// The instance transform of every point (see [`InstanceAttribs`]).
pub fn instance_transforms(g: &Geometry) -> Vec<Mat4> {
    let attribs = InstanceAttribs::new(g);
    (0..g.num_points())
        .into_par_iter()
        .with_min_len(PER_TASK)
        .map(|i| attribs.at(i))
        .collect()
}

/// Points per parallel task.
const PER_TASK: usize = 1 << 12;

/// The rotation taking +Z to `dir` with +Y turned towards `up`.
fn look_along(dir: Vec3, up: Vec3) -> Quat {
    let z = dir.normalize_or_zero();
    if z == Vec3::ZERO {
        return Quat::IDENTITY;
    }
    let x = up.cross(z);
    let x = if x.length_squared() < 1e-12 {
        z.any_orthonormal_vector()
    } else {
        x.normalize()
    };
    let y = z.cross(x);
    Quat::from_mat3(&Mat3::from_cols(x, y, z))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attrib::{AttribData, Attribute, TypeInfo};

    fn point_with(attrs: &[(&str, AttribData)]) -> Geometry {
        let mut g = Geometry::new();
        g.add_point(Vec3::new(1.0, 2.0, 3.0));
        for (name, data) in attrs {
            g.set_attrib(
                AttribClass::Point,
                name,
                Attribute::from_data(data.clone(), TypeInfo::None),
            )
            .unwrap();
        }
        g
    }

    #[test]
    fn precedence_by_hand() {
        let q90 = Quat::from_rotation_y(std::f32::consts::FRAC_PI_2);
        // orient wins over N; scale and pscale multiply; pivot comes first; trans adds.
        let g = point_with(&[
            ("orient", AttribData::Quat(vec![q90])),
            ("N", AttribData::Vec3(vec![Vec3::X])),
            ("pscale", AttribData::Float(vec![2.0])),
            ("scale", AttribData::Vec3(vec![Vec3::new(1.0, 3.0, 1.0)])),
            ("pivot", AttribData::Vec3(vec![Vec3::new(0.0, 0.0, 1.0)])),
            ("trans", AttribData::Vec3(vec![Vec3::new(10.0, 0.0, 0.0)])),
        ]);
        let m = instance_transforms(&g)[0];
        // (0,1,1): minus pivot -> (0,1,0); scale (2,6,2) -> (0,6,0); rotate about Y leaves it; + P + trans.
        assert!(
            (m.transform_point3(Vec3::new(0.0, 1.0, 1.0)) - Vec3::new(11.0, 8.0, 3.0)).length()
                < 1e-5
        );
        // (1,0,1): minus pivot -> (1,0,0); scale -> (2,0,0); +90 about Y -> (0,0,-2).
        assert!(
            (m.transform_point3(Vec3::new(1.0, 0.0, 1.0)) - Vec3::new(11.0, 2.0, 1.0)).length()
                < 1e-5
        );
        // Without orient, N aims +Z: +Z maps onto +X.
        let g = point_with(&[("N", AttribData::Vec3(vec![Vec3::X]))]);
        let m = instance_transforms(&g)[0];
        assert!((m.transform_vector3(Vec3::Z) - Vec3::X).length() < 1e-6);
        assert!(
            (m.transform_vector3(Vec3::Y) - Vec3::Y).length() < 1e-6,
            "up stays up"
        );
        // With up, +Y turns toward it (made perpendicular to N).
        let g = point_with(&[
            ("N", AttribData::Vec3(vec![Vec3::X])),
            ("up", AttribData::Vec3(vec![Vec3::new(0.5, 0.0, 1.0)])),
        ]);
        let m = instance_transforms(&g)[0];
        assert!((m.transform_vector3(Vec3::Z) - Vec3::X).length() < 1e-6);
        assert!((m.transform_vector3(Vec3::Y) - Vec3::Z).length() < 1e-6);
        assert!(
            (m.transform_vector3(Vec3::X) - Vec3::Y).length() < 1e-6,
            "right-handed"
        );
        // rot turns the copy before orient.
        let g = point_with(&[
            ("orient", AttribData::Quat(vec![q90])),
            (
                "rot",
                AttribData::Quat(vec![Quat::from_rotation_x(std::f32::consts::FRAC_PI_2)]),
            ),
        ]);
        let m = instance_transforms(&g)[0];
        assert!(
            (m.transform_vector3(Vec3::Y) - Vec3::X).length() < 1e-5,
            "Y -> Z by rot, Z -> X by orient"
        );
        // transform replaces orient, rot, pscale and scale; trans and pivot stay.
        let shear = Mat4::from_cols_array(&[
            1.0, 0.0, 0.0, 0.0, 0.5, 2.0, 0.0, 0.0, 0.0, 0.0, 3.0, 0.0, 9.0, 9.0, 9.0, 1.0,
        ]);
        let g = point_with(&[
            ("orient", AttribData::Quat(vec![q90])),
            ("pscale", AttribData::Float(vec![7.0])),
            ("transform", AttribData::Mat4(vec![shear])),
            ("trans", AttribData::Vec3(vec![Vec3::X])),
            ("pivot", AttribData::Vec3(vec![Vec3::Z])),
        ]);
        let m = instance_transforms(&g)[0];
        // Local (1, 1, 1): minus pivot (1, 1, 0), by the 3x3 (1.5, 2, 0),
        // plus P + trans (2, 2, 3); the matrix's own translation is ignored.
        let got = m.transform_point3(Vec3::ONE);
        assert!((got - Vec3::new(3.5, 4.0, 3.0)).length() < 1e-5, "{got}");
    }
}
