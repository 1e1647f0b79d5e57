//! Nodes that spread values over space: attribute_transfer (from a second
//! geometry's nearest points or surface) and attribute_blur (over edges or
//! proximity).

use geode_attrib::blur::{self, Mode};
use geode_attrib::kdtree::KdTree;
use geode_attrib::relation::surface_triangles;
use geode_attrib::transfer::{self, Reach, MAX_SAMPLES};
use geode_geo::ops::TriangleBvh;
use geode_geo::pattern::match_names;
use geode_geo::{AttribClass, Geometry, Group};
use geode_op::{
    geometry_input, CookContext, CookError, InputSpec, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, PortType, Registry, Value,
};

use crate::attribute_move::attrib_error;
use crate::util::{
    class, element_positions, geometry, group_param, input, input_owned, ELEMENT_CLASSES,
};

const TRANSFER_POINTS: P = P::new(
    "points",
    "Point attributes",
    T::String,
    D::Str("Cd"),
    "The source's point attributes to transfer onto the destination's points, by name pattern (`Cd uv*`, `* ^P`).",
);
const TRANSFER_PRIMS: P = P::new(
    "primitives",
    "Primitive attributes",
    T::String,
    D::Str(""),
    "The source's primitive attributes to transfer onto the destination's primitives (each from the source primitive nearest its centroid), by name pattern.",
);
const TRANSFER_USE_THRESHOLD: P = P::new(
    "use_threshold",
    "Distance threshold",
    T::Toggle,
    D::Toggle(false),
    "Transfer only within the threshold (and fade over the blend width); off: every destination takes its nearest source's value. The threshold also bounds the search: primitives far from every source surface (inside a closed shape) cost up to a millisecond each unbounded.",
);
const TRANSFER_THRESHOLD: P = P::new(
    "threshold",
    "Threshold",
    T::Float,
    D::Float(0.1),
    "Destinations within this distance of their nearest source take the transferred value whole.",
)
.at_least(0.0);
const TRANSFER_BLEND: P = P::new(
    "blend_width",
    "Blend width",
    T::Float,
    D::Float(0.0),
    "Past the threshold, the distance over which the transferred value fades into the destination's own.",
)
.at_least(0.0);
const TRANSFER_SAMPLES: P = P::new(
    "samples",
    "Max samples",
    T::Int,
    D::Int(1),
    "Source points a destination point averages (by inverse squared distance); 1 takes the nearest's value.",
)
.range(1.0, MAX_SAMPLES as f64);

static TRANSFER: NodeSpec = NodeSpec::new(
    "attribute_transfer",
    "Attribute Transfer",
    "attribute",
    "Copies attributes from a second geometry by proximity (Houdini's Attribute Transfer): points from its nearest points (k-d tree), primitives from its nearest primitive (triangle hierarchy), within a threshold and fading over a blend width.",
    &[
        geometry_input("geometry"),
        InputSpec { name: "source", ty: PortType::Geometry, required: true },
    ],
    &[
        TRANSFER_POINTS,
        TRANSFER_PRIMS,
        TRANSFER_USE_THRESHOLD,
        TRANSFER_THRESHOLD,
        TRANSFER_BLEND,
        TRANSFER_SAMPLES,
    ],
);

fn cook_transfer(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let source = input(ctx, inputs, 1)?;
    let reach = Reach {
        threshold: if p.toggle(&TRANSFER_USE_THRESHOLD)? {
            p.float(&TRANSFER_THRESHOLD)? as f32
        } else {
            f32::INFINITY
        },
        blend_width: p.float(&TRANSFER_BLEND)? as f32,
        samples: p.int(&TRANSFER_SAMPLES)?.clamp(1, MAX_SAMPLES as i64) as usize,
    };
    let cancel = ctx.cancel_fn();
    let point_names = names(source, AttribClass::Point, p.string(&TRANSFER_POINTS)?);
    if !point_names.is_empty() {
        ctx.reserve(
            &TRANSFER_SAMPLES,
            g.num_points() as f64 * reach.samples as f64 * 8.0,
            "transfer weights",
        )?;
        let tree = KdTree::new_cancellable(source.positions(), &cancel)
            .ok_or_else(|| CookError::cancelled(ctx.path))?;
        let stencil = transfer::from_points(&tree, g.positions(), &reach, &cancel)
            .map_err(|e| attrib_error(ctx, &TRANSFER_THRESHOLD, "P", e))?;
        carry(
            ctx,
            &mut g,
            source,
            AttribClass::Point,
            &point_names,
            &stencil,
            &TRANSFER_POINTS,
        )?;
    }
    let prim_names = names(source, AttribClass::Primitive, p.string(&TRANSFER_PRIMS)?);
    if !prim_names.is_empty() {
        let (tris, prim_of) = surface_triangles(source);
        let bvh = TriangleBvh::new_cancellable(source.positions(), &tris, &cancel)
            .ok_or_else(|| CookError::cancelled(ctx.path))?;
        let centroids = element_positions(&g, AttribClass::Primitive);
        let stencil = transfer::from_surface(&bvh, &prim_of, &centroids, &reach, &cancel)
            .map_err(|e| attrib_error(ctx, &TRANSFER_THRESHOLD, "P", e))?;
        carry(
            ctx,
            &mut g,
            source,
            AttribClass::Primitive,
            &prim_names,
            &stencil,
            &TRANSFER_PRIMS,
        )?;
    }
    geometry(g)
}

/// The source's attributes of class `c` a pattern names (P never: the
/// destination keeps its positions).
fn names(source: &Geometry, c: AttribClass, pattern: &str) -> Vec<String> {
    match_names(pattern, source.attribs(c).names())
        .into_iter()
        .filter(|n| !(c == AttribClass::Point && *n == geode_geo::P))
        .map(str::to_owned)
        .collect()
}

/// Each named attribute carried through the stencil onto `g`.
fn carry(
    ctx: &CookContext,
    g: &mut Geometry,
    source: &Geometry,
    c: AttribClass,
    names: &[String],
    stencil: &transfer::Stencil,
    spec: &P,
) -> Result<(), CookError> {
    for name in names {
        let from = source.attrib(c, name).expect("named from the source");
        let moved = transfer::apply(stencil, from, g.attrib(c, name));
        g.set_attrib(c, name, moved)
            .map_err(|e| ctx.kernel_at(spec, e))?;
    }
    Ok(())
}

const BLUR_NAME: P = P::new("name", "Attributes", T::String, D::Str("P"), "The float and vector attributes to blur, by name pattern (`P` smooths the shape, `Cd` the colour).");
const BLUR_CLASS: P = P::new(
    "class",
    "Class",
    T::Menu(ELEMENT_CLASSES),
    D::Str("point"),
    "Blur point attributes (over points) or primitive attributes (over primitives).",
);
const BLUR_METHOD: P = P::new(
    "method",
    "Blurring method",
    T::Menu(&["connectivity", "proximity"]),
    D::Str("connectivity"),
    "Neighbours are the elements an edge joins, or the points within the radius (points only).",
);
const BLUR_RADIUS: P = P::new(
    "radius",
    "Radius",
    T::Float,
    D::Float(0.1),
    "Proximity: how far a point's neighbours may be.",
)
.at_least(0.0);
const BLUR_MAX: P = P::new(
    "max_neighbours",
    "Max neighbours",
    T::Int,
    D::Int(10),
    "Proximity: the nearest this many within the radius.",
)
.range(1.0, 1024.0);
const BLUR_ITERATIONS: P = P::new(
    "iterations",
    "Blurring iterations",
    T::Int,
    D::Int(10),
    "Passes; each moves every value toward its neighbours' mean.",
)
.range(0.0, 100_000.0);
const BLUR_STEP: P = P::new(
    "step",
    "Step size",
    T::Float,
    D::Float(0.5),
    "How far toward the mean each pass goes (1: all the way).",
)
.range(0.0, 1.0);
const BLUR_MODE: P = P::new(
    "mode",
    "Mode",
    T::Menu(&["laplacian", "volume_preserving"]),
    D::Str("laplacian"),
    "Plain averaging, or Taubin's alternating passes, which keep the values' level (and a blurred P's volume) instead of shrinking toward the mean.",
);
const BLUR_PINNED: P = P::new(
    "pinned",
    "Pinned",
    T::String,
    D::Str(""),
    "Elements that keep their values (a group pattern).",
);
const BLUR_PIN_BORDER: P = P::new(
    "pin_border",
    "Pin border points",
    T::Toggle,
    D::Toggle(false),
    "Points on open edges keep their values.",
);

static BLUR: NodeSpec = NodeSpec::new(
    "attribute_blur",
    "Attribute Blur",
    "attribute",
    "Smooths float and vector attributes over the surface (Houdini's Attribute Blur): over edges or by proximity, Laplacian or volume-preserving, with pinned elements.",
    &[geometry_input("geometry")],
    &[
        BLUR_NAME,
        BLUR_CLASS,
        BLUR_METHOD,
        BLUR_RADIUS,
        BLUR_MAX,
        BLUR_ITERATIONS,
        BLUR_STEP,
        BLUR_MODE,
        BLUR_PINNED,
        BLUR_PIN_BORDER,
    ],
);

fn cook_blur(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let c = class(p, &BLUR_CLASS)?;
    let cancel = ctx.cancel_fn();
    let pattern = p.string(&BLUR_NAME)?;
    let names = crate::attribute_move::names_matching(ctx, &BLUR_NAME, pattern, &g, c)?;
    let neighbours = if p.string(&BLUR_METHOD)? == "proximity" {
        if c != AttribClass::Point {
            return Err(ctx.param_error(
                &BLUR_METHOD,
                "proximity blurs point attributes: choose connectivity for primitives",
            ));
        }
        let max = p.int(&BLUR_MAX)?.clamp(1, 1024) as usize;
        ctx.reserve(
            &BLUR_MAX,
            g.num_points() as f64 * max as f64 * 4.0,
            "proximity neighbours",
        )?;
        blur::proximity_neighbours(g.positions(), p.float(&BLUR_RADIUS)? as f32, max, &cancel)
            .map_err(|e| attrib_error(ctx, &BLUR_RADIUS, pattern, e))?
    } else if c == AttribClass::Point {
        blur::point_neighbours(&g)
    } else {
        blur::prim_neighbours(&g)
    };
    let pinned = pinned(ctx, p, &g, c)?;
    let mode = if p.string(&BLUR_MODE)? == "volume_preserving" {
        Mode::VolumePreserving
    } else {
        Mode::Laplacian
    };
    let iterations = p.int(&BLUR_ITERATIONS)?.max(0) as usize;
    let step = p.float(&BLUR_STEP)? as f32;
    for name in names {
        let attr = g.attrib(c, &name).expect("matched").clone();
        let blurred = blur::blur(
            &attr,
            &neighbours,
            iterations,
            step,
            mode,
            pinned.as_ref(),
            &cancel,
        )
        .map_err(|e| attrib_error(ctx, &BLUR_NAME, &name, e))?;
        g.set_attrib(c, &name, blurred)
            .map_err(|e| ctx.kernel_at(&BLUR_NAME, e))?;
    }
    geometry(g)
}

/// The pinned group, with the border's points when asked.
fn pinned(
    ctx: &CookContext,
    p: &Params,
    g: &Geometry,
    c: AttribClass,
) -> Result<Option<Group>, CookError> {
    let mut pinned = if p.string(&BLUR_PINNED)?.is_empty() {
        None
    } else {
        Some(
            group_param(ctx, p, &BLUR_PINNED, g, c)?
                .unwrap_or_else(|| Group::from_flags((0..crate::util::count(g, c)).map(|_| true))),
        )
    };
    if p.toggle(&BLUR_PIN_BORDER)? && c == AttribClass::Point {
        let topo = g.topology();
        let grp = pinned.get_or_insert_with(|| Group::new(g.num_points()));
        for e in topo.boundary_edges() {
            for q in topo.edges()[e] {
                grp.set(q as usize, true);
            }
        }
    }
    Ok(pinned)
}

pub fn register(r: &mut Registry) {
    r.node(&TRANSFER, cook_transfer);
    r.node(&BLUR, cook_blur);
}
