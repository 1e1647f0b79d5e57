//! The cut family of modelling nodes: clip, mirror, polyfill, convex_hull
//! and revolve, each a thin reading of parameters around its kernel in
//! geode-model.

use geode_geo::Geometry;
use geode_model::clip::{self, Cap, ClipOptions, Keep};
use geode_model::fill::{self, FillMode, FillOptions, Triangulation};
use geode_model::hull;
use geode_model::mirror::{self, MirrorOptions};
use geode_model::revolve::{self, RevolveOptions};
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{geometry, input, reserve_mesh, vec3};

/// A direction parameter's value, refused when it has no length.
fn direction(ctx: &CookContext, p: &Params, spec: &P) -> Result<geode_geo::glam::Vec3, CookError> {
    let v = vec3(p, spec)?;
    if !v.is_finite() || v.length() == 0.0 {
        return Err(ctx.param_error(
            spec,
            format!(
                "{} has no direction: [{}, {}, {}]",
                spec.name, v.x, v.y, v.z
            ),
        ));
    }
    Ok(v)
}

/// Refuses an output about `scale` times the input's size that the memory
/// budget cannot hold.
fn reserve_scaled(
    ctx: &CookContext,
    g: &Geometry,
    param: &geode_op::ParamSpec,
    scale: f64,
) -> Result<(), CookError> {
    reserve_mesh(
        ctx,
        param,
        g.num_points() as f64 * scale,
        g.num_vertices() as f64 * scale,
        g.num_prims() as f64 * scale,
    )
}

// ----- clip -----

const CLIP_ORIGIN: P = P::new(
    "origin",
    "Origin",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "A point of the plane.",
);
const CLIP_NORMAL: P = P::new(
    "normal",
    "Direction",
    T::Vec3,
    D::Vec3([0.0, 1.0, 0.0]),
    "The plane's normal: \"above\" is the side it points to.",
);
const CLIP_DISTANCE: P = P::new(
    "distance",
    "Distance",
    T::Float,
    D::Float(0.0),
    "Moves the plane this far along its normal.",
);
const CLIP_KEEP: P = P::new(
    "keep",
    "Keep",
    T::Menu(Keep::NAMES),
    D::Str("above"),
    "What stays: the part above the plane, below it, or both (split along the cut).",
);
const CLIP_CAP: P = P::new(
    "cap",
    "Cap",
    T::Menu(Cap::NAMES),
    D::Str("none"),
    "Closes each cut loop: one polygon, or triangles (ear clipping). A loop inside another (a torus cut through its ring) is a hole of it. Houdini's Clip leaves this to a PolyCap or PolyFill after it.",
);
const CLIP_SPLIT_POINTS: P = P::new(
    "split_points",
    "Split Points",
    T::Toggle,
    D::Toggle(false),
    "With both sides kept: the side below gets its own copies of the points on the cut, so the two parts come apart.",
);
const CLIP_ABOVE_GROUP: P = P::new(
    "above_group",
    "Above Group",
    T::String,
    D::Str("above"),
    "Primitive group of the faces above the plane, caps included (empty: none).",
);
const CLIP_BELOW_GROUP: P = P::new(
    "below_group",
    "Below Group",
    T::String,
    D::Str("below"),
    "Primitive group of the faces below the plane, caps included (empty: none).",
);
const CLIP_CAP_GROUP: P = P::new(
    "cap_group",
    "Cap Group",
    T::String,
    D::Str("cap"),
    "Primitive group of the caps (empty: none).",
);

static CLIP: NodeSpec = NodeSpec::new(
    "clip",
    "Clip",
    "model",
    "Cuts polygons and polylines by a plane and keeps what lies above it, below it, or both, as Houdini's Clip does. Points on the cut interpolate point and vertex attributes along the edge they cut; pieces keep their primitive's attributes and groups. Optionally caps each cut loop (holes bridged in), so a closed mesh stays closed; caps take the attributes of the face beside them, with vertex normals along the plane's.",
    &[geometry_input("geometry")],
    &[
        CLIP_ORIGIN,
        CLIP_NORMAL,
        CLIP_DISTANCE,
        CLIP_KEEP,
        CLIP_CAP,
        CLIP_SPLIT_POINTS,
        CLIP_ABOVE_GROUP,
        CLIP_BELOW_GROUP,
        CLIP_CAP_GROUP,
    ],
);

fn cook_clip(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let keep = Keep::from_name(p.string(&CLIP_KEEP)?).unwrap_or(Keep::Above);
    let options = ClipOptions {
        origin: vec3(p, &CLIP_ORIGIN)?,
        normal: direction(ctx, p, &CLIP_NORMAL)?,
        distance: p.float(&CLIP_DISTANCE)? as f32,
        keep,
        cap: Cap::from_name(p.string(&CLIP_CAP)?).unwrap_or(Cap::None),
        split_points: p.toggle(&CLIP_SPLIT_POINTS)?,
        above_group: p.string(&CLIP_ABOVE_GROUP)?.to_string(),
        below_group: p.string(&CLIP_BELOW_GROUP)?.to_string(),
        cap_group: p.string(&CLIP_CAP_GROUP)?.to_string(),
    };
    // Pieces and caps: at most a little over the input, per side kept.
    let sides = if keep == Keep::Both { 2.0 } else { 1.0 };
    reserve_scaled(ctx, g, &CLIP_KEEP, 1.2 * sides)?;
    let r = clip::clip(g, &options, &ctx.cancel_fn()).map_err(|e| ctx.kernel(e))?;
    if r.open_loops > 0 {
        ctx.warn(format!(
            "{} cut line{} did not close (the mesh is open or non-manifold where the plane crosses it) and {} not capped",
            r.open_loops,
            if r.open_loops == 1 { "" } else { "s" },
            if r.open_loops == 1 { "was" } else { "were" }
        ));
    }
    geometry(r.geometry)
}

// ----- mirror -----

const MIRROR_ORIGIN: P = P::new(
    "origin",
    "Origin",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "A point of the mirror plane.",
);
const MIRROR_NORMAL: P = P::new(
    "normal",
    "Direction",
    T::Vec3,
    D::Vec3([1.0, 0.0, 0.0]),
    "The mirror plane's normal.",
);
const MIRROR_KEEP_ORIGINAL: P = P::new(
    "keep_original",
    "Keep Original",
    T::Toggle,
    D::Toggle(true),
    "Output the input beside its mirror image (off: the image alone).",
);
const MIRROR_REVERSE: P = P::new(
    "reverse",
    "Reverse Winding",
    T::Toggle,
    D::Toggle(true),
    "Reverse the image's polygons so its normals face out, as the original's do.",
);
const MIRROR_FUSE: P = P::new(
    "fuse",
    "Fuse Seam",
    T::Toggle,
    D::Toggle(true),
    "Merge each point of the original near the plane with its image (Houdini's Consolidate Seam), moving it onto the plane: a half model becomes one closed piece.",
);
const MIRROR_FUSE_DISTANCE: P = P::new(
    "fuse_distance",
    "Seam Distance",
    T::Float,
    D::Float(0.001),
    "How close to the plane a point must be to join the seam.",
)
.at_least(0.0);
const MIRROR_GROUP: P = P::new(
    "group",
    "Mirror Group",
    T::String,
    D::Str("mirror"),
    "Primitive group of the mirror image's faces (empty: none).",
);

static MIRROR: NodeSpec = NodeSpec::new(
    "mirror",
    "Mirror",
    "model",
    "Reflects the geometry across a plane, keeping the original beside the image, reversing the image's winding and fusing the seam, as Houdini's Mirror does. Attributes follow their type: positions reflect about the plane, vectors and normals (N, v, any vector or normal attribute) reflect; quaternions keep their rotation part (a reflection is no rotation). Faces of the original lying on the plane are not mirrored onto themselves, and one closed in by faces on all its edges (a capped half model's cap) is dropped, as it would be a wall inside the whole (Houdini and Blender keep both copies).",
    &[geometry_input("geometry")],
    &[
        MIRROR_ORIGIN,
        MIRROR_NORMAL,
        MIRROR_KEEP_ORIGINAL,
        MIRROR_REVERSE,
        MIRROR_FUSE,
        MIRROR_FUSE_DISTANCE,
        MIRROR_GROUP,
    ],
);

fn cook_mirror(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let options = MirrorOptions {
        origin: vec3(p, &MIRROR_ORIGIN)?,
        normal: direction(ctx, p, &MIRROR_NORMAL)?,
        keep_original: p.toggle(&MIRROR_KEEP_ORIGINAL)?,
        reverse: p.toggle(&MIRROR_REVERSE)?,
        fuse: p.toggle(&MIRROR_FUSE)?,
        fuse_distance: p.float(&MIRROR_FUSE_DISTANCE)? as f32,
        group: p.string(&MIRROR_GROUP)?.to_string(),
    };
    // The original and its image, merged and rebuilt once.
    reserve_scaled(ctx, g, &MIRROR_KEEP_ORIGINAL, 4.0)?;
    let r = mirror::mirror(g, &options, &ctx.cancel_fn())
        .map_err(|e| ctx.kernel_at(&MIRROR_FUSE, e))?;
    geometry(r.geometry)
}

// ----- polyfill -----

const FILL_MODE: P = P::new(
    "mode",
    "Fill Mode",
    T::Menu(FillMode::NAMES),
    D::Str("triangles"),
    "triangles: over the hole's own points; polygon: one n-gon per hole; fan: triangles around a new point at the hole's centre. Houdini's PolyFill also offers quads and smoothing, which geode does not.",
);
const FILL_TRIANGULATION: P = P::new(
    "triangulation",
    "Triangulation",
    T::Menu(Triangulation::NAMES),
    D::Str("min_weight"),
    "min_weight: the triangulation of least summed edge length whose triangles all face the hole's way (holes of up to 200 points; larger ones are ear clipped); ear_clip: ear clipping in the hole's best-fit plane.",
);
const FILL_MAX_POINTS: P = P::new(
    "max_points",
    "Max Hole Points",
    T::Int,
    D::Int(0),
    "Holes with more points than this stay open (0: fill every hole, a grid's outline included).",
)
.at_least(0.0);
const FILL_HOLES: P = P::new(
    "holes",
    "Nested Loops Make Holes",
    T::Toggle,
    D::Toggle(true),
    "A loop in the same plane inside another, wound the other way, becomes a hole in that loop's fill: a torus cut in half gets a ring-shaped face over each cut, as clip's cap gives, not two overlapping discs. Loops along faces lying in their plane (a hole in a flat sheet and the sheet's border) are filled on their own. Houdini's PolyFill fills every loop on its own (this off). Not with fan.",
);
const FILL_GROUP: P = P::new(
    "group",
    "Group",
    T::String,
    D::Str("polyfill"),
    "Primitive group of the new faces (empty: none).",
);

static POLYFILL: NodeSpec = NodeSpec::new(
    "polyfill",
    "PolyFill",
    "model",
    "Fills the holes of a polygon mesh (its boundary loops), each new face wound against the faces around it so a mesh with holes becomes closed and consistently oriented, as Houdini's PolyFill does. New faces take the primitive attributes of a neighbouring face and, per corner, the vertex attributes of the neighbouring corner; a fan's centre takes the loop's means.",
    &[geometry_input("geometry")],
    &[FILL_MODE, FILL_TRIANGULATION, FILL_MAX_POINTS, FILL_HOLES, FILL_GROUP],
);

fn cook_polyfill(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let options = FillOptions {
        mode: FillMode::from_name(p.string(&FILL_MODE)?).unwrap_or(FillMode::Triangles),
        triangulation: Triangulation::from_name(p.string(&FILL_TRIANGULATION)?)
            .unwrap_or(Triangulation::MinWeight),
        max_points: p.int(&FILL_MAX_POINTS)?.max(0) as usize,
        group: p.string(&FILL_GROUP)?.to_string(),
        holes: p.toggle(&FILL_HOLES)?,
    };
    // The copy plus a fill at most as large as the boundary.
    reserve_scaled(ctx, g, &FILL_MODE, 2.0)?;
    let r = fill::polyfill(g, &options, &ctx.cancel_fn()).map_err(|e| ctx.kernel(e))?;
    geometry(r.geometry)
}

// ----- convex_hull -----

const HULL_KEEP_USED: P = P::new(
    "keep_used_points",
    "Keep Only Hull Points",
    T::Toggle,
    D::Toggle(true),
    "Keep only the points the hull uses (off: every input point stays, the hull's faces over them).",
);

static CONVEX_HULL: NodeSpec = NodeSpec::new(
    "convex_hull",
    "Convex Hull",
    "model",
    "The convex hull of the input's points: a closed triangle mesh wound outward (3D quickhull with exact orientation tests, so coplanar, collinear and repeated points need no tolerance and are never vertices, as with Qhull). Points all on one plane give one polygon (facing the plane's dominant axis), all on one line a polyline. Points keep their attributes and groups; faces are new. Houdini's Convex Hull SOP (Qhull) gives the same hull.",
    &[geometry_input("geometry")],
    &[HULL_KEEP_USED],
);

fn cook_convex_hull(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    // Outside sets of 16 bytes a point, the hull's own columns.
    ctx.reserve(
        &HULL_KEEP_USED,
        g.num_points() as f64 * 40.0,
        &format!("the hull of {} points", g.num_points()),
    )?;
    let h = hull::convex_hull(g, p.toggle(&HULL_KEEP_USED)?, &ctx.cancel_fn())
        .map_err(|e| ctx.kernel(e))?;
    geometry(h)
}

// ----- revolve -----

const REVOLVE_ORIGIN: P = P::new(
    "origin",
    "Origin",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "A point of the axis.",
);
const REVOLVE_AXIS: P = P::new(
    "axis",
    "Axis",
    T::Vec3,
    D::Vec3([0.0, 1.0, 0.0]),
    "The axis's direction; the turn is counter-clockwise seen from its tip.",
);
const REVOLVE_START: P = P::new(
    "start_angle",
    "Start Angle",
    T::Float,
    D::Float(0.0),
    "Degrees where the surface starts.",
);
const REVOLVE_END: P = P::new(
    "end_angle",
    "End Angle",
    T::Float,
    D::Float(360.0),
    "Degrees where it ends; a whole number of turns closes the surface.",
);
const REVOLVE_DIVISIONS: P = P::new(
    "divisions",
    "Divisions",
    T::Int,
    D::Int(16),
    "Steps from the start angle to the end angle.",
)
.at_least(1.0);
const REVOLVE_CAPS: P = P::new(
    "caps",
    "End Caps",
    T::Toggle,
    D::Toggle(true),
    "Close a closed curve's partial turn with its outline at both ends.",
);
const REVOLVE_UV: P = P::new(
    "uv",
    "UVs",
    T::Toggle,
    D::Toggle(false),
    "Write vertex uv: u around the axis over the sweep, v along the curve by arc length.",
);

static REVOLVE: NodeSpec = NodeSpec::new(
    "revolve",
    "Revolve",
    "model",
    "Turns polylines and polygon outlines about an axis into surfaces, as Houdini's Revolve does. A point on the axis becomes one point (a pole, with triangles around it), so a half circle with its ends on the axis gives a closed sphere; a whole turn joins up, a partial one caps closed curves. A profile running along the axis on the far side of it (anticlockwise in its radius-height half-plane) faces out. Point and vertex attributes are copied to every step, directions turned with it.",
    &[geometry_input("curves")],
    &[
        REVOLVE_ORIGIN,
        REVOLVE_AXIS,
        REVOLVE_START,
        REVOLVE_END,
        REVOLVE_DIVISIONS,
        REVOLVE_CAPS,
        REVOLVE_UV,
    ],
);

fn cook_revolve(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let (start, end) = (p.float(&REVOLVE_START)?, p.float(&REVOLVE_END)?);
    if start == end {
        return Err(ctx.param_error(
            &REVOLVE_END,
            format!("end_angle equals start_angle ({end}): nothing to revolve"),
        ));
    }
    let divisions = p.int(&REVOLVE_DIVISIONS)?;
    if !(1..=u32::MAX as i64).contains(&divisions) {
        return Err(ctx.param_error(
            &REVOLVE_DIVISIONS,
            format!("divisions must be at least 1 (got {divisions})"),
        ));
    }
    let steps = divisions as f64 + 1.0;
    reserve_mesh(
        ctx,
        &REVOLVE_DIVISIONS,
        g.num_points() as f64 * steps,
        g.num_vertices() as f64 * 4.0 * steps,
        g.num_vertices() as f64 * steps,
    )?;
    let options = RevolveOptions {
        origin: vec3(p, &REVOLVE_ORIGIN)?,
        axis: direction(ctx, p, &REVOLVE_AXIS)?,
        start_angle: start as f32,
        end_angle: end as f32,
        divisions: divisions as u32,
        caps: p.toggle(&REVOLVE_CAPS)?,
        uv: p.toggle(&REVOLVE_UV)?,
    };
    let r = revolve::revolve(g, &options, &ctx.cancel_fn()).map_err(|e| ctx.kernel(e))?;
    geometry(r)
}

pub fn register(r: &mut Registry) {
    r.node(&CLIP, cook_clip);
    r.node(&MIRROR, cook_mirror);
    r.node(&POLYFILL, cook_polyfill);
    r.node(&CONVEX_HULL, cook_convex_hull);
    r.node(&REVOLVE, cook_revolve);
}
