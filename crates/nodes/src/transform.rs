//! The transform node: translate, rotate (degrees, XYZ order), scale and uniform scale about a pivot.

use geode_geo::glam::{EulerRot, Mat4, Quat};
use geode_geo::ops;
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, Operator, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{geometry, input_owned, vec3};

struct Transform;
static TRANSFORM: NodeSpec = NodeSpec::new(
    "transform",
    "Transform",
    "transform",
    "Moves, rotates and scales geometry: scale, then rotate (X, then Y, then Z) about the pivot, then translate. \
     Normals use the inverse transpose, vectors and quaternions follow by their type-info, packed instances keep sharing.",
    &[geometry_input("geometry")],
    &[
        P::new("translate", "Translate", T::Vec3, D::Vec3([0.0; 3]), "Offset applied last."),
        P::new("rotate", "Rotate", T::Vec3, D::Vec3([0.0; 3]), "Rotation in degrees about X, Y and Z (applied in that order)."),
        P::new("scale", "Scale", T::Vec3, D::Vec3([1.0; 3]), "Per-axis scale."),
        P::new("uniform_scale", "Uniform scale", T::Float, D::Float(1.0), "Multiplies the per-axis scale."),
        P::new("pivot", "Pivot", T::Vec3, D::Vec3([0.0; 3]), "The point that scale and rotation keep fixed."),
    ],
);

/// The matrix of the transform node's parameters.
pub fn matrix(p: &Params) -> Result<Mat4, CookError> {
    let r = vec3(p, "rotate")?;
    let rot = Quat::from_euler(
        EulerRot::ZYX,
        r.z.to_radians(),
        r.y.to_radians(),
        r.x.to_radians(),
    );
    let scale = vec3(p, "scale")? * p.float("uniform_scale")? as f32;
    let pivot = vec3(p, "pivot")?;
    Ok(Mat4::from_translation(vec3(p, "translate")? + pivot)
        * Mat4::from_quat(rot)
        * Mat4::from_scale(scale)
        * Mat4::from_translation(-pivot))
}

impl Operator for Transform {
    fn spec(&self) -> &'static NodeSpec {
        &TRANSFORM
    }
    fn cook(
        &self,
        ctx: &CookContext,
        inputs: &[Option<Value>],
        p: &Params,
    ) -> Result<Value, CookError> {
        let mut g = input_owned(ctx, inputs, 0)?;
        ops::transform(&mut g, matrix(p)?);
        geometry(g)
    }
}

pub fn register(r: &mut Registry) {
    r.add(Transform);
}
