//! The FRep nodes that turn a field into geometry: `polygonise` (the
//! sharp-feature, adaptive mesher) and `sample` (values on a grid of
//! points), with the bounds every sampling node shares.

use geode_frep::Field;
use geode_geo::{AttribClass, AttribData, Attribute, TypeInfo};
use geode_mesher::{MeshError, MeshOptions};
use geode_op::{
    CookContext, CookError, InputSpec, NodeSpec, ParamDefault as D, ParamSpec as P, ParamType as T,
    Params, PortType, Registry, Value,
};

use crate::util::input_owned;

use crate::frep::{field_input, v3, FIELD_IN};

pub(crate) const BOUNDS_MIN: P = P::new(
    "min",
    "Bounds min",
    T::Vec3,
    D::Vec3([-1.0; 3]),
    "Box corner.",
);
pub(crate) const BOUNDS_MAX: P = P::new(
    "max",
    "Bounds max",
    T::Vec3,
    D::Vec3([1.0; 3]),
    "Opposite corner.",
);
const POLYGONISE_DEPTH: P = P::new(
    "depth",
    "Octree depth",
    T::Int,
    D::Int(6),
    "Resolution: 2^depth cells along the longest side.",
)
.range(1.0, 12.0);
const POLYGONISE_SHARPNESS: P = P::new(
    "sharpness",
    "Feature threshold",
    T::Float,
    D::Float(0.05),
    "Smaller keeps fainter sharp features.",
)
.range(1e-6, 1.0);
const POLYGONISE_TOLERANCE: P = P::new(
    "tolerance",
    "Tolerance",
    T::Float,
    D::Float(0.0),
    "Adaptive output, in model units: cells merge and triangles collapse wherever the surface stays within this distance of the field's (first-order distance |f|/|grad f|), and edges split where the uniform mesh strays further. 0 keeps the uniform mesh.",
)
.at_least(0.0);

static POLYGONISE: NodeSpec = NodeSpec::new(
    "polygonise",
    "Polygonise",
    "frep",
    "Meshes a field into closed, manifold triangles with sharp edges and corners kept and point normals from the gradient. The box bounds the solid (and closes it where the solid reaches it); the longest side is cut into 2^depth cells. With a tolerance, flat and gently curved regions take few, large triangles (adaptive output). Surface thinner than a cell that the cells' corners miss (a wall, a slot, a sharp crest) is meshed on both of its sides where grid edges cross it twice; what no grid edge meets (a speck inside a cell) is reported in a warning naming its region, never lost silently.",
    &[FIELD_IN],
    &[
        BOUNDS_MIN,
        BOUNDS_MAX,
        POLYGONISE_DEPTH,
        POLYGONISE_SHARPNESS,
        POLYGONISE_TOLERANCE,
    ],
);

fn cook_polygonise(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let f = field_input(ctx, inputs, 0)?;
    let mut opts = MeshOptions::new(
        v3(p, &BOUNDS_MIN)?,
        v3(p, &BOUNDS_MAX)?,
        p.int(&POLYGONISE_DEPTH)? as u32,
    );
    opts.sharpness = p.float(&POLYGONISE_SHARPNESS)?;
    opts.tolerance = p.float(&POLYGONISE_TOLERANCE)?;
    reserve_meshing(ctx, f, &opts)?;
    let cancel = || ctx.cancel.is_cancelled();
    let progress = |x: f32| ctx.progress(x);
    match geode_mesher::polygonise(f, &opts, &cancel, &progress) {
        Ok((g, stats)) => {
            warn_of_thin_features(ctx, &opts, &stats);
            warn_of_deviation(ctx, &opts, &stats);
            Ok(Value::geometry(g))
        }
        Err(MeshError::Cancelled) => Err(CookError::cancelled(ctx.path)),
        Err(MeshError::BadBounds) => {
            Err(ctx.param_error(&BOUNDS_MAX, "the bounds must have max > min on every axis"))
        }
        Err(e) => Err(ctx.kernel_at(&POLYGONISE_DEPTH, e)),
    }
}

/// Names the region where surface thinner than a cell is missing.
fn warn_of_thin_features(ctx: &CookContext, opts: &MeshOptions, stats: &geode_mesher::MeshStats) {
    let Some((lo, hi)) = stats.thin_region else {
        return;
    };
    let longest = (0..3)
        .map(|a| opts.max[a] - opts.min[a])
        .fold(0.0, f64::max);
    let cell = longest / (1u64 << opts.depth) as f64;
    let at = |p: [f64; 3]| format!("({:.4}, {:.4}, {:.4})", p[0], p[1], p[2]);
    ctx.warn(format!(
        "surface thinner than a cell ({cell:.4}: a wall, a gap or a sharp tip) is missing from the mesh in {} cells between {} and {}: raise depth (now {}) or thicken it",
        stats.thin_cells,
        at(lo),
        at(hi),
        opts.depth
    ));
}

/// Names how far adaptive output strays where splitting edges could not
/// bring it within the tolerance (a feature thinner than a cell, or a field
/// whose first-order distance reads high in a blend).
fn warn_of_deviation(ctx: &CookContext, opts: &MeshOptions, stats: &geode_mesher::MeshStats) {
    if opts.tolerance > 0.0 && stats.deviation > opts.tolerance {
        ctx.warn(format!(
            "adaptive output strays up to {:.4} from the surface in places, beyond the tolerance {}: raise depth (now {}) to follow it closer",
            stats.deviation, opts.tolerance, opts.depth
        ));
    }
}

/// Refuses meshing the memory budget cannot hold, from the kernel's
/// estimate (a coarse interval octree: milliseconds at any depth). Shallow
/// meshes cannot reach any budget worth having and skip it.
fn reserve_meshing(ctx: &CookContext, f: &Field, opts: &MeshOptions) -> Result<(), CookError> {
    if opts.depth < 9 {
        return Ok(());
    }
    let cancel = || ctx.cancel.is_cancelled();
    let est = match geode_mesher::polygonise::estimate(f, opts, &cancel) {
        Ok(est) => est,
        Err(MeshError::Cancelled) => return Err(CookError::cancelled(ctx.path)),
        Err(e) => return Err(ctx.kernel_at(&POLYGONISE_DEPTH, e)),
    };
    ctx.reserve(
        &POLYGONISE_DEPTH,
        est.bytes,
        &format!(
            "meshing at depth {} ({} cells with surface)",
            opts.depth,
            crate::util::count_text(est.surface_cells)
        ),
    )
}

const SAMPLE_NAME: P = P::new(
    "name",
    "Attribute",
    T::String,
    D::Str("density"),
    "Name of the float point attribute to write.",
);

static SAMPLE: NodeSpec = NodeSpec::new(
    "frep_sample",
    "FRep Sample",
    "frep",
    "Evaluates a field at every point of a geometry into a float point attribute (>= 0 inside the solid).",
    &[InputSpec { name: "geometry", ty: PortType::Geometry, required: true }, FIELD_IN],
    &[
        SAMPLE_NAME,
    ],
);

fn cook_sample(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let f = field_input(ctx, inputs, 1)?;
    let values = geode_mesher::sample(f, g.positions());
    g.set_attrib(
        AttribClass::Point,
        p.string(&SAMPLE_NAME)?,
        Attribute::from_data(AttribData::Float(values), TypeInfo::None),
    )
    .map_err(|e| ctx.kernel_at(&SAMPLE_NAME, e))?;
    Ok(Value::geometry(g))
}

pub fn register(r: &mut Registry) {
    r.node(&POLYGONISE, cook_polygonise);
    r.node(&SAMPLE, cook_sample);
}
