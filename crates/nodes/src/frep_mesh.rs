//! Meshes as FRep inputs: any closed (or nearly closed) polygon mesh as its
//! exact signed distance (frep_from_mesh), and the box, sphere, torus and
//! tube nodes (with `analytic` on) as the exact solids they stand for, moved
//! by any `transform` on the way (the seed's use of Houdini's own
//! primitives as guide geometry).

use geode_frep::{shapes, Field, MeshDistance, MeshFieldError};
use geode_geo::{analytic, AttribClass, Geometry};
use geode_op::{
    CookContext, CookError, InputSpec, NodeSpec, ParamDefault as D, ParamSpec as P, ParamType as T,
    Params, PortType, Registry, Value,
};

const FROM_MESH_GROUP: P = P::new(
    "group",
    "Group",
    T::String,
    D::Str(""),
    "The polygons that make the solid (a primitive group pattern); empty for all.",
);

static FROM_MESH: NodeSpec = NodeSpec::new(
    "frep_from_mesh",
    "FRep From Mesh",
    "frep",
    "A polygon mesh as a solid: the exact signed distance to its surface (positive inside), for CSG with other solids, offsets, shells, blends, infill and wall checks. Inside is where the generalized winding number passes one half in magnitude, so a mesh with small holes, gaps or overlapping parts (a typical STL) still has a clear inside, and one wound inside out is the same solid; neighbouring faces must agree on which way they point (a warning names the edges where they do not). An open sheet encloses nothing: its field is the distance to it, so frep_shell with side centered thickens it into a plate. Polygons are triangulated; other primitives are ignored. Exact everywhere, far from the mesh included; cost grows with the log of the triangle count.",
    &[InputSpec {
        name: "mesh",
        ty: PortType::Geometry,
        required: true,
    }],
    &[FROM_MESH_GROUP],
)
.output(PortType::Field);

/// Bytes a mesh field holds per triangle (its corners, hierarchy and
/// winding dipoles, measured from `MeshDistance::memory_bytes`).
const FIELD_BYTES_PER_TRIANGLE: f64 = 160.0;

fn cook_from_mesh(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = crate::util::input(ctx, inputs, 0)?;
    let group = crate::util::group_param(ctx, p, &FROM_MESH_GROUP, g, AttribClass::Primitive)?;
    let (triangles, prim_of) = geode_attrib::relation::surface_triangles(g);
    let triangles: Vec<[u32; 3]> = match &group {
        Some(group) => triangles
            .into_iter()
            .zip(prim_of)
            .filter(|&(_, prim)| group.contains(prim as usize))
            .map(|(t, _)| t)
            .collect(),
        None => triangles,
    };
    ctx.reserve(
        &FROM_MESH_GROUP,
        triangles.len() as f64 * FIELD_BYTES_PER_TRIANGLE,
        "the mesh's distance hierarchy",
    )?;
    warn_of_unclear_inside(ctx, g, &triangles);
    let positions = g.positions().iter().map(|v| v.to_array()).collect();
    let cancel = ctx.cancel_fn();
    match MeshDistance::new(positions, triangles, &cancel) {
        Ok(mesh) => Ok(Value::Field(Field::mesh(mesh))),
        Err(MeshFieldError::Cancelled) => Err(CookError::cancelled(ctx.path)),
        Err(MeshFieldError::Empty) => Err(ctx.input_error(if group.is_some() {
            "the group selects no polygons: a solid needs a closed surface of polygons"
        } else {
            "input 1 has no polygons: a solid needs a closed surface of polygons"
        })),
        Err(e) => Err(ctx.input_error(format!("input 1: {e}"))),
    }
}

/// Warns of what makes an inside unclear: edges that bound one polygon only
/// (the winding number bridges small holes, but a hole wider than the wall
/// around it leaks), edges of three polygons and more, neighbours facing
/// opposite ways, a mesh wound inside out (read as the same solid), and
/// one that encloses no volume at all (an open sheet, a flat patch).
fn warn_of_unclear_inside(ctx: &CookContext, g: &Geometry, triangles: &[[u32; 3]]) {
    let report = g.topology().manifold_report(g);
    if report.boundary_edges > 0 {
        ctx.warn(format!(
            "the mesh is not closed: {} edges bound one polygon only; inside is decided by winding number, so small holes are bridged, but fuse points (or fill holes) for a watertight solid",
            report.boundary_edges
        ));
    }
    if report.non_manifold_edges > 0 {
        ctx.warn(format!(
            "{} edges are shared by more than two polygons; inside is decided by winding number",
            report.non_manifold_edges
        ));
    }
    if report.inconsistent_edges > 0 {
        ctx.warn(format!(
            "{} edges join polygons facing opposite ways: the inside is clear only where the faces around it all point out (or all in); reverse the odd ones",
            report.inconsistent_edges
        ));
    }
    let p = g.positions();
    let corner = |i: u32| p[i as usize].as_dvec3();
    let volume: f64 = triangles
        .iter()
        .map(|t| corner(t[0]).dot(corner(t[1]).cross(corner(t[2]))) / 6.0)
        .sum();
    let extent = geode_geo::ops::bounds(g).map_or(0.0, |b| (b.max - b.min).max_element() as f64);
    if volume.abs() <= 1e-6 * extent.powi(3) {
        ctx.warn(
            "the mesh encloses no volume (an open or flat surface): frep_from_mesh makes solids of closed meshes; for a sheet, thicken it with frep_shell (side centered)",
        );
    } else if volume < 0.0 {
        ctx.warn(
            "the mesh's faces point inward (its volume is negative): it is read as the same solid, but reverse it for tools that trust orientation",
        );
    }
}

static FROM_PRIMITIVES: NodeSpec = NodeSpec::new(
    "frep_from_primitives",
    "FRep From Primitives",
    "frep",
    "The exact solids behind mesh primitives (box, sphere, torus, tube made with `analytic` on, then transformed, merged or partly deleted): their union as a field. Any other polygon is an error naming it.",
    &[InputSpec {
        name: "primitives",
        ty: PortType::Geometry,
        required: true,
    }],
    &[],
)
.output(PortType::Field);

fn cook_from_primitives(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    _: &Params,
) -> Result<Value, CookError> {
    let g = crate::util::input(ctx, inputs, 0)?;
    let found = analytic::shapes(g).map_err(|e| ctx.input_error(format!("input 1: {e}")))?;
    let mut solids = Vec::with_capacity(found.len());
    for (shape, frame) in found {
        let solid = shapes::analytic(&shape)
            .transformed(&frame.as_dmat4())
            .ok_or_else(|| ctx.input_error(format!("a {shape:?} is scaled to nothing")))?;
        solids.push(solid);
    }
    shapes::union_all(solids)
        .map(Value::Field)
        .ok_or_else(|| ctx.input_error("input 1 has no primitives"))
}

pub fn register(r: &mut Registry) {
    r.node(&FROM_MESH, cook_from_mesh);
    r.node(&FROM_PRIMITIVES, cook_from_primitives);
}
