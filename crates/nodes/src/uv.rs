//! UV nodes: uv_project (planar, cylindrical, spherical, box through a
//! frame) and uv_flatten (islands cut along seams, least-squares conformal
//! maps, packed into the unit square), writing vertex `uv` as Houdini does
//! (kernels in geode-uv).

use geode_geo::glam::Vec3;
use geode_geo::pattern::GroupPattern;
use geode_geo::{ops, AttribClass, AttribData, Geometry};
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};
use geode_uv::{
    flatten, frame_from_trs, project, write_islands, write_uv, Axis, ConformalMethod,
    FlattenOptions, PackOptions, ProjectOptions, Projection, UvError, UvTransform,
};

use crate::util::{attribute_name, geometry, group_param, input_owned, vec2, vec3};

const NAME: P = P::new(
    "name",
    "UV attribute",
    T::String,
    D::Str("uv"),
    "The vertex attribute written (three floats, z = 0).",
);

/// A kernel error at parameter `param`.
fn uv_error(ctx: &CookContext, param: &P, e: UvError) -> CookError {
    match e {
        UvError::Cancelled => CookError::cancelled(ctx.path),
        UvError::Invalid(why) => ctx.param_error(param, why),
    }
}

const PROJECT_GROUP: P = P::new(
    "group",
    "Group",
    T::String,
    D::Str(""),
    "The primitives to project (a group pattern); the others keep their uv. Empty for all.",
);
const PROJECT_TYPE: P = P::new(
    "type",
    "Projection",
    T::Menu(&["planar", "cylindrical", "spherical", "box"]),
    D::Str("planar"),
    "Planar along an axis, cylindrical or spherical around one, or box (each polygon planar along the axis its normal is closest to).",
);
const PROJECT_AXIS: P = P::new(
    "axis",
    "Axis",
    T::Menu(&["x", "y", "z"]),
    D::Str("y"),
    "The frame's axis the projection is along (planar) or around (cylindrical, spherical).",
);
const PROJECT_FIT: P = P::new("fit", "Fit to bounds", T::Toggle, D::Toggle(true), "Centre the frame on the geometry's bounding box and size it to the box (then rotate it); off: the centre and size below.");
const PROJECT_CENTER: P = P::new(
    "center",
    "Center",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "The frame's centre, when not fitted.",
);
const PROJECT_SIZE: P = P::new(
    "size",
    "Size",
    T::Vec3,
    D::Vec3([1.0; 3]),
    "The frame's size (its unit cube maps onto the unit square), when not fitted.",
);
const PROJECT_ROTATE: P = P::new(
    "rotate",
    "Rotate",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "The frame's rotation in degrees (X, then Y, then Z).",
);
const PROJECT_UV_SCALE: P = P::new(
    "uv_scale",
    "UV scale",
    T::Vec2,
    D::Vec2([1.0, 1.0]),
    "Scale of the result in uv.",
);
const PROJECT_UV_ROTATE: P = P::new(
    "uv_rotate",
    "UV rotate",
    T::Float,
    D::Float(0.0),
    "Rotation of the result in uv, in degrees.",
);
const PROJECT_UV_OFFSET: P = P::new(
    "uv_offset",
    "UV offset",
    T::Vec2,
    D::Vec2([0.0, 0.0]),
    "Offset of the result in uv.",
);

static UV_PROJECT: NodeSpec = NodeSpec::new(
    "uv_project",
    "UV Project",
    "uv",
    "Writes texture coordinates by projection (Houdini's UV Project): planar, cylindrical, spherical or box through a frame fitted to the geometry or placed by hand; polygons across a cylindrical or spherical seam stay continuous. Then scaled, rotated and offset in uv.",
    &[geometry_input("geometry")],
    &[
        PROJECT_GROUP,
        NAME,
        PROJECT_TYPE,
        PROJECT_AXIS,
        PROJECT_FIT,
        PROJECT_CENTER,
        PROJECT_SIZE,
        PROJECT_ROTATE,
        PROJECT_UV_SCALE,
        PROJECT_UV_ROTATE,
        PROJECT_UV_OFFSET,
    ],
);

fn cook_project(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let name = p.string(&NAME)?;
    attribute_name(ctx, &NAME, name)?;
    let axis = match p.string(&PROJECT_AXIS)? {
        "x" => Axis::X,
        "z" => Axis::Z,
        _ => Axis::Y,
    };
    let projection = match p.string(&PROJECT_TYPE)? {
        "cylindrical" => Projection::Cylindrical { axis },
        "spherical" => Projection::Spherical { axis },
        "box" => Projection::Box,
        _ => Projection::Planar { axis },
    };
    let (center, size) = if p.toggle(&PROJECT_FIT)? {
        let b = ops::bounds(&g);
        match b {
            Some(b) => (b.center(), (b.max - b.min).max(Vec3::splat(1e-6))),
            None => (Vec3::ZERO, Vec3::ONE),
        }
    } else {
        (vec3(p, &PROJECT_CENTER)?, vec3(p, &PROJECT_SIZE)?)
    };
    if size.cmpeq(Vec3::ZERO).any() || !size.is_finite() {
        return Err(ctx.param_error(
            &PROJECT_SIZE,
            format!("the frame's size must be finite and not zero, not {size}"),
        ));
    }
    let options = ProjectOptions {
        projection,
        frame: frame_from_trs(center, vec3(p, &PROJECT_ROTATE)?, size),
        transform: UvTransform {
            scale: vec2(p, &PROJECT_UV_SCALE)?,
            rotate_degrees: p.float(&PROJECT_UV_ROTATE)? as f32,
            offset: vec2(p, &PROJECT_UV_OFFSET)?,
        },
    };
    let mut uv = project(&g, &options).map_err(|e| uv_error(ctx, &PROJECT_SIZE, e))?;
    if let Some(group) = group_param(ctx, p, &PROJECT_GROUP, &g, AttribClass::Primitive)? {
        let old = existing_uv(&g, name);
        for prim in (0..g.num_prims()).filter(|&i| !group.contains(i)) {
            for v in g.prim_vertex_range(prim) {
                uv[v] = old.as_ref().map_or(Vec3::ZERO, |o| o[v]);
            }
        }
    }
    write_uv(&mut g, name, uv).map_err(|e| uv_error(ctx, &NAME, e))?;
    geometry(g)
}

/// The vertex uv there is now, as three floats per vertex.
fn existing_uv(g: &Geometry, name: &str) -> Option<Vec<Vec3>> {
    match g.attrib(AttribClass::Vertex, name).map(|a| a.data()) {
        Some(AttribData::Vec3(v)) => Some(v.clone()),
        Some(AttribData::Vec2(v)) => Some(v.iter().map(|x| x.extend(0.0)).collect()),
        _ => None,
    }
}

const FLATTEN_SEAMS: P = P::new(
    "seams",
    "Seams",
    T::String,
    D::Str(""),
    "Where to cut, besides the mesh's open edges: edges as Houdini writes them (`p3-4`, or a path `p0-1-2-3`), and point group patterns (`seam`, `@P.x==0`): an edge whose two points are both selected is cut.",
);
const FLATTEN_MARGIN: P = P::new(
    "margin",
    "Margin",
    T::Float,
    D::Float(0.01),
    "The gap around each island in the unit square, as a fraction of its side.",
)
.range(0.0, 0.49);
const FLATTEN_ROTATE: P = P::new(
    "rotate",
    "Rotate islands",
    T::Toggle,
    D::Toggle(true),
    "Turn islands to their tightest rectangles to pack them closer.",
);
const FLATTEN_METHOD: P = P::new(
    "method",
    "Method",
    T::Menu(&["spectral", "two_pins"]),
    D::Str("spectral"),
    "How each island's least-squares conformal map is fixed: `spectral` (Mullen et al.'s spectral conformal map: no pins, the boundary spread evenly; long curved islands stay straight) or `two_pins` (classic LSCM with the two farthest boundary points pinned, as libigl and Blender's Conformal unwrap: can curl a long strip). Islands without a boundary use two pins.",
);
const FLATTEN_ISLAND: P = P::new(
    "island_attribute",
    "Island attribute",
    T::String,
    D::Str("island"),
    "A primitive integer attribute of each polygon's island number; empty for none.",
);

static UV_FLATTEN: NodeSpec = NodeSpec::new(
    "uv_flatten",
    "UV Flatten",
    "uv",
    "Unwraps the mesh into texture space (Houdini's UV Flatten and Layout): islands cut along the seams and the open edges, each flattened by least-squares conformal maps (angles kept, sized to its area) and packed into the unit square with a margin. Each island must be a disc: a closed mesh or a tube needs seams (the node warns of islands that are not discs). The spectral method keeps a long island far from developable (a torus cut into one strip) a band of even texel density, where two pins let it curl.",
    &[geometry_input("geometry")],
    &[FLATTEN_SEAMS, NAME, FLATTEN_METHOD, FLATTEN_MARGIN, FLATTEN_ROTATE, FLATTEN_ISLAND],
);

fn cook_flatten(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let name = p.string(&NAME)?;
    attribute_name(ctx, &NAME, name)?;
    let island = p.string(&FLATTEN_ISLAND)?;
    if !island.is_empty() {
        attribute_name(ctx, &FLATTEN_ISLAND, island)?;
    }
    let seams = seams(ctx, p.string(&FLATTEN_SEAMS)?, &g)?;
    ctx.reserve(
        &NAME,
        g.num_vertices() as f64 * 200.0,
        "the flattening's system",
    )?;
    let options = FlattenOptions {
        pack: PackOptions {
            margin: p.float(&FLATTEN_MARGIN)?,
            rotate: p.toggle(&FLATTEN_ROTATE)?,
        },
        method: match p.string(&FLATTEN_METHOD)? {
            "two_pins" => ConformalMethod::TwoPins,
            _ => ConformalMethod::Spectral,
        },
        ..FlattenOptions::default()
    };
    let flat = flatten(&g, &seams, &options, &ctx.cancel_fn())
        .map_err(|e| uv_error(ctx, &FLATTEN_SEAMS, e))?;
    if flat.unconverged_islands > 0 {
        ctx.warn(format!(
            "{} island(s) did not converge to the solver's tolerance",
            flat.unconverged_islands
        ));
    }
    if flat.margin < options.pack.margin {
        ctx.warn(format!(
            "{} islands did not fit with margin {}: packed with {:.4}",
            flat.island_count, options.pack.margin, flat.margin
        ));
    }
    warn_not_discs(ctx, &g, &flat.uv, &flat.prim_island, flat.island_count)?;
    write_uv(&mut g, name, flat.uv).map_err(|e| uv_error(ctx, &NAME, e))?;
    if !island.is_empty() {
        write_islands(&mut g, island, flat.prim_island)
            .map_err(|e| uv_error(ctx, &FLATTEN_ISLAND, e))?;
    }
    geometry(g)
}

/// Warns of islands that are not discs (Euler characteristic other than
/// 1: closed, or a tube with two rims): a least-squares conformal map
/// flattens a disc; anything else folds or collapses. Counted on the
/// flattened result, where a seam has split its points (corners and edges
/// sorted and deduplicated per island, with the cook's cancel polled).
fn warn_not_discs(
    ctx: &CookContext,
    g: &Geometry,
    uv: &[Vec3],
    island: &[i32],
    count: usize,
) -> Result<(), CookError> {
    use rayon::slice::ParallelSliceMut;
    type Corner = (u32, u32, u32);
    let key = |v: usize| (g.vertex_points()[v], uv[v].x.to_bits(), uv[v].y.to_bits());
    let mut corners: Vec<(u32, Corner)> = Vec::with_capacity(g.num_vertices());
    let mut edges: Vec<(u32, [Corner; 2])> = Vec::with_capacity(g.num_vertices());
    let mut faces = vec![0i64; count];
    for (prim, &own) in island.iter().enumerate().take(g.num_prims()) {
        if prim % 16384 == 0 {
            ctx.check()?;
        }
        let Some(k) = usize::try_from(own).ok().filter(|&k| k < count) else {
            continue;
        };
        faces[k] += 1;
        let r = g.prim_vertex_range(prim);
        let n = r.len();
        for j in 0..n {
            let (a, b) = (key(r.start + j), key(r.start + (j + 1) % n));
            corners.push((k as u32, a));
            edges.push((k as u32, if a < b { [a, b] } else { [b, a] }));
        }
    }
    ctx.check()?;
    corners.par_sort_unstable();
    corners.dedup();
    ctx.check()?;
    edges.par_sort_unstable();
    edges.dedup();
    let mut chi = faces;
    for (k, _) in &corners {
        chi[*k as usize] += 1;
    }
    for (k, _) in &edges {
        chi[*k as usize] -= 1;
    }
    let odd: Vec<String> = (0..count)
        .filter_map(|k| {
            let chi = chi[k];
            (chi != 1).then(|| match chi {
                2 => format!("island {k} is closed"),
                0 => format!("island {k} is a tube or ring"),
                c => format!("island {k} has Euler characteristic {c}"),
            })
        })
        .collect();
    if !odd.is_empty() {
        ctx.warn(format!(
            "{}: only a disc flattens without folding or collapsing; add seams to open it",
            odd.iter().take(4).cloned().collect::<Vec<_>>().join(", ")
        ));
    }
    Ok(())
}

/// The seam edges a seams parameter names: `pA-B[-C...]` paths, and the
/// edges of the mesh whose points a point pattern selects both of.
fn seams(ctx: &CookContext, text: &str, g: &Geometry) -> Result<Vec<[u32; 2]>, CookError> {
    let mut edges = Vec::new();
    let mut rest: Vec<&str> = Vec::new();
    for token in text.split_whitespace() {
        match token
            .strip_prefix('p')
            .filter(|t| t.starts_with(|c: char| c.is_ascii_digit()))
        {
            Some(path) => {
                let pts: Result<Vec<u32>, _> = path.split('-').map(str::parse::<u32>).collect();
                let pts = pts.ok().filter(|p| p.len() >= 2).ok_or_else(|| {
                    ctx.param_error(&FLATTEN_SEAMS, format!("`{token}`: an edge is `p` and two or more point numbers joined by `-` (`p3-4`)"))
                })?;
                if let Some(&bad) = pts.iter().find(|&&q| q as usize >= g.num_points()) {
                    return Err(ctx.param_error(
                        &FLATTEN_SEAMS,
                        format!(
                            "`{token}`: there is no point {bad} ({} points)",
                            g.num_points()
                        ),
                    ));
                }
                let topo = g.topology();
                if let Some(w) = pts
                    .windows(2)
                    .find(|w| topo.find_edge(w[0], w[1]).is_none())
                {
                    return Err(ctx.param_error(
                        &FLATTEN_SEAMS,
                        format!("`{token}`: points {} and {} share no edge", w[0], w[1]),
                    ));
                }
                edges.extend(pts.windows(2).map(|w| [w[0], w[1]]));
            }
            None => rest.push(token),
        }
    }
    if !rest.is_empty() {
        let text = rest.join(" ");
        let selected = GroupPattern::parse(&text)
            .and_then(|pat| pat.group(g, AttribClass::Point))
            .map_err(|e| ctx.param_error(&FLATTEN_SEAMS, format!("`{text}`: {e}")))?;
        let topo = g.topology();
        edges.extend(
            topo.edges()
                .iter()
                .filter(|[a, b]| selected.contains(*a as usize) && selected.contains(*b as usize))
                .copied(),
        );
    }
    Ok(edges)
}

pub fn register(r: &mut Registry) {
    r.node(&UV_PROJECT, cook_project);
    r.node(&UV_FLATTEN, cook_flatten);
}
