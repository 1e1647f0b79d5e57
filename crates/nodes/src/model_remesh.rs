//! The remesh node: isotropic remeshing of polygon meshes to a target edge
//! length, uniform or following curvature, features kept (geode-model's
//! `remesh`).

use geode_geo::AttribClass;
use geode_model::remesh::{self, RemeshOptions, Sizing};
use geode_model::ModelError;
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{geometry, group_param, input};

const SIZING: P = P::new(
    "sizing",
    "Sizing",
    T::Menu(&["uniform", "adaptive"]),
    D::Str("uniform"),
    "uniform: one target edge length everywhere. adaptive: shorter edges where the surface bends more (between the minimum and maximum length).",
);
const RELATIVE: P = P::new(
    "relative",
    "Relative to size",
    T::Toggle,
    D::Toggle(true),
    "Lengths and the tolerance are fractions of the input's bounding box diagonal (off: scene units).",
);
const TARGET_LENGTH: P = P::new(
    "target_length",
    "Target edge length",
    T::Float,
    D::Float(0.02),
    "Uniform sizing: the edge length aimed at (edges end between 4/5 and 4/3 of it, their mean within a few percent of it). At most the length that leaves about a hundred triangles on the surface, so a target past the model's size gives a coarse solid, not a speck.",
);
const MIN_LENGTH: P = P::new(
    "min_length",
    "Minimum edge length",
    T::Float,
    D::Float(0.005),
    "Adaptive sizing: the shortest target length, where the surface bends most.",
);
const MAX_LENGTH: P = P::new(
    "max_length",
    "Maximum edge length",
    T::Float,
    D::Float(0.05),
    "Adaptive sizing: the longest target length, on flat parts.",
);
const TOLERANCE: P = P::new(
    "tolerance",
    "Tolerance",
    T::Float,
    D::Float(0.001),
    "Adaptive sizing: how far an edge may stray from the curved surface it spans; the target length at curvature k is sqrt(6 e / k - 3 e²).",
);
const GRADATION: P = P::new(
    "gradation",
    "Gradation",
    T::Float,
    D::Float(0.5),
    "Adaptive sizing: how fast the target length may grow with distance (0.5: by half a unit of length per unit of distance); smaller grades more smoothly.",
)
.range(0.0, 100.0);
const ITERATIONS: P = P::new(
    "iterations",
    "Iterations",
    T::Int,
    D::Int(10),
    "Rounds of split, collapse, flip, then three of relax and project (MeshLab's default is also 10).",
)
.range(0.0, 1000.0);
const CREASE_ANGLE: P = P::new(
    "crease_angle",
    "Crease angle",
    T::Float,
    D::Float(30.0),
    "Degrees: edges whose faces turn more than this are kept as features (never flipped, collapsed only along their line); 180 keeps none but borders.",
)
.range(0.0, 180.0);
const FEATURE_GROUP: P = P::new(
    "feature_group",
    "Feature points",
    T::String,
    D::Str(""),
    "A point group: edges between two of its points are kept as features too (geode has no edge groups). Empty: none.",
);

static REMESH: NodeSpec = NodeSpec::new(
    "remesh",
    "Remesh",
    "model",
    "Isotropic remeshing (Botsch and Kobbelt 2004): splits long edges, collapses short ones, flips edges toward valence 6, relaxes points in their tangent planes and projects them back onto the original surface, for near-equilateral triangles of the target length. Borders, creases sharper than the crease angle and edges of the feature group are kept, their corners fixed. Point and vertex attributes are interpolated from the original where each point lands, primitive attributes and groups come from the nearest original face. The output is triangles. Houdini's Remesh SOP and Blender's (voxel/quad) remesher differ: Houdini keeps the same kind of triangles but its hard edges come from an edge group and its adaptive mode from a gradation only; Blender's voxel remesh rebuilds topology and loses attributes. MeshLab's isotropic explicit remeshing is the same algorithm.",
    &[geometry_input("geometry")],
    &[SIZING, RELATIVE, TARGET_LENGTH, MIN_LENGTH, MAX_LENGTH, TOLERANCE, GRADATION, ITERATIONS, CREASE_ANGLE, FEATURE_GROUP],
);

fn cook_remesh(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let features = group_param(ctx, p, &FEATURE_GROUP, g, AttribClass::Point)?;
    let sizing = match p.string(&SIZING)? {
        "adaptive" => Sizing::Adaptive {
            min: p.float(&MIN_LENGTH)? as f32,
            max: p.float(&MAX_LENGTH)? as f32,
            tolerance: p.float(&TOLERANCE)? as f32,
            gradation: p.float(&GRADATION)? as f32,
        },
        _ => Sizing::Uniform {
            length: p.float(&TARGET_LENGTH)? as f32,
        },
    };
    let opts = RemeshOptions {
        sizing,
        relative: p.toggle(&RELATIVE)?,
        iterations: p.int(&ITERATIONS)?.clamp(0, 1000) as u32,
        crease_angle: p.float(&CREASE_ANGLE)? as f32,
        feature_points: features.as_ref(),
    };
    let blame = |e: ModelError| {
        let text = e.to_string();
        let param = [
            ("target length", &TARGET_LENGTH),
            ("minimum length", &MIN_LENGTH),
            ("maximum length", &MAX_LENGTH),
            ("tolerance", &TOLERANCE),
            ("gradation", &GRADATION),
            ("crease angle", &CREASE_ANGLE),
            ("feature group", &FEATURE_GROUP),
        ]
        .iter()
        .find(|(what, _)| text.contains(what))
        .map(|(_, name)| *name);
        match (e, param) {
            (ModelError::Cancelled, _) => CookError::cancelled(ctx.path),
            (e, Some(param)) => ctx.kernel_at(param, e),
            (e, None) => ctx.kernel(e),
        }
    };
    // Per output triangle: three corners, the working mesh's arrays, the
    // attribute weights (about 160 bytes); the original's hierarchy.
    let triangles = remesh::expected_triangles(g, &opts).map_err(blame)?;
    let bytes = triangles * 160.0 + g.num_vertices() as f64 * 96.0;
    let param = match sizing {
        Sizing::Uniform { .. } => &TARGET_LENGTH,
        Sizing::Adaptive { .. } => &MIN_LENGTH,
    };
    ctx.reserve(param, bytes, "the remeshed triangles")?;
    remesh::remesh(g, &opts, &ctx.cancel_fn())
        .map_err(blame)
        .and_then(geometry)
}

pub fn register(r: &mut Registry) {
    r.node(&REMESH, cook_remesh);
}
