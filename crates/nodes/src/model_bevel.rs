//! The polybevel node: edges or points of a polygon mesh bevelled by an
//! offset, in segments following a profile, clamped so bevels never
//! overlap (geode-model's `bevel`).

use geode_geo::AttribClass;
use geode_model::bevel::{bevel, Affect, Bevel, CORNER_GROUP, EDGE_GROUP};
use geode_model::ModelError;
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{geometry, group_param, input, length_text};

const AFFECT: P = P::new(
    "affect",
    "Affect",
    T::Menu(Affect::NAMES),
    D::Str("edges"),
    "edges: each selected edge becomes a strip, with patches where they meet; points: each selected point's corner is cut off (Blender's Vertices).",
);
const GROUP: P = P::new(
    "group",
    "Group",
    T::String,
    D::Str(""),
    "The points to bevel, or whose edges to bevel (an edge is bevelled when both its points are in it): a point group's name or a pattern; empty for all.",
);
const OFFSET: P = P::new(
    "offset",
    "Offset",
    T::Float,
    D::Float(0.1),
    "Distance from the edge to the cut, measured in each face (Houdini's Distance); in points mode along each edge from the point.",
)
.at_least(0.0);
const SEGMENTS: P = P::new(
    "segments",
    "Segments",
    T::Int,
    D::Int(1),
    "Quads across each bevel (1: a flat chamfer).",
)
.range(1.0, 1024.0);
const PROFILE: P = P::new(
    "profile",
    "Profile",
    T::Float,
    D::Float(0.5),
    "Shape across the bevel, Blender's profile: 0.5 a circular arc, 0.25 straight, toward 1 a square corner, toward 0 a concave one.",
)
.range(0.0, 1.0);
const CLAMP: P = P::new(
    "clamp",
    "Clamp overlap",
    T::Toggle,
    D::Toggle(true),
    "Lower the offset (for the whole mesh) so no cut passes the far end of an edge or crosses a neighbouring bevel.",
);
const IGNORE_FLAT: P = P::new(
    "ignore_flat",
    "Ignore flat edges",
    T::Toggle,
    D::Toggle(true),
    "Edges mode: leave edges whose two faces are within the flat angle of each other.",
);
const FLAT_ANGLE: P = P::new(
    "flat_angle",
    "Flat angle",
    T::Float,
    D::Float(2.0),
    "Degrees between two faces' normals under which their edge counts as flat.",
)
.range(0.0, 180.0);
const EDGE_GROUP_PARAM: P = P::new(
    "edge_group",
    "Edge faces group",
    T::String,
    D::Str(EDGE_GROUP),
    "Primitive group of the strips along the bevelled edges (empty: none).",
);
const CORNER_GROUP_PARAM: P = P::new(
    "corner_group",
    "Corner faces group",
    T::String,
    D::Str(CORNER_GROUP),
    "Primitive group of the patches over corners and bevelled points (empty: none).",
);

static POLYBEVEL: NodeSpec = NodeSpec::new(
    "polybevel",
    "PolyBevel",
    "model",
    "Bevels the edges or points of a manifold polygon mesh (closed stays closed, Euler characteristic kept): faces are cut back by the offset, each bevelled edge becomes a strip of segments quads along a superellipse profile (Blender's profile; 0.5 is circular), and corners get patches: where three bevelled edges meet (or a bevelled point has three faces) a triangular grid on the sphere-like corner, where two meet alone their profiles are averaged into one (Blender's weld), otherwise one polygon. Groups bevelEdges and bevelCorners. New points take their source point's attributes (points slid along an edge blend its two ends), face corners their corner's (blended along the edge), strips and patches the primitive attributes of an adjacent face and join none of its groups. Unlike Houdini and Blender: edges are chosen by a point group (geode has no edge groups) and the flat angle; the clamp lowers one offset for the whole mesh (as Blender's Clamp Overlap, not Houdini's per-point limit); corners of four or more bevelled edges are one polygon rather than Blender's subdivided vertex mesh; boundary edges are never bevelled (as in Blender); the triangular corner grid is triangles where Blender makes quads.",
    &[geometry_input("geometry")],
    &[AFFECT, GROUP, OFFSET, SEGMENTS, PROFILE, CLAMP, IGNORE_FLAT, FLAT_ANGLE, EDGE_GROUP_PARAM, CORNER_GROUP_PARAM],
);

fn cook_polybevel(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let group = group_param(ctx, p, &GROUP, g, AttribClass::Point)?;
    let offset = p.float(&OFFSET)?;
    if !offset.is_finite() || offset < 0.0 {
        return Err(ctx.param_error(
            &OFFSET,
            format!("offset must be zero or more, not {offset}"),
        ));
    }
    let segments = p.int(&SEGMENTS)?;
    if !(1..=1024).contains(&segments) {
        return Err(ctx.param_error(
            &SEGMENTS,
            format!("segments must be between 1 and 1024, not {segments}"),
        ));
    }
    let profile = p.float(&PROFILE)?;
    if !(0.0..=1.0).contains(&profile) {
        return Err(ctx.param_error(
            &PROFILE,
            format!("profile must be between 0 and 1, not {profile}"),
        ));
    }
    let flat = p.float(&FLAT_ANGLE)?;
    if !(0.0..=180.0).contains(&flat) {
        return Err(ctx.param_error(
            &FLAT_ANGLE,
            format!("the flat angle must be between 0 and 180 degrees, not {flat}"),
        ));
    }
    let (edge_group, corner_group) = (p.string(&EDGE_GROUP_PARAM)?, p.string(&CORNER_GROUP_PARAM)?);
    if !edge_group.is_empty() && edge_group == corner_group {
        return Err(ctx.param_error(
            &CORNER_GROUP_PARAM,
            format!(
                "the corner group needs a name of its own (the edge group is `{edge_group}` too)"
            ),
        ));
    }
    let how = Bevel {
        affect: Affect::from_name(p.string(&AFFECT)?).unwrap_or(Affect::Edges),
        offset: offset as f32,
        segments: segments as u32,
        profile: profile as f32,
        clamp: p.toggle(&CLAMP)?,
        flat_angle: p.toggle(&IGNORE_FLAT)?.then_some(flat as f32),
        edge_group: edge_group.to_string(),
        corner_group: corner_group.to_string(),
    };
    // Each corner becomes a chain and each edge at most a strip of n
    // quads (4n vertices over its two half-edges); a corner patch holds
    // about 1.5 n^2 triangle corners. Vertices about 48 bytes with their
    // attributes, points 32 per segment.
    let n = segments as f64;
    let vertices = g.num_vertices() as f64 * (1.0 + 2.0 * n) + g.num_points() as f64 * 1.5 * n * n;
    let bytes = vertices * 48.0 + g.num_points() as f64 * (1.0 + n) * 32.0;
    ctx.reserve(&SEGMENTS, bytes, "the bevel")?;
    match bevel(g, group.as_ref(), &how, &ctx.cancel_fn()) {
        Ok((out, report)) => {
            // A clamp below the asked offset is worth saying: one short
            // edge (a boolean's sliver) lowers it for the whole mesh, and
            // at the limit bevels meet in points (faces with no area).
            if how.clamp && report.offset < 0.999 * how.offset {
                ctx.warn(format!(
                    "the clamp lowered the offset from {} to {} for the whole mesh: its shortest bevelled edges allow no more (turn Clamp off, or clean the mesh's short edges first)",
                    how.offset,
                    length_text(report.offset)
                ));
            }
            if !how.clamp && how.offset > report.limit {
                ctx.warn(format!(
                    "offset {} passes {}, where bevels meet: the result overlaps itself (turn Clamp on to stop there)",
                    how.offset,
                    length_text(report.limit)
                ));
            }
            geometry(out)
        }
        Err(ModelError::Cancelled) => Err(CookError::cancelled(ctx.path)),
        Err(e) => Err(ctx.kernel(e)),
    }
}

pub fn register(r: &mut Registry) {
    r.node(&POLYBEVEL, cook_polybevel);
}
