//! The attach node: cylinder hsplines (limbs) joined to rectangular regions
//! of a parent hspline through one Catmull-Clark control mesh, and the
//! convention by which an hspline travels between nodes (a typed payload on
//! its tessellation, with a key of the points it was tessellated to, so a
//! surface moved after its hspline node is an error, never a silent use of
//! the old hierarchy).

use geode_geo::{AttribClass, AttribData, Attribute, GeoError, Geometry, Payload, TypeInfo};
use geode_op::{
    CookContext, CookError, InputSpec, ListSpec, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, ParamValue, Params, PortType, Registry, Value,
};
use geode_spline::hspline::attach::{attach, Attached, Limb, Region};
use geode_spline::hspline::{file, Hspline};

use crate::util::geometry;

/// The payload holding an hspline's hierarchy on its tessellation.
pub const HIERARCHY: &str = "hspline";

/// A hierarchy as it travels: the surface and the hash of the points it was
/// tessellated to.
struct Carried {
    surface: Hspline,
    points_key: u128,
}

fn points_key(g: &Geometry) -> u128 {
    let bytes: Vec<u8> = g
        .positions()
        .iter()
        .flat_map(|p| p.to_array())
        .flat_map(f32::to_le_bytes)
        .collect();
    geode_geo::hash_bytes(&bytes)
}

/// Stores `h` on its tessellation `g` as a typed payload (identity: the
/// hash of its canonical .hs form, so equal hierarchies share cache entries).
pub fn carry_hierarchy(g: &mut Geometry, h: &Hspline) -> Result<(), GeoError> {
    let text = file::save(h, true);
    let identity = geode_geo::hash_bytes(text.as_bytes());
    let carried = Carried {
        surface: h.clone(),
        points_key: points_key(g),
    };
    g.set_payload(HIERARCHY, Payload::new(carried, identity, text.len()));
    Ok(())
}

/// The hierarchy an input carries, checked against its points.
fn hierarchy(ctx: &CookContext, g: &Geometry, input: &str) -> Result<Hspline, CookError> {
    let Some(carried) = g.payload(HIERARCHY).and_then(|p| p.get::<Carried>()) else {
        return Err(ctx.input_error(format!(
            "input `{input}` carries no hspline (wire an hspline node, not enveloped, straight in)"
        )));
    };
    if carried.points_key != points_key(g) {
        return Err(ctx.input_error(format!(
            "input `{input}`: its points changed after its hspline node, so the hierarchy it carries no longer describes it (edit the surface in the hspline node; limbs are placed by `place`)"
        )));
    }
    Ok(carried.surface.clone())
}

/// A region row: the parent's level-0 faces a limb replaces.
const REGION_U: P = P::new(
    "u",
    "Faces along u",
    T::Vec2,
    D::Vec2([2.0, 4.0]),
    "u0 u1: the parent's level-0 faces u0..u1 (half-open).",
)
.at_least(0.0)
.not_animatable();

const REGION_V: P = P::new(
    "v",
    "Faces along v",
    T::Vec2,
    D::Vec2([2.0, 4.0]),
    "v0 v1: the parent's level-0 faces v0..v1 (half-open).",
)
.at_least(0.0)
.not_animatable();

static REGION_ROWS: ListSpec = ListSpec {
    fields: &[REGION_U, REGION_V],
    legacy: Some(legacy_regions),
};

/// Old networks: `u0 u1 v0 v1` entries separated by `;`.
fn legacy_regions(text: &str) -> Result<Vec<Vec<ParamValue>>, String> {
    let form = "`u0 u1 v0 v1` (parent faces, half-open)";
    crate::util::legacy_rows(text, "region", form, |w| {
        let faces: Option<Vec<f64>> = w
            .iter()
            .map(|x| x.parse::<usize>().ok().map(|x| x as f64))
            .collect();
        match faces?[..] {
            [u0, u1, v0, v1] => Some(vec![
                ParamValue::Vector(vec![u0, u1]),
                ParamValue::Vector(vec![v0, v1]),
            ]),
            _ => None,
        }
    })
}

/// The region rows.
fn regions(p: &Params) -> Result<Vec<Region>, CookError> {
    p.list(&ATTACH_REGIONS)?
        .iter()
        .map(|row| {
            let [u0, u1] = row.vector::<2>(&REGION_U)?.map(|x| x as usize);
            let [v0, v1] = row.vector::<2>(&REGION_V)?.map(|x| x as usize);
            Ok(((u0, u1), (v0, v1)))
        })
        .collect()
}

const ATTACH_REGIONS: P = P::list(
    "regions", "Regions", &REGION_ROWS, "One row per limb input: the parent's level-0 faces u0..u1 x v0..v1 (half-open) the limb replaces. The limb needs 2 x ((u1 - u0) + (v1 - v0)) vertices around.");
const ATTACH_PLACE: P = P::new("place", "Place limbs", T::Toggle, D::Toggle(true), "Move each limb rigidly onto its region: rim centre on the hole's centre, axis along the parent's normal, turned to fit the rim (its offsets follow). Off: limbs stay where they are.");
const ATTACH_SUBDIVISIONS: P = P::new(
    "subdivisions",
    "Subdivisions",
    T::Int,
    D::Int(2),
    "Levels of refinement past the finest hspline level, for a smoother tessellation.",
)
.range(0.0, 6.0);
const ATTACH_OUTPUT: P = P::new(
    "output",
    "Output",
    T::Menu(&["surface", "control_mesh"]),
    D::Str("surface"),
    "The limit surface, or the level-0 Catmull-Clark control mesh.",
);

static ATTACH: NodeSpec = NodeSpec::new(
    "attach",
    "Attach Limbs",
    "spline",
    "Arbitrary-topology attachments (Forsey's hsplines): each limb input, a cylinder hspline, replaces a rectangle of the parent hspline's level-0 faces; its rim row is bound to the parent vertices around the hole (corners get five edges, limbs side by side six) and the whole control mesh is one Catmull-Clark surface, refined to the finest level of any input with every level's offsets applied in the local frames, so detail on either side of the joint follows and the joint can be edited from both. Away from the joint the result is each hspline exactly. Output: the limit surface as quads with N, uv per corner and the primitive attribute `surface` (0 the parent, then the limbs), or the level-0 control mesh.",
    &[
        InputSpec { name: "parent", ty: PortType::Geometry, required: true },
        InputSpec { name: "limbs", ty: PortType::Geometry, required: true },
    ],
    &[
        ATTACH_REGIONS,
        ATTACH_PLACE,
        ATTACH_SUBDIVISIONS,
        ATTACH_OUTPUT,
    ],
)
.variadic();

fn cook_attach(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let parent = hierarchy(ctx, crate::util::input(ctx, inputs, 0)?, "parent")?;
    let limb_inputs: Vec<_> = inputs.iter().skip(1).flatten().collect();
    let mut surfaces = Vec::with_capacity(limb_inputs.len());
    for (k, value) in limb_inputs.iter().enumerate() {
        let g = value
            .as_geometry()
            .ok_or_else(|| ctx.input_error(format!("limb {k} needs geometry")))?;
        surfaces.push(hierarchy(ctx, g, &format!("limb {k}"))?);
    }
    let regions = regions(p)?;
    if regions.len() != surfaces.len() {
        return Err(ctx.param_error(
            &ATTACH_REGIONS,
            format!(
                "{} regions for {} limb inputs",
                regions.len(),
                surfaces.len()
            ),
        ));
    }
    let limbs: Vec<Limb> = surfaces
        .into_iter()
        .zip(regions)
        .map(|(surface, region)| Limb { surface, region })
        .collect();
    ctx.check()?;
    let a = attach(
        &parent,
        &limbs,
        p.toggle(&ATTACH_PLACE)?,
        p.int(&ATTACH_SUBDIVISIONS)? as usize,
    )
    .map_err(|e| ctx.kernel_at(&ATTACH_REGIONS, e))?;
    let g = if p.string(&ATTACH_OUTPUT)? == "control_mesh" {
        cage(&a)
    } else {
        surface(&a)
    };
    geometry(g.map_err(|e| ctx.kernel(e))?)
}

fn cage(a: &Attached) -> Result<Geometry, GeoError> {
    let points = a.cage_points.iter().map(|p| p.as_vec3()).collect();
    let flat = a.cage_quads.iter().flatten().copied().collect();
    Geometry::from_polygons(points, flat, &vec![4; a.cage_quads.len()])
}

fn surface(a: &Attached) -> Result<Geometry, GeoError> {
    use geode_geo::glam::Vec2;
    let points = a.positions.iter().map(|p| p.as_vec3()).collect();
    let flat = a.quads.iter().flatten().copied().collect();
    let mut g = Geometry::from_polygons(points, flat, &vec![4; a.quads.len()])?;
    g.set_attrib(
        AttribClass::Point,
        "N",
        Attribute::from_data(
            AttribData::Vec3(a.normals.iter().map(|n| n.as_vec3()).collect()),
            TypeInfo::Normal,
        ),
    )?;
    g.set_attrib(
        AttribClass::Vertex,
        "uv",
        Attribute::from_data(
            AttribData::Vec2(
                a.uvs
                    .iter()
                    .map(|&[u, v]| Vec2::new(u as f32, v as f32))
                    .collect(),
            ),
            TypeInfo::TexCoord,
        ),
    )?;
    g.set_attrib(
        AttribClass::Primitive,
        "surface",
        Attribute::from_data(
            AttribData::Int(a.surface.iter().map(|&s| s as i32).collect()),
            TypeInfo::None,
        ),
    )?;
    Ok(g)
}

pub fn register(r: &mut Registry) {
    r.node(&ATTACH, cook_attach);
}
