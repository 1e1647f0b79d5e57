//! FRep nodes (seed 000): primitives, CSG with alpha, blends, transforms and
//! space mappings, offset, morph and expression (`frep_polygonise` turns
//! fields into geometry). Fields travel on `field` wires.

use geode_frep::shapes;
use geode_frep::{CapsuleSet, Field};
use geode_op::{
    CookContext, CookError, InputSpec, NodeSpec, Operator, ParamDefault as D, ParamName,
    ParamSpec as P, ParamType as T, Params, PortType, Registry, Value,
};

use crate::expr::Expr;

pub(crate) const FIELD_IN: InputSpec = InputSpec {
    name: "field",
    ty: PortType::Field,
    required: true,
};
const TWO_FIELDS: &[InputSpec] = &[
    InputSpec {
        name: "a",
        ty: PortType::Field,
        required: true,
    },
    InputSpec {
        name: "b",
        ty: PortType::Field,
        required: true,
    },
];

pub(crate) fn field_input<'a>(
    ctx: &CookContext,
    inputs: &'a [Option<Value>],
    i: usize,
) -> Result<&'a Field, CookError> {
    inputs
        .get(i)
        .and_then(|v| v.as_ref())
        .and_then(|v| v.as_field())
        .ok_or_else(|| {
            ctx.input_error(format!(
                "input {} needs a field (a mesh cannot be used where a field is expected)",
                i + 1
            ))
        })
}

pub(crate) fn v3(p: &Params, name: &(impl ParamName + ?Sized)) -> Result<[f64; 3], CookError> {
    p.vector::<3>(name)
}

pub(crate) fn out(f: Field) -> Result<Value, CookError> {
    Ok(Value::Field(f))
}

/// A primitive node: no inputs, parameters to a field.
struct Primitive {
    spec: &'static NodeSpec,
    build: fn(&CookContext, &Params) -> Result<Field, CookError>,
}

impl Operator for Primitive {
    fn spec(&self) -> &'static NodeSpec {
        self.spec
    }
    fn cook(&self, ctx: &CookContext, _: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
        out((self.build)(ctx, p)?)
    }
}

const CENTER: P = P::new(
    "center",
    "Center",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "Centre of the solid.",
);

const SPHERE_RADIUS: P =
    P::new("radius", "Radius", T::Float, D::Float(1.0), "Radius.").at_least(0.0);

static SPHERE: NodeSpec = NodeSpec::new(
    "frep_sphere",
    "FRep Sphere",
    "frep",
    "A ball: its field is the signed distance to the sphere (positive inside).",
    &[],
    &[CENTER, SPHERE_RADIUS],
)
.output(PortType::Field);
const BLOCK_SIZE: P =
    P::new("size", "Size", T::Vec3, D::Vec3([1.0; 3]), "Edge lengths.").at_least(0.0);

static BLOCK: NodeSpec = NodeSpec::new(
    "frep_box",
    "FRep Box",
    "frep",
    "An axis-aligned box (block); exact signed distance, so its edges and corners are sharp.",
    &[],
    &[CENTER, BLOCK_SIZE],
)
.output(PortType::Field);
const TORUS_MAJOR_RADIUS: P = P::new(
    "major_radius",
    "Major radius",
    T::Float,
    D::Float(1.0),
    "Ring radius.",
)
.at_least(0.0);

static TORUS: NodeSpec = NodeSpec::new(
    "frep_torus",
    "FRep Torus",
    "frep",
    "A torus around the Y axis.",
    &[],
    &[
        CENTER,
        TORUS_MAJOR_RADIUS,
        crate::primitives::TORUS_MINOR_RADIUS,
    ],
)
.output(PortType::Field);
const CYLINDER_RADIUS: P =
    P::new("radius", "Radius", T::Float, D::Float(0.5), "Radius.").at_least(0.0);
const CYLINDER_HEIGHT: P = P::new(
    "height",
    "Height",
    T::Float,
    D::Float(1.0),
    "Length along Y.",
)
.at_least(0.0);

static CYLINDER: NodeSpec = NodeSpec::new(
    "frep_cylinder",
    "FRep Cylinder",
    "frep",
    "A capped cylinder along Y.",
    &[],
    &[CENTER, CYLINDER_RADIUS, CYLINDER_HEIGHT],
)
.output(PortType::Field);
const CONE_APEX: P = P::new(
    "apex",
    "Apex",
    T::Vec3,
    D::Vec3([0.0, 1.0, 0.0]),
    "Tip of the cone.",
);
const CONE_RADIUS: P = P::new(
    "radius",
    "Base radius",
    T::Float,
    D::Float(0.5),
    "Radius at the base.",
)
.at_least(0.0);
const CONE_HEIGHT: P =
    P::new("height", "Height", T::Float, D::Float(1.0), "Apex to base.").at_least(1e-9);

static CONE: NodeSpec = NodeSpec::new(
    "frep_cone",
    "FRep Cone",
    "frep",
    "A cone along Y with its apex at the top, capped at its base.",
    &[],
    &[CONE_APEX, CONE_RADIUS, CONE_HEIGHT],
)
.output(PortType::Field);
const ELLIPSOID_RADII: P = P::new(
    "radii",
    "Radii",
    T::Vec3,
    D::Vec3([1.0, 0.5, 0.5]),
    "Semi-axes.",
)
.at_least(1e-9);

static ELLIPSOID: NodeSpec = NodeSpec::new(
    "frep_ellipsoid",
    "FRep Ellipsoid",
    "frep",
    "An ellipsoid with the given semi-axes.",
    &[],
    &[CENTER, ELLIPSOID_RADII],
)
.output(PortType::Field);
const SUPERELLIPSOID_RADII: P =
    P::new("radii", "Radii", T::Vec3, D::Vec3([1.0; 3]), "Semi-axes.").at_least(1e-9);
const SUPERELLIPSOID_E1: P = P::new(
    "e1",
    "North-south exponent",
    T::Float,
    D::Float(0.5),
    "Shape along Y.",
)
.range(0.01, 10.0);
const SUPERELLIPSOID_E2: P = P::new(
    "e2",
    "East-west exponent",
    T::Float,
    D::Float(0.5),
    "Shape around Y.",
)
.range(0.01, 10.0);

static SUPERELLIPSOID: NodeSpec = NodeSpec::new(
    "frep_superellipsoid",
    "FRep Superellipsoid",
    "frep",
    "Barr's superellipsoid: exponents of 1 give an ellipsoid, smaller ones a rounded box, larger ones a pinched star.",
    &[],
    &[
        CENTER,
        SUPERELLIPSOID_RADII,
        SUPERELLIPSOID_E1,
        SUPERELLIPSOID_E2,
    ],
)
.output(PortType::Field);
const HALFSPACE_NORMAL: P = P::new(
    "normal",
    "Normal",
    T::Vec3,
    D::Vec3([0.0, 1.0, 0.0]),
    "Plane normal (normalised here).",
);
const HALFSPACE_DISTANCE: P = P::new(
    "distance",
    "Distance",
    T::Float,
    D::Float(0.0),
    "Offset of the plane along the normal.",
);

static HALFSPACE: NodeSpec = NodeSpec::new(
    "frep_halfspace",
    "FRep Half-space",
    "frep",
    "Everything behind a plane: inside where normal . p <= distance.",
    &[],
    &[HALFSPACE_NORMAL, HALFSPACE_DISTANCE],
)
.output(PortType::Field);

fn sphere(_: &CookContext, p: &Params) -> Result<Field, CookError> {
    Ok(shapes::sphere(v3(p, &CENTER)?, p.float(&SPHERE_RADIUS)?))
}
fn block(_: &CookContext, p: &Params) -> Result<Field, CookError> {
    let s = v3(p, &BLOCK_SIZE)?;
    Ok(shapes::block(v3(p, &CENTER)?, s.map(|x| x * 0.5)))
}
fn torus(_: &CookContext, p: &Params) -> Result<Field, CookError> {
    Ok(shapes::torus(
        v3(p, &CENTER)?,
        p.float(&TORUS_MAJOR_RADIUS)?,
        p.float(&crate::primitives::TORUS_MINOR_RADIUS)?,
    ))
}
fn cylinder(_: &CookContext, p: &Params) -> Result<Field, CookError> {
    Ok(shapes::cylinder(
        v3(p, &CENTER)?,
        p.float(&CYLINDER_RADIUS)?,
        0.5 * p.float(&CYLINDER_HEIGHT)?,
    ))
}
fn cone(_: &CookContext, p: &Params) -> Result<Field, CookError> {
    Ok(shapes::cone(
        v3(p, &CONE_APEX)?,
        p.float(&CONE_RADIUS)?,
        p.float(&CONE_HEIGHT)?,
    ))
}
fn ellipsoid(_: &CookContext, p: &Params) -> Result<Field, CookError> {
    Ok(shapes::ellipsoid(v3(p, &CENTER)?, v3(p, &ELLIPSOID_RADII)?))
}
fn superellipsoid(_: &CookContext, p: &Params) -> Result<Field, CookError> {
    Ok(shapes::superellipsoid(
        v3(p, &CENTER)?,
        v3(p, &SUPERELLIPSOID_RADII)?,
        p.float(&SUPERELLIPSOID_E1)?,
        p.float(&SUPERELLIPSOID_E2)?,
    ))
}
fn halfspace(ctx: &CookContext, p: &Params) -> Result<Field, CookError> {
    let n = v3(p, &HALFSPACE_NORMAL)?;
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len == 0.0 {
        return Err(ctx.param_error(&HALFSPACE_NORMAL, "the normal must not be zero"));
    }
    Ok(shapes::half_space(
        n.map(|x| x / len),
        p.float(&HALFSPACE_DISTANCE)?,
    ))
}

const OPS: &[&str] = &["union", "intersection", "subtraction"];

const OPERATION: P = P::new(
    "operation",
    "Operation",
    T::Menu(OPS),
    D::Str("union"),
    "The set operation.",
);
const CSG_ALPHA: P = P::new(
    "alpha",
    "Alpha",
    T::Float,
    D::Float(1.0),
    "R-function parameter in [0, 1].",
)
.range(0.0, 1.0);

static CSG: NodeSpec = NodeSpec::new(
    "frep_csg",
    "FRep CSG",
    "frep",
    "Union, intersection or subtraction (a minus b) by R-functions. Alpha 1 is exactly max/min (sharp); smaller alphas smooth the result.",
    TWO_FIELDS,
    &[
        OPERATION,
        CSG_ALPHA,
    ],
)
.output(PortType::Field);

fn cook_csg(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let (a, b) = (field_input(ctx, inputs, 0)?, field_input(ctx, inputs, 1)?);
    let alpha = p.float(&CSG_ALPHA)?;
    out(match p.string(&OPERATION)? {
        "union" => shapes::union(a, b, alpha),
        "intersection" => shapes::intersection(a, b, alpha),
        _ => shapes::subtraction(a, b, alpha),
    })
}

const A0: P = P::new("a0", "a0", T::Float, D::Float(1.0), "Blend amount.");
const A1: P = P::new("a1", "a1", T::Float, D::Float(1.0), "Reach along a.").at_least(1e-9);
const A2: P = P::new("a2", "a2", T::Float, D::Float(1.0), "Reach along b.").at_least(1e-9);

static BLEND: NodeSpec = NodeSpec::new(
    "frep_blend",
    "FRep Blend",
    "frep",
    "Blended union, intersection or subtraction (Pasko's displacement a0 / (1 + (f1/a1)^2 + (f2/a2)^2)): a0 is how much material the blend adds, a1 and a2 how far it reaches along each solid.",
    TWO_FIELDS,
    &[
        OPERATION,
        A0,
        A1,
        A2,
    ],
)
.output(PortType::Field);

fn cook_blend(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let (a, b) = (field_input(ctx, inputs, 0)?, field_input(ctx, inputs, 1)?);
    let k = [p.float(&A0)?, p.float(&A1)?, p.float(&A2)?];
    out(match p.string(&OPERATION)? {
        "union" => shapes::blend_union(a, b, k),
        "intersection" => shapes::blend_intersection(a, b, k),
        _ => shapes::blend_subtraction(a, b, k),
    })
}

const BOUNDED_BLEND_OPERATION: P = P::new(
    "operation",
    "Operation",
    T::Menu(&["union", "intersection"]),
    D::Str("union"),
    "The set operation.",
);
const BOUNDED_BLEND_A3: P = P::new(
    "a3",
    "a3",
    T::Float,
    D::Float(1.0),
    "How fast the blend fades towards the bounding solid's surface.",
)
.at_least(1e-9);

static BOUNDED_BLEND: NodeSpec = NodeSpec::new(
    "frep_bounded_blend",
    "FRep Bounded Blend",
    "frep",
    "A blended union or intersection of a and b whose blend exists only inside the bounding solid (third input): local control of where the blend happens (Pasko, Pasko and Kunii 2005).",
    &[
        InputSpec { name: "a", ty: PortType::Field, required: true },
        InputSpec { name: "b", ty: PortType::Field, required: true },
        InputSpec { name: "bound", ty: PortType::Field, required: true },
    ],
    &[
        BOUNDED_BLEND_OPERATION,
        A0,
        A1,
        A2,
        BOUNDED_BLEND_A3,
    ],
)
.output(PortType::Field);

fn cook_bounded_blend(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let (a, b, c) = (
        field_input(ctx, inputs, 0)?,
        field_input(ctx, inputs, 1)?,
        field_input(ctx, inputs, 2)?,
    );
    let k = [
        p.float(&A0)?,
        p.float(&A1)?,
        p.float(&A2)?,
        p.float(&BOUNDED_BLEND_A3)?,
    ];
    out(shapes::bounded_blend(
        a,
        b,
        c,
        k,
        p.string(&BOUNDED_BLEND_OPERATION)? == "union",
    ))
}

const SWEEP_RADIUS: P = P::new(
    "radius",
    "Radius",
    T::Float,
    D::Float(0.1),
    "Radius where the points have no radius attribute.",
)
.at_least(0.0);
const SWEEP_RADIUS_ATTRIBUTE: P = P::new(
    "radius_attribute",
    "Radius attribute",
    T::String,
    D::Str("pscale"),
    "Float (or int) point attribute giving the radius per point (if present).",
);

static SWEEP: NodeSpec = NodeSpec::new(
    "frep_sweep",
    "FRep Sphere Sweep",
    "frep",
    "A sphere swept along every polyline of the input: the union of capsules, the radius from a point attribute (pscale by default) or the radius parameter.",
    &[InputSpec { name: "curves", ty: PortType::Geometry, required: true }],
    &[
        SWEEP_RADIUS,
        SWEEP_RADIUS_ATTRIBUTE,
    ],
)
.output(PortType::Field)
// 2: an int radius attribute.
.version(2);

fn cook_sweep(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let g = crate::util::input(ctx, inputs, 0)?;
    let attr = geode_geo::ops::point_scalar(g, p.string(&SWEEP_RADIUS_ATTRIBUTE)?)
        .map_err(|e| ctx.kernel_at(&SWEEP_RADIUS_ATTRIBUTE, e))?;
    let r = p.float(&SWEEP_RADIUS)?;
    let pos = g.positions();
    let mut segments = Vec::new();
    for prim in 0..g.num_prims() {
        if g.prim_kind(prim) != geode_geo::PrimKind::Polyline {
            continue;
        }
        ctx.check()?;
        let pts = g.prim_points(prim);
        let points: Vec<[f64; 3]> = pts
            .iter()
            .map(|&i| pos[i as usize].as_dvec3().to_array())
            .collect();
        let radii: Vec<f64> = pts
            .iter()
            .map(|&i| attr.map_or(r, |a| a.get(i as usize) as f64))
            .collect();
        segments.extend(CapsuleSet::polyline_segments(&points, &radii));
    }
    // One set for every polyline: its hierarchy spans the whole skeleton.
    CapsuleSet::new(&segments)
        .map(|set| Value::Field(Field::capsules(set)))
        .ok_or_else(|| ctx.input_error("the input has no polylines to sweep along"))
}

static INSTANCE: NodeSpec = NodeSpec::new(
    "frep_instance",
    "FRep Instancer",
    "frep",
    "Copies a field onto every point of the input, placed by the same instance attributes as copy-to-points (P, orient, N and up, rot, pscale, scale, trans, pivot); the copies are united.",
    &[FIELD_IN, InputSpec { name: "points", ty: PortType::Geometry, required: true }],
    &[],
)
.output(PortType::Field)
// 2: instance attributes as copy_to_points reads them (its version 2).
.version(2);

fn cook_instance(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    _: &Params,
) -> Result<Value, CookError> {
    let f = field_input(ctx, inputs, 0)?;
    let g = crate::util::input(ctx, inputs, 1)?;
    let mut copies = Vec::new();
    let transforms = geode_geo::ops::instance_transforms(g).map_err(|e| ctx.kernel(e))?;
    for m in transforms {
        ctx.check()?;
        copies.push(
            f.transformed(&m.as_dmat4())
                .ok_or_else(|| ctx.input_error("an instance has a zero scale"))?,
        );
    }
    shapes::union_all(copies)
        .map(Value::Field)
        .ok_or_else(|| ctx.input_error("the input has no points to instance onto"))
}

const TRANSFORM_ROTATE: P = P::new(
    "rotate",
    "Rotate",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "Degrees about X, Y, Z.",
);
const TRANSFORM_SCALE: P = P::new(
    "scale",
    "Scale",
    T::Vec3,
    D::Vec3([1.0; 3]),
    "Per-axis scale (non-uniform scaling distorts distances).",
);
const TRANSFORM_PIVOT: P = P::new(
    "pivot",
    "Pivot",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "The fixed point of rotation and scale.",
);

static TRANSFORM: NodeSpec = NodeSpec::new(
    "frep_transform",
    "FRep Transform",
    "frep",
    "Moves, rotates (degrees, X then Y then Z) and scales a field about a pivot, as the transform node does meshes.",
    &[FIELD_IN],
    &[
        crate::transform::TRANSFORM_TRANSLATE,
        TRANSFORM_ROTATE,
        TRANSFORM_SCALE,
        TRANSFORM_PIVOT,
    ],
)
.output(PortType::Field);

fn cook_transform(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let f = field_input(ctx, inputs, 0)?;
    let s = v3(p, &TRANSFORM_SCALE)?;
    if s.iter().any(|x| x.abs() < 1e-12) {
        return Err(ctx.param_error(&TRANSFORM_SCALE, "a zero scale collapses the solid"));
    }
    let m = crate::transform::trs_about_pivot(
        v3(p, &crate::transform::TRANSFORM_TRANSLATE)?,
        v3(p, &TRANSFORM_ROTATE)?,
        s,
        v3(p, &TRANSFORM_PIVOT)?,
    );
    f.transformed(&m)
        .map(Value::Field)
        .ok_or_else(|| ctx.param_error(&TRANSFORM_SCALE, "the transform is not invertible"))
}

const DEFORM_MODE: P = P::new(
    "mode",
    "Mode",
    T::Menu(&["taper", "twist", "bend", "point"]),
    D::Str("twist"),
    "Which deformation.",
);
const DEFORM_TAPER_RANGE: P = P::new(
    "taper_range",
    "Taper from/to height",
    T::Vec2,
    D::Vec2([-1.0, 1.0]),
    "Y where the scale is start and end.",
);
const DEFORM_TAPER_SCALE: P = P::new(
    "taper_scale",
    "Taper start/end scale",
    T::Vec2,
    D::Vec2([1.0, 0.5]),
    "Scale at each height.",
)
.at_least(1e-6);
const DEFORM_TWIST: P = P::new(
    "twist",
    "Twist rate",
    T::Float,
    D::Float(1.0),
    "Radians per unit of Y.",
);
const DEFORM_BEND_RADIUS: P = P::new(
    "bend_radius",
    "Bend radius",
    T::Float,
    D::Float(2.0),
    "Radius of the arc the X axis follows.",
)
.at_least(1e-6);
const DEFORM_POINT: P = P::new(
    "point",
    "Deform point",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "Centre of the point deformation.",
);
const DEFORM_OFFSET: P = P::new(
    "offset",
    "Deform offset",
    T::Vec3,
    D::Vec3([0.0, 0.3, 0.0]),
    "How far space at the centre moves.",
);
const DEFORM_FALLOFF: P = P::new(
    "falloff",
    "Deform radius",
    T::Float,
    D::Float(0.5),
    "Distance at which the deformation fades out.",
)
.at_least(1e-6);

static DEFORM: NodeSpec = NodeSpec::new(
    "frep_deform",
    "FRep Deform",
    "frep",
    "Space mappings of seed 000: taper (scale X and Z along Y between two heights), twist (about Y, radians per unit), bend (X around an arc of the given radius), point (push space near a point by an offset with a smooth falloff).",
    &[FIELD_IN],
    &[
        DEFORM_MODE,
        DEFORM_TAPER_RANGE,
        DEFORM_TAPER_SCALE,
        DEFORM_TWIST,
        DEFORM_BEND_RADIUS,
        DEFORM_POINT,
        DEFORM_OFFSET,
        DEFORM_FALLOFF,
    ],
)
.output(PortType::Field);

fn cook_deform(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let f = field_input(ctx, inputs, 0)?;
    out(match p.string(&DEFORM_MODE)? {
        "taper" => {
            let [y0, y1] = p.vector::<2>(&DEFORM_TAPER_RANGE)?;
            let [s0, s1] = p.vector::<2>(&DEFORM_TAPER_SCALE)?;
            if y0 == y1 {
                return Err(ctx.param_error(&DEFORM_TAPER_RANGE, "the two heights must differ"));
            }
            f.taper_y(y0, y1, s0, s1)
        }
        "twist" => f.twist_y(p.float(&DEFORM_TWIST)?),
        "point" => f.deform_point(
            v3(p, &DEFORM_POINT)?,
            v3(p, &DEFORM_OFFSET)?,
            p.float(&DEFORM_FALLOFF)?,
        ),
        _ => f.bend_x(p.float(&DEFORM_BEND_RADIUS)?),
    })
}

const MORPH_ALPHA: P =
    P::new("alpha", "Alpha", T::Float, D::Float(0.5), "Blend factor.").range(0.0, 1.0);

static MORPH: NodeSpec = NodeSpec::new(
    "frep_morph",
    "FRep Metamorphosis",
    "frep",
    "Interpolates two solids of any topology: alpha 0 gives a, 1 gives b.",
    TWO_FIELDS,
    &[MORPH_ALPHA],
)
.output(PortType::Field);

fn cook_morph(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    out(shapes::morph(
        field_input(ctx, inputs, 0)?,
        field_input(ctx, inputs, 1)?,
        p.float(&MORPH_ALPHA)?,
    ))
}

const EXPRESSION_EXPRESSION: P = P::new(
    "expression",
    "Expression",
    T::String,
    D::Str("1 - (x*x + y*y + z*z)"),
    "The formula.",
);
const EXPRESSION_A: P = P::new("a", "a", T::Float, D::Float(1.0), "Parameter a.");
const EXPRESSION_B: P = P::new("b", "b", T::Float, D::Float(0.0), "Parameter b.");
const EXPRESSION_C: P = P::new("c", "c", T::Float, D::Float(0.0), "Parameter c.");

static EXPRESSION: NodeSpec = NodeSpec::new(
    "frep_expression",
    "FRep Expression",
    "frep",
    "A field written as a formula over x, y, z and the parameters a, b, c (>= 0 inside), e.g. `a - (x^2 + y^2 + z^2)`. Same language as group_expression.",
    &[],
    &[
        EXPRESSION_EXPRESSION,
        EXPRESSION_A,
        EXPRESSION_B,
        EXPRESSION_C,
    ],
)
.output(PortType::Field);

fn cook_expression(ctx: &CookContext, _: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let e = Expr::parse(
        p.string(&EXPRESSION_EXPRESSION)?,
        &["x", "y", "z", "a", "b", "c"],
    )
    .map_err(|e| {
        ctx.param_error(&EXPRESSION_EXPRESSION, e.to_string())
            .at_position(1, e.column as u32)
    })?;
    let vars = [
        Field::x(),
        Field::y(),
        Field::z(),
        Field::constant(p.float(&EXPRESSION_A)?),
        Field::constant(p.float(&EXPRESSION_B)?),
        Field::constant(p.float(&EXPRESSION_C)?),
    ];
    out(e.to_field(&vars))
}

pub fn register(r: &mut Registry) {
    for (spec, build) in [
        (
            &SPHERE,
            sphere as fn(&CookContext, &Params) -> Result<Field, CookError>,
        ),
        (&BLOCK, block),
        (&TORUS, torus),
        (&CYLINDER, cylinder),
        (&CONE, cone),
        (&ELLIPSOID, ellipsoid),
        (&SUPERELLIPSOID, superellipsoid),
        (&HALFSPACE, halfspace),
    ] {
        r.add(Primitive { spec, build });
    }
    r.node(&CSG, cook_csg);
    r.node(&BLEND, cook_blend);
    r.node(&BOUNDED_BLEND, cook_bounded_blend);
    r.node(&SWEEP, cook_sweep);
    r.node(&INSTANCE, cook_instance);
    r.node(&TRANSFORM, cook_transform);
    r.node(&DEFORM, cook_deform);
    r.node(&MORPH, cook_morph);
    r.node(&EXPRESSION, cook_expression);
}
