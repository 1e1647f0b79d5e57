//! Skeleton enveloping of any geometry's points: linear blend or dual
//! quaternion skinning, weights automatic (distance to the bones) or from
//! float point attributes `w_<joint>`, pose keyframable through one bend.

use geode_geo::glam::DVec3;
use geode_geo::AttribClass;
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, Operator, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};
use geode_spline::skin::{skin, SkinMethod};

use crate::hspline::parse_skeleton;
use crate::util::{geometry, input_owned};

struct Skin;
static SKIN: NodeSpec = NodeSpec::new(
    "skin",
    "Skin",
    "deform",
    "Moves the points with a posed skeleton (joints `name parent x y z` at rest, rotations about each joint): linear blend or dual quaternions. Weights come from float point attributes `w_<joint>` when the geometry has any, else from the distance to each bone (inverse fourth power, four bones at most). Normals are not recomputed.",
    &[geometry_input("geometry")],
    &[
        P::new("method", "Method", T::Menu(&["linear", "dual_quaternion"]), D::Str("dual_quaternion"), "Linear blend (may collapse at joints) or dual quaternions (keeps volume)."),
        P::new("skeleton", "Skeleton", T::String, D::Str(""), "Joints `name parent x y z` separated by `;` (parent `-` for the root; parents first), at rest."),
        P::new("pose", "Pose", T::String, D::Str(""), "Joint rotations `name rx ry rz` in degrees (X, then Y, then Z), separated by `;`."),
        P::new("bend_joint", "Bend joint", T::String, D::Str(""), "A joint whose rotation the animatable `bend` adds to."),
        P::new("bend", "Bend", T::Vec3, D::Vec3([0.0; 3]), "Degrees about X, Y, Z added to the bend joint (keyframable)."),
    ],
);

impl Operator for Skin {
    fn spec(&self) -> &'static NodeSpec {
        &SKIN
    }
    fn cook(
        &self,
        ctx: &CookContext,
        inputs: &[Option<Value>],
        p: &Params,
    ) -> Result<Value, CookError> {
        let mut g = input_owned(ctx, inputs, 0)?;
        let bend = p.vector::<3>("bend")?;
        let skeleton = parse_skeleton(
            p.string("skeleton")?,
            p.string("pose")?,
            Some((p.string("bend_joint")?, bend)),
        )
        .map_err(|(param, why)| ctx.param_error(param, why))?;
        let points: Vec<DVec3> = g.positions().iter().map(|q| q.as_dvec3()).collect();
        // Given weights: one float attribute per joint, normalized per point.
        let given: Vec<Option<&[f32]>> = skeleton
            .joints
            .iter()
            .map(|j| {
                g.attrib(AttribClass::Point, &format!("w_{}", j.name))
                    .and_then(|a| a.as_f32())
            })
            .collect();
        let weights = if given.iter().any(Option::is_some) {
            (0..points.len())
                .map(|i| {
                    let w: Vec<(usize, f64)> = given
                        .iter()
                        .enumerate()
                        .filter_map(|(j, a)| a.map(|a| (j, a[i].max(0.0) as f64)))
                        .filter(|x| x.1 > 0.0)
                        .collect();
                    let sum: f64 = w.iter().map(|x| x.1).sum();
                    w.into_iter().map(|(j, x)| (j, x / sum)).collect()
                })
                .collect()
        } else {
            skeleton.auto_weights(&points)
        };
        let method = if p.string("method")? == "linear" {
            SkinMethod::Linear
        } else {
            SkinMethod::DualQuaternion
        };
        let moved = skin(&points, &weights, &skeleton.motions(), method);
        // A point with no weight at all stays where it is.
        for ((q, m), w) in g.positions_mut().iter_mut().zip(moved).zip(&weights) {
            if !w.is_empty() {
                *q = m.as_vec3();
            }
        }
        geometry(g)
    }
}

pub fn register(r: &mut Registry) {
    r.add(Skin);
}
