//! Surface modelling nodes: smooth, peak, mountain, bound, match_size
//! (kernels in `geode_model::{smooth, deform, bound}`).
//!
//! Mountain's noise comes from geode-vex through `noise_params` (shared
//! with attribute_noise), passed to the kernel as a closure: the modelling
//! kernel knows no noise function.

use crate::noise_params;
use geode_geo::glam::{Mat3, Vec3};
use geode_geo::ops::{self, Aabb};
use geode_geo::{AttribClass, AttribData, AttribType, Attribute, Geometry, PrimKind, TypeInfo};
use geode_model::bound::{self, BoundingSphere, Justify, OrientedBox, ScaleMode};
use geode_model::deform;
use geode_model::smooth::{self, SmoothMethod, SmoothOptions};
use geode_model::ModelError;
use geode_op::{
    geometry_input, CookContext, CookError, InputSpec, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, PortType, Registry, Value,
};

use crate::util::{geometry, input, input_owned, vec3};

const UPDATE_NORMALS: P = P::new(
    "update_normals",
    "Update normals",
    T::Toggle,
    D::Toggle(true),
    "Recompute an `N` the input has (point: angle-weighted, vertex: split at 60°, primitive: face normals, as the normals node makes them).",
);

const SMOOTH_METHOD: P = P::new(
    "method",
    "Method",
    T::Menu(SmoothMethod::NAMES),
    D::Str("taubin"),
    "laplacian: each pass moves points toward their neighbours' mean (closed surfaces shrink). taubin: a pass forward and one back (Taubin's λ|μ), which smooths without shrinking; like every Taubin filter it slightly amplifies the broadest bends (by at most (λ+μ)²/(4|λμ|) a pass: 0.07% at the defaults), so hundreds of passes inflate the shape: turn on Keep Volume for long runs.",
);
const SMOOTH_STRENGTH: P = P::new(
    "strength",
    "Strength",
    T::Float,
    D::Float(0.5),
    "How far toward the neighbours' mean a point moves in a pass (Taubin's λ).",
)
.range(0.0, 1.0);
const SMOOTH_PASS_BAND: P = P::new(
    "pass_band",
    "Pass band",
    T::Float,
    D::Float(0.1),
    "Taubin: the frequency below which shape is kept, k = 1/λ + 1/μ (0.01 to 0.1 usual; larger smooths more).",
)
.range(0.0, 1.0);
const SMOOTH_ITERATIONS: P = P::new(
    "iterations",
    "Iterations",
    T::Int,
    D::Int(10),
    "Passes (Taubin: pairs of passes).",
)
.range(0.0, 100_000.0);
const SMOOTH_PIN_BORDER: P = P::new(
    "pin_border",
    "Pin border",
    T::Toggle,
    D::Toggle(true),
    "Points on boundary edges (used by one polygon) and the ends of open polylines stay.",
);
const SMOOTH_PIN_GROUP: P = P::new(
    "pin_group",
    "Pin group",
    T::String,
    D::Str(""),
    "A point group that stays (empty: none).",
);
const SMOOTH_KEEP_VOLUME: P = P::new(
    "keep_volume",
    "Keep volume",
    T::Toggle,
    D::Toggle(false),
    "Closed meshes: after every iteration, scale the free points about the centroid so the enclosed volume is the input's.",
);

static SMOOTH: NodeSpec = NodeSpec::new(
    "smooth",
    "Smooth",
    "model",
    "Smooths polygon meshes and polylines over their edges: every point moves toward the mean of the points it shares an edge with (uniform weights), Laplacian or Taubin's shrink-free λ|μ. Borders and a point group can be pinned; closed meshes can keep their volume. Only `P` changes (and `N`, when updated). Houdini's Smooth SOP filters by its own frequency method and Blender's Smooth modifier is the plain Laplacian: results differ in detail; Blender's Laplacian Smooth with volume preservation is closest to keep_volume.",
    &[geometry_input("geometry")],
    &[
        SMOOTH_METHOD,
        SMOOTH_STRENGTH,
        SMOOTH_PASS_BAND,
        SMOOTH_ITERATIONS,
        SMOOTH_PIN_BORDER,
        SMOOTH_PIN_GROUP,
        SMOOTH_KEEP_VOLUME,
        UPDATE_NORMALS,
    ],
);

fn cook_smooth(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let method = match p.string(&SMOOTH_METHOD)? {
        "laplacian" => SmoothMethod::Laplacian,
        _ => SmoothMethod::Taubin {
            pass_band: p.float(&SMOOTH_PASS_BAND)? as f32,
        },
    };
    // Two position buffers, the topology's edges, adjacency and rows.
    let bytes = g.num_points() as f64 * 80.0 + g.num_vertices() as f64 * 48.0;
    ctx.reserve(
        &SMOOTH_ITERATIONS,
        bytes,
        "smoothing's buffers and topology",
    )?;
    let pinned = crate::util::group_param(ctx, p, &SMOOTH_PIN_GROUP, &g, AttribClass::Point)?;
    let opts = SmoothOptions {
        method,
        strength: p.float(&SMOOTH_STRENGTH)? as f32,
        iterations: p.int(&SMOOTH_ITERATIONS)? as u32,
        pin_border: p.toggle(&SMOOTH_PIN_BORDER)?,
        pinned: pinned.as_ref(),
        keep_volume: p.toggle(&SMOOTH_KEEP_VOLUME)?,
    };
    smooth::smooth(&mut g, &opts, &ctx.cancel_fn()).map_err(|e| {
        // The ranges leave two refusals: an open mesh to keep the volume
        // of, and a pass band of exactly 0 or 1.
        let param = match e {
            ModelError::NotClosed { .. } => &SMOOTH_KEEP_VOLUME,
            _ => &SMOOTH_PASS_BAND,
        };
        ctx.kernel_at(param, e)
    })?;
    finish_normals(ctx, g, p)
}

const DEFORM_GROUP: P = P::new(
    "group",
    "Group",
    T::String,
    D::Str(""),
    "The point group that moves (empty: every point).",
);
const PEAK_DISTANCE: P = P::new(
    "distance",
    "Distance",
    T::Float,
    D::Float(0.1),
    "How far each point moves along its normal (negative: inward).",
);

static PEAK: NodeSpec = NodeSpec::new(
    "peak",
    "Peak",
    "model",
    "Moves points along their normals by a distance: the point `N` when the input has one (normalised), else area-weighted normals of the polygons around each point (points of no polygon stay). As Houdini's Peak SOP; Blender's Displace modifier along normals with a flat strength does the same.",
    &[geometry_input("geometry")],
    &[DEFORM_GROUP, PEAK_DISTANCE, UPDATE_NORMALS],
);

fn cook_peak(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let group = crate::util::group_param(ctx, p, &DEFORM_GROUP, &g, AttribClass::Point)?;
    let normals = displacement_normals(ctx, &g)?;
    let distance = p.float(&PEAK_DISTANCE)? as f32;
    deform::peak(&mut g, &normals, group.as_ref(), distance, &ctx.cancel_fn())
        .map_err(|e| ctx.kernel(e))?;
    finish_normals(ctx, g, p)
}

const MOUNTAIN_NOISE: P = P::new(
    "noise",
    "Noise",
    T::Menu(&["perlin", "simplex", "worley"]),
    D::Str("perlin"),
    "The basis: Perlin's improved gradient noise, simplex noise, or Worley's cellular noise as 1 - 2 F1 (cells raised, their borders low).",
);
const MOUNTAIN_HEIGHT: P = P::new(
    "height",
    "Height",
    T::Float,
    D::Float(1.0),
    "The largest displacement: the fractal sum is normalised to [-1, 1] and scaled by it.",
);
static MOUNTAIN: NodeSpec = NodeSpec::new(
    "mountain",
    "Mountain",
    "model",
    "Displaces points along their normals by fractal noise (Perlin, simplex or Worley; octaves, roughness, lacunarity, seed): the same bytes on every machine and thread count. Normals as peak's. Like Houdini's Mountain SOP, but the noise functions are geode's own (the same kinds of field, not Houdini's numbers) and the sum is normalised, so no point moves more than the height; Blender's Displace modifier with a noise texture is the nearest there.",
    &[geometry_input("geometry")],
    &[
        DEFORM_GROUP,
        MOUNTAIN_NOISE,
        MOUNTAIN_HEIGHT,
        noise_params::ELEMENT_SIZE,
        noise_params::OFFSET,
        noise_params::OCTAVES,
        noise_params::ROUGHNESS,
        noise_params::LACUNARITY,
        noise_params::SEED,
        UPDATE_NORMALS,
    ],
);

fn cook_mountain(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let group = crate::util::group_param(ctx, p, &DEFORM_GROUP, &g, AttribClass::Point)?;
    let height = p.float(&MOUNTAIN_HEIGHT)? as f32;
    let fractal = noise_params::fractal(ctx, p, height, &MOUNTAIN_HEIGHT)?;
    let basis = noise_params::basis(p.string(&MOUNTAIN_NOISE)?);
    let normals = displacement_normals(ctx, &g)?;
    deform::mountain(
        &mut g,
        &normals,
        group.as_ref(),
        &fractal,
        &basis,
        &ctx.cancel_fn(),
    )
    .map_err(|e| ctx.kernel(e))?;
    finish_normals(ctx, g, p)
}

/// The directions points move along: point `N`, else area-weighted.
fn displacement_normals(ctx: &CookContext, g: &Geometry) -> Result<Vec<Vec3>, CookError> {
    ctx.reserve(
        &DEFORM_GROUP,
        g.num_points() as f64 * 24.0,
        "normals and moved positions",
    )?;
    match g.attrib(AttribClass::Point, "N").map(|a| a.data()) {
        Some(AttribData::Vec3(n)) => Ok(n.clone()),
        Some(other) => Err(ctx.input_error(format!(
            "point N is {}, not a vector; remove it or make it a vector",
            other.attrib_type()
        ))),
        None => {
            if !g.prim_kinds().contains(&PrimKind::Polygon) {
                ctx.warn("no point N and no polygons to take normals from: nothing moves");
            }
            Ok(deform::area_weighted_normals(g))
        }
    }
}

/// Recomputes an `N` the geometry has, when asked.
fn finish_normals(ctx: &CookContext, mut g: Geometry, p: &Params) -> Result<Value, CookError> {
    if p.toggle(&UPDATE_NORMALS)? {
        for class in [
            AttribClass::Point,
            AttribClass::Vertex,
            AttribClass::Primitive,
        ] {
            let Some(a) = g.attrib(class, "N") else {
                continue;
            };
            if a.attrib_type() != AttribType::Vec3 {
                continue;
            }
            let n = match class {
                AttribClass::Point => ops::point_normals(&g),
                AttribClass::Vertex => ops::vertex_normals(&g, 60.0),
                _ => ops::prim_normals(&g),
            };
            g.set_attrib(
                class,
                "N",
                Attribute::from_data(AttribData::Vec3(n), TypeInfo::Normal),
            )
            .map_err(|e| ctx.kernel(e))?;
        }
    }
    geometry(g)
}

const BOUND_GROUP: P = P::new(
    "group",
    "Group",
    T::String,
    D::Str(""),
    "Bound only this point group's points (empty: every point).",
);
const BOUND_TYPE: P = P::new(
    "type",
    "Type",
    T::Menu(&["box", "oriented", "sphere"]),
    D::Str("box"),
    "box: axis-aligned. oriented: the smallest box found with a face on the convex hull (every large hull face direction and the principal axes, refined by rotating calipers). sphere: the exact smallest sphere (Welzl).",
);
const BOUND_PADDING: P = P::new(
    "padding",
    "Padding",
    T::Float,
    D::Float(0.0),
    "Grows the bound by this distance on every side.",
)
.at_least(0.0);
const BOUND_OUTPUT: P = P::new(
    "output",
    "Output",
    T::Menu(&["mesh", "attributes"]),
    D::Str("mesh"),
    "mesh: the bound as a closed mesh (a box of 6 quads, or a UV sphere of 32 x 16 with its points on the sphere). attributes: the input, unchanged but for the detail attributes.",
);

static BOUND: NodeSpec = NodeSpec::new(
    "bound",
    "Bound",
    "model",
    "The bounding box, oriented bounding box or smallest bounding sphere of the points, with padding, as a mesh or as detail attributes: `bbox_min` and `bbox_max` (the points' axis-aligned bounds, padded), `center` and `radius` (the bound's centre; the sphere's radius, or a box's half diagonal), `size` (a box's side lengths along its axes; the sphere's diameter) and `axes` (3x3, rows the box's axes; identity for box and sphere). The mesh keeps the input's detail attributes. Houdini's Bound SOP makes the same three kinds; its oriented box and sphere come from its own fits, so sizes may differ slightly (geode's sphere is the true minimum).",
    &[geometry_input("geometry")],
    &[BOUND_GROUP, BOUND_TYPE, BOUND_PADDING, BOUND_OUTPUT],
);

/// A bound measured, as the node describes it.
enum Measured {
    Box(OrientedBox),
    Sphere(BoundingSphere),
}

fn cook_bound(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let group = crate::util::group_param(ctx, p, &BOUND_GROUP, g, AttribClass::Point)?;
    let points: Vec<Vec3> = match &group {
        Some(grp) => grp.members().map(|i| g.positions()[i]).collect(),
        None => g.positions().to_vec(),
    };
    if points.is_empty() && group.is_some() {
        return Err(ctx.param_error(&BOUND_GROUP, "the group has no points"));
    }
    let padding = p.float(&BOUND_PADDING)? as f32;
    let kind = p.string(&BOUND_TYPE)?;
    if kind == "oriented" {
        // f64 copies, the hull's faces and outside sets.
        ctx.reserve(&BOUND_TYPE, points.len() as f64 * 200.0, "the convex hull")?;
    }
    let Some(aabb) = bound::axis_aligned_box(&points) else {
        return Err(ctx.input_error("no points to bound"));
    };
    let cancel = ctx.cancel_fn();
    let measured = match kind {
        "oriented" => bound::oriented_box(&points, &cancel)
            .map_err(|e| ctx.kernel(e))?
            .map(|b| Measured::Box(b.padded(padding))),
        "sphere" => bound::bounding_sphere(&points, &cancel)
            .map_err(|e| ctx.kernel(e))?
            .map(|s| Measured::Sphere(s.padded(padding))),
        _ => Some(Measured::Box(OrientedBox::from_aabb(&aabb).padded(padding))),
    }
    .ok_or_else(|| ctx.input_error("no points to bound"))?;
    let padded = Aabb {
        min: aabb.min - Vec3::splat(padding),
        max: aabb.max + Vec3::splat(padding),
    };
    let mut out = if p.string(&BOUND_OUTPUT)? == "attributes" {
        Geometry::clone(g)
    } else {
        let mut mesh = match &measured {
            Measured::Box(b) => bound::box_geometry(b),
            Measured::Sphere(s) => bound::sphere_geometry(s, 32, 16),
        };
        for (name, a) in g.attribs(AttribClass::Detail).iter() {
            mesh.set_attrib(AttribClass::Detail, name, a.clone())
                .map_err(|e| ctx.kernel(e))?;
        }
        mesh
    };
    write_bound_attributes(ctx, &mut out, &measured, &padded)?;
    geometry(out)
}

fn write_bound_attributes(
    ctx: &CookContext,
    g: &mut Geometry,
    measured: &Measured,
    padded: &Aabb,
) -> Result<(), CookError> {
    let (center, radius, size, axes) = match measured {
        Measured::Box(b) => (
            b.center,
            b.half_size.length(),
            b.half_size * 2.0,
            Mat3::from_cols(b.axes[0], b.axes[1], b.axes[2]).transpose(),
        ),
        Measured::Sphere(s) => (
            s.center,
            s.radius,
            Vec3::splat(2.0 * s.radius),
            Mat3::IDENTITY,
        ),
    };
    let vector = |v: Vec3, info| Attribute::from_data(AttribData::Vec3(vec![v]), info);
    let columns = [
        ("bbox_min", vector(padded.min, TypeInfo::Position)),
        ("bbox_max", vector(padded.max, TypeInfo::Position)),
        ("center", vector(center, TypeInfo::Position)),
        ("size", vector(size, TypeInfo::None)),
        (
            "radius",
            Attribute::from_data(AttribData::Float(vec![radius]), TypeInfo::None),
        ),
        (
            "axes",
            Attribute::from_data(AttribData::Mat3(vec![axes]), TypeInfo::None),
        ),
    ];
    for (name, a) in columns {
        g.set_attrib(AttribClass::Detail, name, a)
            .map_err(|e| ctx.kernel(e))?;
    }
    Ok(())
}

const MATCH_TARGET_CENTER: P = P::new(
    "target_center",
    "Target center",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "Without a reference input: the centre of the box to match.",
);
const MATCH_TARGET_SIZE: P = P::new(
    "target_size",
    "Target size",
    T::Vec3,
    D::Vec3([1.0; 3]),
    "Without a reference input: the size of the box to match.",
)
.at_least(0.0);
const JUSTIFY_HELP: &str = "Which side of the bounds meets the target's along this axis: min, center, max, or none (no move).";
const MATCH_JUSTIFY_X: P = P::new(
    "justify_x",
    "Justify X",
    T::Menu(Justify::NAMES),
    D::Str("center"),
    JUSTIFY_HELP,
);
const MATCH_JUSTIFY_Y: P = P::new(
    "justify_y",
    "Justify Y",
    T::Menu(Justify::NAMES),
    D::Str("center"),
    JUSTIFY_HELP,
);
const MATCH_JUSTIFY_Z: P = P::new(
    "justify_z",
    "Justify Z",
    T::Menu(Justify::NAMES),
    D::Str("center"),
    JUSTIFY_HELP,
);
const MATCH_SCALE: P = P::new(
    "scale",
    "Scale",
    T::Menu(ScaleMode::NAMES),
    D::Str("none"),
    "none: move only. uniform: one factor, the largest that fits every side inside the target. per_axis: each side as long as the target's (flat axes keep their size).",
);

static MATCH_SIZE: NodeSpec = NodeSpec::new(
    "match_size",
    "Match Size",
    "model",
    "Moves (and optionally scales) the geometry so its bounds meet the reference input's bounds, or a target centre and size when there is none, justified per axis at the min, centre or max. Normals and other tagged attributes follow the transform; the detail attribute `match_xform` (4x4) holds it. As Houdini's Match Size SOP; its uniform scale fits the chosen axis, geode's fits inside on every axis.",
    &[
        geometry_input("geometry"),
        InputSpec {
            name: "reference",
            ty: PortType::Geometry,
            required: false,
        },
    ],
    &[
        MATCH_TARGET_CENTER,
        MATCH_TARGET_SIZE,
        MATCH_JUSTIFY_X,
        MATCH_JUSTIFY_Y,
        MATCH_JUSTIFY_Z,
        MATCH_SCALE,
    ],
);

fn cook_match_size(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let target = match inputs.get(1).and_then(|v| v.as_ref()) {
        Some(_) => ops::bounds(input(ctx, inputs, 1)?)
            .ok_or_else(|| ctx.input_error("the reference input has nothing to match"))?,
        None => {
            let (c, half) = (
                vec3(p, &MATCH_TARGET_CENTER)?,
                vec3(p, &MATCH_TARGET_SIZE)? * 0.5,
            );
            Aabb {
                min: c - half,
                max: c + half,
            }
        }
    };
    let mut justify = [Justify::Center; 3];
    for (k, param) in [&MATCH_JUSTIFY_X, &MATCH_JUSTIFY_Y, &MATCH_JUSTIFY_Z]
        .into_iter()
        .enumerate()
    {
        justify[k] = Justify::from_name(p.string(param)?).unwrap_or(Justify::Center);
    }
    let scale = ScaleMode::from_name(p.string(&MATCH_SCALE)?).unwrap_or(ScaleMode::None);
    let m = bound::match_size(&mut g, &target, justify, scale)
        .map_err(|e| ctx.kernel_at(&MATCH_TARGET_SIZE, e))?;
    g.set_attrib(
        AttribClass::Detail,
        "match_xform",
        Attribute::from_data(AttribData::Mat4(vec![m]), TypeInfo::None),
    )
    .map_err(|e| ctx.kernel(e))?;
    geometry(g)
}

pub fn register(r: &mut Registry) {
    r.node(&SMOOTH, cook_smooth);
    r.node(&PEAK, cook_peak);
    r.node(&MOUNTAIN, cook_mountain);
    r.node(&BOUND, cook_bound);
    r.node(&MATCH_SIZE, cook_match_size);
}
