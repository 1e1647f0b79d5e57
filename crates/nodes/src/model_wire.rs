//! The wire family of modelling nodes: polywire (tubes around edges),
//! edge_divide and divide, each a thin reading of parameters around its
//! kernel in geode-model.

use geode_geo::AttribClass;
use geode_model::divide::{self, DivideOptions};
use geode_model::edge_divide::{self, EdgeDivideOptions};
use geode_model::polywire::{self, PolywireOptions};
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{geometry, group_param, input, reserve_mesh, vec3};

/// An int parameter in `lo..=hi`, refused (naming it) outside.
fn int_in(ctx: &CookContext, p: &Params, spec: &P, lo: i64, hi: i64) -> Result<u32, CookError> {
    let v = p.int(spec)?;
    if !(lo..=hi).contains(&v) {
        return Err(ctx.param_error(
            spec,
            format!("{} must be from {lo} to {hi} (got {v})", spec.name),
        ));
    }
    Ok(v as u32)
}

// ----- polywire -----

const WIRE_GROUP: P = P::new(
    "group",
    "Group",
    T::String,
    D::Str(""),
    "The primitives whose edges get tubes: a group's name or a pattern (`0-3`, `@kind==1`); empty for all.",
);
const WIRE_RADIUS: P = P::new(
    "radius",
    "Wire Radius",
    T::Float,
    D::Float(0.1),
    "The tubes' radius, above 0 (times the radius attribute when one is named). Where edges are too short for it, bends and joints are narrowed to fit.",
)
.at_least(0.0);
const WIRE_RADIUS_ATTRIBUTE: P = P::new(
    "radius_attribute",
    "Radius Attribute",
    T::String,
    D::Str(""),
    "A float or int point attribute multiplying the radius (e.g. `pscale`), blended along each edge; empty for none. Named but missing is an error.",
);
const WIRE_DIVISIONS: P = P::new(
    "divisions",
    "Divisions",
    T::Int,
    D::Int(8),
    "Points around each ring.",
)
.range(3.0, 4096.0);
const WIRE_SEGMENTS: P = P::new(
    "segments",
    "Segments",
    T::Int,
    D::Int(1),
    "Rings across each edge (1: rings at its ends only).",
)
.range(1.0, 4096.0);
const WIRE_CAPS: P = P::new(
    "caps",
    "End Caps",
    T::Toggle,
    D::Toggle(true),
    "Close the tubes at free ends (points with one edge) with their ring as one polygon.",
);
const WIRE_UV: P = P::new(
    "uv",
    "UVs",
    T::Toggle,
    D::Toggle(false),
    "Write vertex uv: u around each tube, v by arc length along each run of edges between joints and ends (it replaces a point or primitive uv carried from the input).",
);

const WIRE_UNION: P = P::new(
    "union",
    "Union Crowded Twigs",
    T::Toggle,
    D::Toggle(true),
    "Where a crowded joint leaves twigs out (capped inside a kept tube), union the overlapping closed pieces into one solid through the boolean, so the result does not pass through itself there (it is then triangles). Off: the pieces stay separate, overlapping, and quads.",
);

static POLYWIRE: NodeSpec = NodeSpec::new(
    "polywire",
    "PolyWire",
    "model",
    "Tubes around every edge of polylines and polygons, as Houdini's PolyWire, joined into one closed surface: each run of edges between ends and branch points is one tube (frames carried without twist), a point where two edges meet is one mitred ring, and where three or more meet the tubes stop short and the convex hull of their end rings closes the joint. A tree or graph skeleton gives a closed manifold with outward faces. Ring points blend their edge's points' attributes; faces copy their edge's primitive. Unlike Houdini (separate tubes overlapping at shared points, not closed), joints here are watertight; where edges are too short for the radius a joint's rings, and a bend's mitre, are narrowed until they fit (a pinch: a radius far past the edges gives a pinched lattice, not tubes through each other); where dozens of twigs leave a point a degree or two apart (as space colonization grows them) the twigs nearest in angle to a kept tube are left out of the joint and capped inside it, then unioned with it (see Union Crowded Twigs); where every edge leaves a point on one side (a broom), the tubes run to the point and are unioned there; and a very sharp bend's mitre is stretched at most four times.",
    &[geometry_input("skeleton")],
    &[
        WIRE_GROUP,
        WIRE_RADIUS,
        WIRE_RADIUS_ATTRIBUTE,
        WIRE_DIVISIONS,
        WIRE_SEGMENTS,
        WIRE_CAPS,
        WIRE_UV,
        WIRE_UNION,
    ],
);

fn cook_polywire(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let group = group_param(ctx, p, &WIRE_GROUP, g, AttribClass::Primitive)?;
    let radius = p.float(&WIRE_RADIUS)?;
    if !(radius > 0.0 && radius.is_finite()) {
        return Err(ctx.param_error(
            &WIRE_RADIUS,
            format!("radius must be positive (got {radius})"),
        ));
    }
    let attribute = p.string(&WIRE_RADIUS_ATTRIBUTE)?;
    if !attribute.is_empty() && g.attrib(AttribClass::Point, attribute).is_none() {
        return Err(ctx.param_error(
            &WIRE_RADIUS_ATTRIBUTE,
            format!("there is no point attribute `{attribute}` for the radius"),
        ));
    }
    let options = PolywireOptions {
        radius: radius as f32,
        radius_attribute: Some(attribute.to_string()).filter(|a| !a.is_empty()),
        divisions: int_in(ctx, p, &WIRE_DIVISIONS, 3, 4096)?,
        segments: int_in(ctx, p, &WIRE_SEGMENTS, 1, 4096)?,
        caps: p.toggle(&WIRE_CAPS)?,
        uv: p.toggle(&WIRE_UV)?,
        union: p.toggle(&WIRE_UNION)?,
    };
    // At most one edge per vertex; each edge makes segments + 1 rings.
    let rings = g.num_vertices() as f64 * (options.segments as f64 + 1.0);
    let n = options.divisions as f64;
    reserve_mesh(ctx, &WIRE_SEGMENTS, rings * n, 4.0 * rings * n, rings * n)?;
    let out = polywire::polywire(g, group.as_ref(), &options, &ctx.cancel_fn())
        .map_err(|e| ctx.kernel(e))?;
    geometry(out)
}

// ----- edge_divide -----

const DIVIDE_GROUP: P = P::new(
    "group",
    "Group",
    T::String,
    D::Str(""),
    "A point group or pattern: edges with both ends in it are divided; empty for all edges.",
);
const DIVIDE_DIVISIONS: P = P::new(
    "divisions",
    "Divisions",
    T::Int,
    D::Int(1),
    "New points on each edge, evenly spaced.",
)
.at_least(1.0);
const DIVIDE_GROUP_NAME: P = P::new(
    "group_name",
    "Point Group",
    T::String,
    D::Str("divided"),
    "The point group the new points join; empty for none.",
);

static EDGE_DIVIDE: NodeSpec = NodeSpec::new(
    "edge_divide",
    "Edge Divide",
    "model",
    "Inserts points evenly along edges, each new point shared by every polygon or polyline along its edge, so a connected or closed mesh stays so. New points blend their edge's points' attributes and join a point group; polygons keep theirs. Houdini's Edge Divide takes an edge group; geode has none, so edges are chosen by a point group (both ends in it). Unlike Blender's subdivide, faces are not split: an n-gon gains corners on its sides.",
    &[geometry_input("geometry")],
    &[DIVIDE_GROUP, DIVIDE_DIVISIONS, DIVIDE_GROUP_NAME],
);

fn cook_edge_divide(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let group = group_param(ctx, p, &DIVIDE_GROUP, g, AttribClass::Point)?;
    let divisions = int_in(ctx, p, &DIVIDE_DIVISIONS, 1, 1 << 16)?;
    // At most one new edge per vertex, `divisions` points each.
    let new = g.num_vertices() as f64 * divisions as f64;
    reserve_mesh(
        ctx,
        &DIVIDE_DIVISIONS,
        g.num_points() as f64 + new,
        g.num_vertices() as f64 + 2.0 * new,
        g.num_prims() as f64,
    )?;
    let options = EdgeDivideOptions {
        divisions,
        group_name: Some(p.string(&DIVIDE_GROUP_NAME)?.to_string()).filter(|s| !s.is_empty()),
    };
    let out = edge_divide::edge_divide(g, group.as_ref(), &options, &ctx.cancel_fn())
        .map_err(|e| ctx.kernel(e))?;
    geometry(out)
}

// ----- divide -----

const DIVIDE_MODES: &[&str] = &["convex", "bricker"];
const DIVIDE_MODE: P = P::new(
    "mode",
    "Mode",
    T::Menu(DIVIDE_MODES),
    D::Str("convex"),
    "convex: non-convex polygons (and those over max_edges sides) split into convex ones; bricker: every polygon cut by a grid of planes into pieces one cell each.",
);
const DIVIDE_MAX_EDGES: P = P::new(
    "max_edges",
    "Maximum Edges",
    T::Int,
    D::Int(64),
    "convex: the most sides a piece may have (3: triangles).",
)
.at_least(3.0);
const DIVIDE_SIZE: P = P::new(
    "size",
    "Brick Size",
    T::Vec3,
    D::Vec3([1.0, 1.0, 1.0]),
    "bricker: the grid's cell size on each axis.",
);
const DIVIDE_OFFSET: P = P::new(
    "offset",
    "Brick Offset",
    T::Vec3,
    D::Vec3([0.0, 0.0, 0.0]),
    "bricker: where the grid's planes start (planes at offset + k x size).",
);

static DIVIDE: NodeSpec = NodeSpec::new(
    "divide",
    "Divide",
    "model",
    "Houdini's Divide: convex polygons (ear clipping, then Hertel-Mehlhorn removes diagonals while both pieces stay convex and within Maximum Edges: no new points, area unchanged, closed stays closed) or brick polygons (every polygon cut by axis planes at offset + k x size, one piece per cell, cut points shared by neighbours so closed stays closed). Pieces keep their polygon's attributes and groups. Unlike Houdini, Remove Shared Edges and Compute Dual are not offered, and a cut point with a cut point at an end of its edge blends the nearer source points (Houdini interpolates within the face).",
    &[geometry_input("geometry")],
    &[DIVIDE_MODE, DIVIDE_MAX_EDGES, DIVIDE_SIZE, DIVIDE_OFFSET],
);

fn cook_divide(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let out = if p.string(&DIVIDE_MODE)? == "bricker" {
        let size = vec3(p, &DIVIDE_SIZE)?;
        if !(size.is_finite() && size.min_element() > 0.0) {
            return Err(ctx.param_error(
                &DIVIDE_SIZE,
                format!("brick size must be positive on every axis (got {size})"),
            ));
        }
        // A rough count: each polygon crosses its bounds' cells.
        let bounds = geode_geo::ops::bounds(g);
        let cells = bounds.map_or(1.0, |b| {
            ((b.max - b.min) / size)
                .as_dvec3()
                .max(geode_geo::glam::DVec3::ONE)
                .element_product()
        });
        let pieces = (g.num_prims() as f64 * 4.0).max(cells.powf(2.0 / 3.0) * 2.0);
        reserve_mesh(
            ctx,
            &DIVIDE_SIZE,
            g.num_points() as f64 + pieces * 2.0,
            g.num_vertices() as f64 + pieces * 5.0,
            pieces,
        )?;
        divide::bricker(g, size, vec3(p, &DIVIDE_OFFSET)?, &ctx.cancel_fn())
    } else {
        let max_edges = int_in(ctx, p, &DIVIDE_MAX_EDGES, 3, u32::MAX as i64)?;
        reserve_mesh(
            ctx,
            &DIVIDE_MAX_EDGES,
            g.num_points() as f64,
            3.0 * g.num_vertices() as f64,
            g.num_vertices() as f64,
        )?;
        divide::convex_polygons(g, &DivideOptions { max_edges }, &ctx.cancel_fn())
    }
    .map_err(|e| ctx.kernel(e))?;
    geometry(out)
}

pub fn register(r: &mut Registry) {
    r.node(&DIVIDE, cook_divide);
    r.node(&POLYWIRE, cook_polywire);
    r.node(&EDGE_DIVIDE, cook_edge_divide);
}
