//! Houdini's instance attributes turned into one transform per point
//! (shared by copy-to-points, the FRep instancer and the sweep's `orient`).

use glam::{Mat3, Mat4, Quat, Vec3};
use rayon::prelude::*;

use crate::attrib::{AttribClass, AttribData, AttribType};
use crate::error::GeoError;
use crate::geometry::Geometry;

/// Houdini's instance attributes of a geometry's points, read once, by
/// SideFX's "Copying and instancing point attributes" page: `orient` and
/// `rot` from any float4 column (a wrangle's `p@orient` is a plain
/// vector4), `N`, `up`, `v`, `scale`, `trans` and `pivot` from any float3
/// column whatever its tag, `pscale` from a float or an int, `transform` a
/// 3x3 or 4x4 matrix.
///
/// The page's combination, in its row-vector form (`X` translates by
/// `-pivot`, `S` scales by `scale * pscale`, `O` is `orient`, `L` the
/// alignment from `N` or `v` and `up`, `R` is `rot`, `T` translates by
/// `P + trans`, `M` is `transform`):
///
/// ```text
/// transform exists:  X * M * T
/// orient exists:     X * S * (O * R) * T
/// otherwise:         X * S * L * R * T
/// ```
///
/// so a copy is moved off its pivot, scaled, oriented, turned by `rot`
/// after the orientation, then placed. In geode's column-vector form:
/// `T(P + trans) * R_rot * (R_orient or L) * S(scale * pscale) * T(-pivot)`.
/// `L`: `N` as +Z with +Y turned toward `up` when `up` is present and not
/// zero (`mlookatup`), else the shortest turn of +Z onto `N`
/// (`dihedral`); without `N` the same from `v`; without either, none. Only
/// the linear part of `transform` is used: P, pivot and trans place it.
///
/// An attribute of one of these names whose type cannot mean what the name
/// does (a string `orient`, a float3 `orient`, a float4 `N`) is an error,
/// not skipped: Houdini binds such a name to nothing and silently copies
/// without it, which hides a mistake the user can fix in one rename (a
/// copy whose orientation silently vanished looks like a bug elsewhere).
pub struct InstanceAttribs<'a> {
    p: &'a [Vec3],
    orient: Option<&'a [[f32; 4]]>,
    rot: Option<&'a [[f32; 4]]>,
    normal: Option<&'a [Vec3]>,
    velocity: Option<&'a [Vec3]>,
    up: Option<&'a [Vec3]>,
    trans: Option<&'a [Vec3]>,
    pivot: Option<&'a [Vec3]>,
    scale: Option<&'a [Vec3]>,
    pscale: Option<Scalars<'a>>,
    xform: Option<Matrices<'a>>,
}

/// A float or int point column read as floats.
#[derive(Clone, Copy, Debug)]
pub enum Scalars<'a> {
    Float(&'a [f32]),
    Int(&'a [i32]),
}

impl Scalars<'_> {
    pub fn get(&self, i: usize) -> f32 {
        match self {
            Scalars::Float(v) => v[i],
            Scalars::Int(v) => v[i] as f32,
        }
    }
}

#[derive(Clone, Copy, Debug)]
enum Matrices<'a> {
    M3(&'a [Mat3]),
    M4(&'a [Mat4]),
}

fn wrong(name: &str, expected: &'static str, found: AttribType) -> GeoError {
    GeoError::AttribReadAs {
        name: name.into(),
        expected,
        found,
    }
}

/// Point attribute `name` as float4 values (`x, y, z, w`: a quaternion's
/// real part last, as VEX writes it), from a vector4 or quaternion column;
/// `None` when absent, an error for any other type.
pub fn point_float4<'a>(g: &'a Geometry, name: &str) -> Result<Option<&'a [[f32; 4]]>, GeoError> {
    let Some(a) = g.attrib(AttribClass::Point, name) else {
        return Ok(None);
    };
    match a.data() {
        AttribData::Vec4(v) => Ok(Some(bytemuck::cast_slice(v))),
        AttribData::Quat(v) => Ok(Some(bytemuck::cast_slice(v))),
        other => Err(wrong(
            name,
            "float4 (vector4 or quaternion)",
            other.attrib_type(),
        )),
    }
}

/// Point attribute `name` as float3 values, whatever its tag; `None` when
/// absent, an error for any other type.
pub fn point_float3<'a>(g: &'a Geometry, name: &str) -> Result<Option<&'a [Vec3]>, GeoError> {
    let Some(a) = g.attrib(AttribClass::Point, name) else {
        return Ok(None);
    };
    match a.data() {
        AttribData::Vec3(v) => Ok(Some(v)),
        other => Err(wrong(name, "float3 (vector3)", other.attrib_type())),
    }
}

/// Point attribute `name` as one number per point, from a float or an int
/// column; `None` when absent, an error for any other type.
pub fn point_scalar<'a>(g: &'a Geometry, name: &str) -> Result<Option<Scalars<'a>>, GeoError> {
    let Some(a) = g.attrib(AttribClass::Point, name) else {
        return Ok(None);
    };
    match a.data() {
        AttribData::Float(v) => Ok(Some(Scalars::Float(v))),
        AttribData::Int(v) => Ok(Some(Scalars::Int(v))),
        other => Err(wrong(name, "a float or an int", other.attrib_type())),
    }
}

/// A unit quaternion from float4 `x, y, z, w`; a zero one is no rotation.
pub fn unit_quat(q: [f32; 4]) -> Quat {
    let q = Quat::from_array(q);
    let len = q.length();
    if len > 0.0 && len.is_finite() {
        q / len
    } else {
        Quat::IDENTITY
    }
}

impl<'a> InstanceAttribs<'a> {
    /// Reads the attributes; an attribute of a wrong type is an error
    /// naming it and the type it must have.
    pub fn new(g: &'a Geometry) -> Result<InstanceAttribs<'a>, GeoError> {
        let xform = match g.attrib(AttribClass::Point, "transform").map(|a| a.data()) {
            None => None,
            Some(AttribData::Mat3(m)) => Some(Matrices::M3(m)),
            Some(AttribData::Mat4(m)) => Some(Matrices::M4(m)),
            Some(other) => {
                return Err(wrong(
                    "transform",
                    "a 3x3 or 4x4 matrix",
                    other.attrib_type(),
                ))
            }
        };
        Ok(InstanceAttribs {
            p: g.positions(),
            orient: point_float4(g, "orient")?,
            rot: point_float4(g, "rot")?,
            normal: point_float3(g, "N")?,
            velocity: point_float3(g, "v")?,
            up: point_float3(g, "up")?,
            trans: point_float3(g, "trans")?,
            pivot: point_float3(g, "pivot")?,
            scale: point_float3(g, "scale")?,
            pscale: point_scalar(g, "pscale")?,
            xform,
        })
    }

    /// The alignment `L` of point `i` (see [`InstanceAttribs`]).
    fn alignment(&self, i: usize) -> Quat {
        let Some(dir) = self.normal.or(self.velocity).map(|d| d[i]) else {
            return Quat::IDENTITY;
        };
        match self.up.map(|u| u[i]).filter(|u| *u != Vec3::ZERO) {
            Some(up) => look_along(dir, up),
            None => dihedral_z(dir),
        }
    }

    /// Point `i`'s instance transform.
    pub fn at(&self, i: usize) -> Mat4 {
        let t = self.p[i] + self.trans.map_or(Vec3::ZERO, |t| t[i]);
        let pv = self.pivot.map_or(Vec3::ZERO, |v| v[i]);
        let linear = match self.xform {
            Some(Matrices::M3(m)) => m[i],
            Some(Matrices::M4(m)) => Mat3::from_mat4(m[i]),
            None => {
                let aim = match self.orient {
                    Some(o) => unit_quat(o[i]),
                    None => self.alignment(i),
                };
                let r = self.rot.map_or(Quat::IDENTITY, |r| unit_quat(r[i])) * aim;
                let s =
                    self.scale.map_or(Vec3::ONE, |s| s[i]) * self.pscale.map_or(1.0, |s| s.get(i));
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
pub fn instance_transforms(g: &Geometry) -> Result<Vec<Mat4>, GeoError> {
    let attribs = InstanceAttribs::new(g)?;
    Ok((0..g.num_points())
        .into_par_iter()
        .with_min_len(PER_TASK)
        .map(|i| attribs.at(i))
        .collect())
}

/// Points per parallel task.
const PER_TASK: usize = 1 << 12;

/// `dihedral({0,0,1}, dir)`: the shortest rotation of +Z onto `dir` (none
/// for a zero `dir`; a half turn about +X for `-Z`).
fn dihedral_z(dir: Vec3) -> Quat {
    let d = dir.normalize_or_zero();
    if d == Vec3::ZERO {
        return Quat::IDENTITY;
    }
    if d.z < -1.0 + 1e-7 {
        return Quat::from_rotation_x(std::f32::consts::PI);
    }
    Quat::from_rotation_arc(Vec3::Z, d)
}

/// `mlookatup(dir, 0, up)`: +Z onto `dir`, +Y turned toward `up`; an `up`
/// along `dir` leaves the dihedral turn.
fn look_along(dir: Vec3, up: Vec3) -> Quat {
    let z = dir.normalize_or_zero();
    if z == Vec3::ZERO {
        return Quat::IDENTITY;
    }
    let x = up.cross(z);
    if x.length_squared() < 1e-12 * up.length_squared().max(f32::MIN_POSITIVE) {
        return dihedral_z(dir);
    }
    let x = x.normalize();
    let y = z.cross(x);
    Quat::from_mat3(&Mat3::from_cols(x, y, z))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attrib::{Attribute, TypeInfo};
    use glam::Vec4;

    const P0: Vec3 = Vec3::new(1.0, 2.0, 3.0);

    fn point_with(attrs: &[(&str, AttribData)]) -> Geometry {
        let mut g = Geometry::new();
        g.add_point(P0);
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

    // ---- SideFX's formula written out in its own row-vector form ----
    // A row vector v is placed by v * M; matrices are 4x4, row-major.

    type Row = [[f64; 4]; 4];

    fn identity() -> Row {
        let mut m = [[0.0; 4]; 4];
        for (k, row) in m.iter_mut().enumerate() {
            row[k] = 1.0;
        }
        m
    }

    fn mul(a: &Row, b: &Row) -> Row {
        let mut m = [[0.0; 4]; 4];
        for r in 0..4 {
            for c in 0..4 {
                m[r][c] = (0..4).map(|k| a[r][k] * b[k][c]).sum();
            }
        }
        m
    }

    fn translate(t: [f64; 3]) -> Row {
        let mut m = identity();
        m[3][..3].copy_from_slice(&t);
        m
    }

    fn scale(s: [f64; 3]) -> Row {
        let mut m = identity();
        for k in 0..3 {
            m[k][k] = s[k];
        }
        m
    }

    /// The rotation of unit quaternion (x, y, z, w) for row vectors: the
    /// textbook column-vector matrix, transposed.
    fn rotation(q: [f64; 4]) -> Row {
        let n = q.iter().map(|c| c * c).sum::<f64>().sqrt();
        let [x, y, z, w] = q.map(|c| c / n);
        let col = [
            [
                1.0 - 2.0 * (y * y + z * z),
                2.0 * (x * y - z * w),
                2.0 * (x * z + y * w),
            ],
            [
                2.0 * (x * y + z * w),
                1.0 - 2.0 * (x * x + z * z),
                2.0 * (y * z - x * w),
            ],
            [
                2.0 * (x * z - y * w),
                2.0 * (y * z + x * w),
                1.0 - 2.0 * (x * x + y * y),
            ],
        ];
        let mut m = identity();
        for r in 0..3 {
            for c in 0..3 {
                m[r][c] = col[c][r];
            }
        }
        m
    }

    /// Rows are the images of X, Y, Z.
    fn frame(x: [f64; 3], y: [f64; 3], z: [f64; 3]) -> Row {
        let mut m = identity();
        m[0][..3].copy_from_slice(&x);
        m[1][..3].copy_from_slice(&y);
        m[2][..3].copy_from_slice(&z);
        m
    }

    fn apply(m: &Row, v: [f64; 3]) -> [f64; 3] {
        let row = [v[0], v[1], v[2], 1.0];
        std::array::from_fn(|c| (0..4).map(|k| row[k] * m[k][c]).sum())
    }

    fn quat_axis_angle(axis: [f64; 3], angle: f64) -> [f64; 4] {
        let n = axis.iter().map(|c| c * c).sum::<f64>().sqrt();
        let s = (angle / 2.0).sin() / n;
        [axis[0] * s, axis[1] * s, axis[2] * s, (angle / 2.0).cos()]
    }

    fn f32x4(q: [f64; 4]) -> Vec4 {
        Vec4::from_array(q.map(|c| c as f32))
    }

    fn agree(g: &Geometry, expected: &Row) {
        let m = instance_transforms(g).unwrap()[0];
        for v in [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.3, -0.7, 1.9],
        ] {
            let want = apply(expected, v);
            let got = m.transform_point3(Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32));
            for k in 0..3 {
                assert!(
                    (got[k] as f64 - want[k]).abs() < 1e-5,
                    "{v:?} -> {got}, documented {want:?}"
                );
            }
        }
    }

    fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    fn unit(a: [f64; 3]) -> [f64; 3] {
        let n = a.iter().map(|c| c * c).sum::<f64>().sqrt();
        a.map(|c| c / n)
    }

    const PIVOT: [f64; 3] = [0.1, 0.2, 0.3];
    const SCALE: [f64; 3] = [1.0, 2.0, 3.0];
    const PSCALE: f64 = 1.5;
    const TRANS: [f64; 3] = [1.0, -1.0, 2.0];

    fn x_s_t() -> (Row, Row, Row) {
        (
            translate(PIVOT.map(|c| -c)),
            scale(SCALE.map(|c| c * PSCALE)),
            translate([
                P0.x as f64 + TRANS[0],
                P0.y as f64 + TRANS[1],
                P0.z as f64 + TRANS[2],
            ]),
        )
    }

    fn placement() -> Vec<(&'static str, AttribData)> {
        vec![
            ("pivot", AttribData::Vec3(vec![Vec3::new(0.1, 0.2, 0.3)])),
            ("scale", AttribData::Vec3(vec![Vec3::new(1.0, 2.0, 3.0)])),
            ("pscale", AttribData::Float(vec![1.5])),
            ("trans", AttribData::Vec3(vec![Vec3::new(1.0, -1.0, 2.0)])),
        ]
    }

    #[test]
    fn orient_and_rot_follow_the_documented_product() {
        // Transform = X * S * (O * R) * T, with orient a plain vector4 (as
        // a wrangle writes it) and rot a quaternion column; N must lose.
        let o = quat_axis_angle([1.0, 2.0, 3.0], 0.7);
        let r = quat_axis_angle([0.0, 1.0, -1.0], 1.1);
        let mut attrs = placement();
        attrs.push(("orient", AttribData::Vec4(vec![f32x4(o)])));
        attrs.push(("rot", AttribData::Quat(vec![Quat::from_vec4(f32x4(r))])));
        attrs.push(("N", AttribData::Vec3(vec![Vec3::X])));
        let (x, s, t) = x_s_t();
        let expected = mul(&mul(&mul(&x, &s), &mul(&rotation(o), &rotation(r))), &t);
        agree(&point_with(&attrs), &expected);
    }

    #[test]
    fn n_and_up_follow_the_documented_product() {
        // Transform = X * S * L * R * T, L = mlookatup(N, 0, up): N is +Z,
        // up (made perpendicular) +Y.
        let (n, up) = ([1.0, 1.0, 0.5], [0.0, 0.2, 1.0]);
        let r = quat_axis_angle([1.0, 0.0, 1.0], 0.4);
        let mut attrs = placement();
        attrs.push(("N", AttribData::Vec3(vec![Vec3::new(1.0, 1.0, 0.5)])));
        attrs.push(("up", AttribData::Vec3(vec![Vec3::new(0.0, 0.2, 1.0)])));
        attrs.push(("rot", AttribData::Vec4(vec![f32x4(r)])));
        let z = unit(n);
        let xa = unit(cross(up, z));
        let l = frame(xa, cross(z, xa), z);
        let (x, s, t) = x_s_t();
        let expected = mul(&mul(&mul(&mul(&x, &s), &l), &rotation(r)), &t);
        agree(&point_with(&attrs), &expected);
    }

    #[test]
    fn n_without_up_is_the_dihedral_turn() {
        // L = dihedral({0,0,1}, N): a turn about Z x N by the angle between
        // them, so the axis Z x N stays put (a look-at with +Y up would not
        // keep it).
        let n = [1.0, 1.0, 1.0];
        let axis = cross([0.0, 0.0, 1.0], unit(n));
        let angle = (unit(n)[2]).acos();
        let l = rotation(quat_axis_angle(axis, angle));
        let expected = mul(&l, &translate([1.0, 2.0, 3.0]));
        let g = point_with(&[("N", AttribData::Vec3(vec![Vec3::ONE]))]);
        agree(&g, &expected);
        // A zero up is no up.
        let g = point_with(&[
            ("N", AttribData::Vec3(vec![Vec3::ONE])),
            ("up", AttribData::Vec3(vec![Vec3::ZERO])),
        ]);
        agree(&g, &expected);
        // Without N, v aims +Z the same way; with up it is a look-at.
        let g = point_with(&[("v", AttribData::Vec3(vec![Vec3::ONE * 4.0]))]);
        agree(&g, &expected);
        let g = point_with(&[
            ("v", AttribData::Vec3(vec![Vec3::X])),
            ("up", AttribData::Vec3(vec![Vec3::Z])),
        ]);
        let m = instance_transforms(&g).unwrap()[0];
        assert!((m.transform_vector3(Vec3::Z) - Vec3::X).length() < 1e-6);
        assert!((m.transform_vector3(Vec3::Y) - Vec3::Z).length() < 1e-6);
        // N wins over v.
        let g = point_with(&[
            ("N", AttribData::Vec3(vec![Vec3::Y])),
            ("v", AttribData::Vec3(vec![Vec3::X])),
        ]);
        let m = instance_transforms(&g).unwrap()[0];
        assert!((m.transform_vector3(Vec3::Z) - Vec3::Y).length() < 1e-6);
    }

    #[test]
    fn transform_replaces_rotation_and_scale() {
        // Transform = X * M * T: only the matrix's linear part; P, trans
        // and pivot still place it. A 3x3 matrix works as a 4x4 does.
        let linear = Mat3::from_cols_array(&[1.0, 0.0, 0.0, 0.5, 2.0, 0.0, 0.0, 0.0, 3.0]);
        for m in [
            AttribData::Mat3(vec![linear]),
            AttribData::Mat4(vec![
                Mat4::from_mat3(linear) * Mat4::from_translation(Vec3::splat(9.0)),
            ]),
        ] {
            let g = point_with(&[
                ("orient", AttribData::Quat(vec![Quat::from_rotation_y(1.0)])),
                ("pscale", AttribData::Float(vec![7.0])),
                ("transform", m),
                ("trans", AttribData::Vec3(vec![Vec3::X])),
                ("pivot", AttribData::Vec3(vec![Vec3::Z])),
            ]);
            let m = instance_transforms(&g).unwrap()[0];
            // Local (1, 1, 1): minus pivot (1, 1, 0), by the 3x3 (1.5, 2, 0),
            // plus P + trans (2, 2, 3).
            let got = m.transform_point3(Vec3::ONE);
            assert!((got - Vec3::new(3.5, 4.0, 3.0)).length() < 1e-5, "{got}");
        }
    }

    #[test]
    fn pscale_may_be_an_int_and_tags_do_not_matter() {
        let mut g = point_with(&[("pscale", AttribData::Int(vec![2]))]);
        let m = instance_transforms(&g).unwrap()[0];
        assert!((m.transform_vector3(Vec3::X) - Vec3::X * 2.0).length() < 1e-6);
        // A float3 scale tagged as a colour is still a scale.
        g.set_attrib(
            AttribClass::Point,
            "scale",
            Attribute::from_data(
                AttribData::Vec3(vec![Vec3::new(1.0, 3.0, 1.0)]),
                TypeInfo::Color,
            ),
        )
        .unwrap();
        let m = instance_transforms(&g).unwrap()[0];
        assert!((m.transform_vector3(Vec3::Y) - Vec3::Y * 6.0).length() < 1e-5);
    }

    #[test]
    fn a_wrong_type_is_an_error_naming_attribute_and_type() {
        let string = {
            let mut g = point_with(&[]);
            g.set_attrib(
                AttribClass::Point,
                "orient",
                Attribute::new(
                    crate::attrib::AttribValue::String("up".into()),
                    TypeInfo::None,
                    1,
                ),
            )
            .unwrap();
            g
        };
        let cases = [
            (string, "orient", "float4"),
            (
                point_with(&[("orient", AttribData::Vec3(vec![Vec3::X]))]),
                "orient",
                "float4",
            ),
            (
                point_with(&[("N", AttribData::Vec4(vec![Vec4::X]))]),
                "N",
                "float3",
            ),
            (
                point_with(&[("pscale", AttribData::Vec3(vec![Vec3::X]))]),
                "pscale",
                "a float or an int",
            ),
            (
                point_with(&[("transform", AttribData::Float(vec![1.0]))]),
                "transform",
                "matrix",
            ),
        ];
        for (g, name, expected) in cases {
            let e = instance_transforms(&g).unwrap_err();
            let text = e.to_string();
            assert!(matches!(&e, GeoError::AttribReadAs { name: n, .. } if n == name));
            assert!(
                text.contains(&format!("`{name}`")) && text.contains(expected),
                "{text}"
            );
        }
    }
}
