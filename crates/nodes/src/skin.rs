//! Skeleton enveloping of any geometry's points: linear blend or dual
//! quaternion skinning, weights automatic (distance to the bones) or from
//! float point attributes `w_<joint>`; the skeleton and the pose are list
//! parameters (rows of joints, rows of keyframable rotations).

use geode_geo::glam::{DQuat, DVec3};
use geode_geo::AttribClass;
use geode_op::{
    geometry_input, CookContext, CookError, ListSpec, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, ParamValue, Params, Registry, Value,
};
use geode_spline::skin::{skin, Joint, Skeleton, SkinMethod};

use crate::util::{geometry, input_owned};

/// A joint row: its name, its parent's (empty for the root; parents come
/// first) and where it is at rest.
const JOINT_NAME: P = P::new(
    "name",
    "Name",
    T::String,
    D::Str(""),
    "The joint's name (weights are read from `w_<name>`).",
);

const JOINT_PARENT: P = P::new(
    "parent",
    "Parent",
    T::String,
    D::Str(""),
    "An earlier joint's name; empty for the root.",
);

const JOINT_REST: P = P::new(
    "rest",
    "Rest position",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "Where the joint is at rest.",
);

static JOINT_ROWS: ListSpec = ListSpec {
    fields: &[JOINT_NAME, JOINT_PARENT, JOINT_REST],
    legacy: Some(legacy_joints),
};

/// A pose row: a joint and its rotation.
const POSE_JOINT: P = P::new(
    "joint",
    "Joint",
    T::String,
    D::Str(""),
    "The joint to rotate.",
);

const POSE_ROTATE: P = P::new(
    "rotate",
    "Rotate",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "Degrees about X, then Y, then Z (keyframable).",
);

static POSE_ROWS: ListSpec = ListSpec {
    fields: &[POSE_JOINT, POSE_ROTATE],
    legacy: Some(legacy_pose),
};

/// The skeleton parameters, declared once for every node that envelopes.
pub(crate) const SKELETON: P = P::list(
    "skeleton",
    "Skeleton",
    &JOINT_ROWS,
    "The joints at rest, parents first.",
);
pub(crate) const POSE: P = P::list(
    "pose",
    "Pose",
    &POSE_ROWS,
    "Joint rotations; several rows for one joint apply in order.",
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

/// Old networks: joints as `name parent x y z` separated by `;` (parent `-`
/// for the root).
fn legacy_joints(text: &str) -> Result<Vec<Vec<ParamValue>>, String> {
    crate::util::legacy_rows(text, "joint", "`name parent x y z`", |w| match *w {
        [name, parent, x, y, z] => Some(vec![
            ParamValue::String(name.to_owned()),
            ParamValue::String(if parent == "-" { "" } else { parent }.to_owned()),
            vector3(x, y, z)?,
        ]),
        _ => None,
    })
}

/// Old networks: rotations as `name rx ry rz` separated by `;`.
fn legacy_pose(text: &str) -> Result<Vec<Vec<ParamValue>>, String> {
    crate::util::legacy_rows(text, "entry", "`name rx ry rz`", |w| match *w {
        [name, x, y, z] => Some(vec![ParamValue::String(name.to_owned()), vector3(x, y, z)?]),
        _ => None,
    })
}

fn vector3(x: &str, y: &str, z: &str) -> Option<ParamValue> {
    let f = crate::util::finite;
    Some(ParamValue::Vector(vec![f(x)?, f(y)?, f(z)?]))
}

/// The posed skeleton the parameters describe; errors name the parameter
/// and row (`skeleton[1].parent`).
pub(crate) fn skeleton_from_params(ctx: &CookContext, p: &Params) -> Result<Skeleton, CookError> {
    let mut joints: Vec<Joint> = Vec::new();
    for row in p.list(&SKELETON)? {
        let name = row.string(&JOINT_NAME)?.trim().to_owned();
        if name.is_empty() {
            return Err(ctx.field_error(&row, &JOINT_NAME, "a joint needs a name"));
        }
        let parent = match row.string(&JOINT_PARENT)?.trim() {
            "" | "-" => None,
            parent => Some(
                joints
                    .iter()
                    .position(|j| j.name == parent)
                    .ok_or_else(|| {
                        ctx.field_error(
                            &row,
                            &JOINT_PARENT,
                            format!("`{parent}` is not an earlier joint"),
                        )
                    })?,
            ),
        };
        joints.push(Joint {
            name,
            parent,
            rest: DVec3::from_array(row.vector::<3>(&JOINT_REST)?),
            rotation: DQuat::IDENTITY,
        });
    }
    posed(ctx, p, joints)
}

/// Joints at rest (from an .hs file) posed by the `pose` and `bend` parameters.
pub(crate) fn posed_skeleton(
    ctx: &CookContext,
    p: &Params,
    joints: &[Joint],
) -> Result<Skeleton, CookError> {
    posed(ctx, p, joints.to_vec())
}

/// Applies the pose rows, then the bend, to joints at rest.
fn posed(ctx: &CookContext, p: &Params, mut joints: Vec<Joint>) -> Result<Skeleton, CookError> {
    let euler = |d: [f64; 3]| {
        DQuat::from_euler(
            geode_geo::glam::EulerRot::ZYX,
            d[2].to_radians(),
            d[1].to_radians(),
            d[0].to_radians(),
        )
    };
    for row in p.list(&POSE)? {
        let name = row.string(&POSE_JOINT)?;
        let j = joints.iter_mut().find(|j| j.name == name).ok_or_else(|| {
            ctx.field_error(&row, &POSE_JOINT, format!("no joint named `{name}`"))
        })?;
        j.rotation = euler(row.vector::<3>(&POSE_ROTATE)?) * j.rotation;
    }
    let name = p.string(&BEND_JOINT)?;
    if !name.is_empty() {
        let j = joints
            .iter_mut()
            .find(|j| j.name == name)
            .ok_or_else(|| ctx.param_error(&BEND_JOINT, format!("no joint named `{name}`")))?;
        j.rotation = euler(p.vector::<3>(&BEND)?) * j.rotation;
    }
    Skeleton::new(joints).map_err(|e| ctx.kernel_at(&SKELETON, e))
}

const SKIN_METHOD: P = P::new(
    "method",
    "Method",
    T::Menu(&["linear", "dual_quaternion"]),
    D::Str("dual_quaternion"),
    "Linear blend (may collapse at joints) or dual quaternions (keeps volume).",
);

static SKIN: NodeSpec = NodeSpec::new(
    "skin",
    "Skin",
    "deform",
    "Moves the points with a posed skeleton (joint rows: name, parent, rest position; pose rows: a joint and its rotation): linear blend or dual quaternions. Weights come from float point attributes `w_<joint>` when the geometry has any, else from the distance to each bone (inverse fourth power, four bones at most). Normals are not recomputed.",
    &[geometry_input("geometry")],
    &[
        SKIN_METHOD,
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
    let method = if p.string(&SKIN_METHOD)? == "linear" {
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
