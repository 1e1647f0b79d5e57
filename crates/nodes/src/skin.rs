//! Skeleton enveloping of any geometry's points: linear blend or dual
//! quaternion skinning, weights automatic (distance to the bones) or from
//! float point attributes `w_<joint>`, pose keyframable through one bend.

use geode_geo::glam::{DQuat, DVec3};
use geode_geo::AttribClass;
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};
use geode_spline::skin::{skin, Joint, Skeleton, SkinMethod};

use crate::util::{geometry, input_owned};

/// The skeleton parameters, declared once for every node that envelopes.
pub(crate) const SKELETON: P = P::new("skeleton", "Skeleton", T::String, D::Str(""), "Joints `name parent x y z` separated by `;` (parent `-` for the root; parents first), at rest.");
pub(crate) const POSE: P = P::new(
    "pose",
    "Pose",
    T::String,
    D::Str(""),
    "Joint rotations `name rx ry rz` in degrees (X, then Y, then Z), separated by `;`.",
);
pub(crate) const BEND_JOINT: P = P::new(
    "bend_joint",
    "Bend joint",
    T::String,
    D::Str(""),
    "A joint whose rotation the animatable `bend` adds to.",
);
pub(crate) const BEND: P = P::new(
    "bend",
    "Bend",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "Degrees about X, Y, Z added to the bend joint (keyframable).",
);

/// The posed skeleton those parameters describe; errors name the parameter.
pub(crate) fn skeleton_from_params(ctx: &CookContext, p: &Params) -> Result<Skeleton, CookError> {
    let bend = p.vector::<3>("bend")?;
    parse_skeleton(
        p.string("skeleton")?,
        p.string("pose")?,
        Some((p.string("bend_joint")?, bend)),
    )
    .map_err(|(param, why)| ctx.param_error(param, why))
}

/// Joints at rest (from an .hs file) posed by the `pose` and `bend` parameters.
pub(crate) fn posed_skeleton(
    ctx: &CookContext,
    p: &Params,
    joints: &[Joint],
) -> Result<Skeleton, CookError> {
    let text: Vec<String> = joints
        .iter()
        .map(|j| {
            let parent = j.parent.map_or("-", |k| joints[k].name.as_str());
            format!("{} {parent} {} {} {}", j.name, j.rest.x, j.rest.y, j.rest.z)
        })
        .collect();
    let bend = p.vector::<3>("bend")?;
    parse_skeleton(
        &text.join("; "),
        p.string("pose")?,
        Some((p.string("bend_joint")?, bend)),
    )
    .map_err(|(param, why)| ctx.param_error(param, why))
}

/// The skeleton and pose parameters as joints (rest positions, rotations).
fn parse_skeleton(
    skeleton: &str,
    pose: &str,
    bend: Option<(&str, [f64; 3])>,
) -> Result<Skeleton, (&'static str, String)> {
    let mut joints: Vec<Joint> = Vec::new();
    for (k, entry) in skeleton
        .split(';')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .enumerate()
    {
        let w: Vec<&str> = entry.split_whitespace().collect();
        let bad = |why: &str| ("skeleton", format!("joint {} `{entry}`: {why}", k + 1));
        if w.len() != 5 {
            return Err(bad("expected `name parent x y z`"));
        }
        let parent = match w[1] {
            "-" => None,
            name => Some(
                joints
                    .iter()
                    .position(|j| j.name == name)
                    .ok_or_else(|| bad("the parent must be an earlier joint"))?,
            ),
        };
        let num = |s: &str| s.parse::<f64>().ok().filter(|x| x.is_finite());
        let (Some(x), Some(y), Some(z)) = (num(w[2]), num(w[3]), num(w[4])) else {
            return Err(bad("x y z must be numbers"));
        };
        joints.push(Joint {
            name: w[0].to_owned(),
            parent,
            rest: DVec3::new(x, y, z),
            rotation: DQuat::IDENTITY,
        });
    }
    let euler = |d: [f64; 3]| {
        DQuat::from_euler(
            geode_geo::glam::EulerRot::ZYX,
            d[2].to_radians(),
            d[1].to_radians(),
            d[0].to_radians(),
        )
    };
    for (k, entry) in pose
        .split(';')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .enumerate()
    {
        let w: Vec<&str> = entry.split_whitespace().collect();
        let bad = |why: &str| ("pose", format!("entry {} `{entry}`: {why}", k + 1));
        let nums: Vec<f64> = w.iter().skip(1).filter_map(|s| s.parse().ok()).collect();
        if w.len() != 4 || nums.len() != 3 {
            return Err(bad("expected `name rx ry rz`"));
        }
        let j = joints
            .iter_mut()
            .find(|j| j.name == w[0])
            .ok_or_else(|| bad("no such joint"))?;
        j.rotation = euler([nums[0], nums[1], nums[2]]) * j.rotation;
    }
    if let Some((name, d)) = bend.filter(|(n, _)| !n.is_empty()) {
        let j = joints
            .iter_mut()
            .find(|j| j.name == name)
            .ok_or(("bend_joint", format!("no joint named `{name}`")))?;
        j.rotation = euler(d) * j.rotation;
    }
    Skeleton::new(joints).map_err(|e| ("skeleton", e.to_string()))
}

static SKIN: NodeSpec = NodeSpec::new(
    "skin",
    "Skin",
    "deform",
    "Moves the points with a posed skeleton (joints `name parent x y z` at rest, rotations about each joint): linear blend or dual quaternions. Weights come from float point attributes `w_<joint>` when the geometry has any, else from the distance to each bone (inverse fourth power, four bones at most). Normals are not recomputed.",
    &[geometry_input("geometry")],
    &[
        P::new("method", "Method", T::Menu(&["linear", "dual_quaternion"]), D::Str("dual_quaternion"), "Linear blend (may collapse at joints) or dual quaternions (keeps volume)."),
        SKELETON,
        POSE,
        BEND_JOINT,
        BEND,
    ],
);

fn cook_skin(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let skeleton = skeleton_from_params(ctx, p)?;
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

pub fn register(r: &mut Registry) {
    r.node(&SKIN, cook_skin);
}
