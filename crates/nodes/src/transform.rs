//! The transform node: translate, rotate (degrees, XYZ order), scale and uniform scale about a pivot.

use geode_geo::glam::{DMat4, DQuat, DVec3, EulerRot, Mat4};
use geode_geo::ops;
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{geometry, input};

pub(crate) const TRANSFORM_TRANSLATE: P = P::new(
    "translate",
    "Translate",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "Offset applied last.",
);
pub(crate) const TRANSFORM_ROTATE: P = P::new(
    "rotate",
    "Rotate",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "Rotation in degrees about X, Y and Z (applied in that order).",
);
pub(crate) const TRANSFORM_SCALE: P = P::new(
    "scale",
    "Scale",
    T::Vec3,
    D::Vec3([1.0; 3]),
    "Per-axis scale.",
);
pub(crate) const TRANSFORM_UNIFORM_SCALE: P = P::new(
    "uniform_scale",
    "Uniform scale",
    T::Float,
    D::Float(1.0),
    "Multiplies the per-axis scale.",
);
pub(crate) const TRANSFORM_PIVOT: P = P::new(
    "pivot",
    "Pivot",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "The point that scale and rotation keep fixed.",
);

static TRANSFORM: NodeSpec = NodeSpec::new(
    "transform",
    "Transform",
    "transform",
    "Moves, rotates and scales geometry: scale, then rotate (X, then Y, then Z) about the pivot, then translate. \
     Normals use the inverse transpose, vectors and quaternions follow by their type-info, packed instances keep sharing.",
    &[geometry_input("geometry")],
    &[
        TRANSFORM_TRANSLATE,
        TRANSFORM_ROTATE,
        TRANSFORM_SCALE,
        TRANSFORM_UNIFORM_SCALE,
        TRANSFORM_PIVOT,
    ],
);

/// Scale, then rotate (degrees about X, then Y, then Z), both about `pivot`,
/// then translate: the matrix every transform node builds (meshes and fields).
pub fn trs_about_pivot(
    translate: [f64; 3],
    rotate_degrees: [f64; 3],
    scale: [f64; 3],
    pivot: [f64; 3],
) -> DMat4 {
    let r = rotate_degrees.map(f64::to_radians);
    let rot = DQuat::from_euler(EulerRot::ZYX, r[2], r[1], r[0]);
    let pivot = DVec3::from_array(pivot);
    DMat4::from_translation(DVec3::from_array(translate) + pivot)
        * DMat4::from_quat(rot)
        * DMat4::from_scale(DVec3::from_array(scale))
        * DMat4::from_translation(-pivot)
}

/// The matrix of the transform node's parameters.
pub fn matrix(p: &Params) -> Result<Mat4, CookError> {
    let k = p.float(&TRANSFORM_UNIFORM_SCALE)?;
    let scale = p.vector::<3>(&TRANSFORM_SCALE)?.map(|s| s * k);
    Ok(trs_about_pivot(
        p.vector::<3>(&TRANSFORM_TRANSLATE)?,
        p.vector::<3>(&TRANSFORM_ROTATE)?,
        scale,
        p.vector::<3>(&TRANSFORM_PIVOT)?,
    )
    .as_mat4())
}

fn cook_transform(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    geometry(ops::transformed(g, matrix(p)?))
}

pub fn register(r: &mut Registry) {
    r.node(&TRANSFORM, cook_transform);
}
