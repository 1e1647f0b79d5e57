//! Attribute nodes: create an attribute with a value; randomize one (seeded, thread-count independent).

use geode_geo::glam::{Vec2, Vec3, Vec4};
use geode_geo::{AttribData, AttribValue, Attribute, TypeInfo};
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{class, count, geometry, input_owned, vec3, CLASSES};

const TYPES: &[&str] = &[
    "float", "int", "vector2", "vector3", "vector4", "color", "normal",
];

fn check_name(ctx: &CookContext, name: &str) -> Result<(), CookError> {
    if name.is_empty()
        || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        || name.starts_with(|c: char| c.is_ascii_digit())
    {
        return Err(ctx.param_error("name", format!("`{name}` is not a valid attribute name (letters, digits and _, not starting with a digit)")));
    }
    Ok(())
}

const CREATE_NAME: P = P::new("name", "Name", T::String, D::Str("attr"), "Attribute name.");
const CREATE_CLASS: P = P::new(
    "class",
    "Class",
    T::Menu(CLASSES),
    D::Str("point"),
    "Element class to store it on.",
);
const CREATE_TYPE: P = P::new(
    "type",
    "Type",
    T::Menu(TYPES),
    D::Str("float"),
    "Storage type; color and normal are vector3 with that type-info.",
);
const CREATE_VALUE: P = P::new(
    "value",
    "Value",
    T::Vec4,
    D::Vec4([0.0; 4]),
    "The value (components beyond the type's size are ignored).",
);

static CREATE: NodeSpec = NodeSpec::new(
    "attribute_create",
    "Attribute Create",
    "attribute",
    "Adds (or overwrites) an attribute with one value on every element of a class.",
    &[geometry_input("geometry")],
    &[CREATE_NAME, CREATE_CLASS, CREATE_TYPE, CREATE_VALUE],
);

fn cook_create(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let name = p.string(&CREATE_NAME)?;
    check_name(ctx, name)?;
    let c = class(p, &CREATE_CLASS)?;
    let v = p.vector::<4>(&CREATE_VALUE)?.map(|x| x as f32);
    let (value, info) = match p.string(&CREATE_TYPE)? {
        "float" => (AttribValue::Float(v[0]), TypeInfo::None),
        "int" => (AttribValue::Int(v[0].round() as i32), TypeInfo::None),
        "vector2" => (AttribValue::Vec2(Vec2::new(v[0], v[1])), TypeInfo::None),
        "vector4" => (AttribValue::Vec4(Vec4::from_array(v)), TypeInfo::None),
        "color" => (
            AttribValue::Vec3(Vec3::new(v[0], v[1], v[2])),
            TypeInfo::Color,
        ),
        "normal" => (
            AttribValue::Vec3(Vec3::new(v[0], v[1], v[2])),
            TypeInfo::Normal,
        ),
        _ => (
            AttribValue::Vec3(Vec3::new(v[0], v[1], v[2])),
            TypeInfo::Vector,
        ),
    };
    let n = count(&g, c);
    g.set_attrib(c, name, Attribute::new(value, info, n))
        .map_err(|e| ctx.kernel_at("name", e))?;
    geometry(g)
}

const RANDOMIZE_NAME: P = P::new("name", "Name", T::String, D::Str("Cd"), "Attribute name.");
const RANDOMIZE_CLASS: P = P::new(
    "class",
    "Class",
    T::Menu(CLASSES),
    D::Str("point"),
    "Element class.",
);
const RANDOMIZE_TYPE: P = P::new(
    "type",
    "Type",
    T::Menu(&["float", "vector3", "color"]),
    D::Str("color"),
    "float uses the first component of min and max.",
);
const RANDOMIZE_MIN: P = P::new(
    "min",
    "Min",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "Lower bound per component.",
);
const RANDOMIZE_MAX: P = P::new(
    "max",
    "Max",
    T::Vec3,
    D::Vec3([1.0; 3]),
    "Upper bound per component.",
);
const RANDOMIZE_SEED: P = P::new("seed", "Seed", T::Int, D::Int(0), "Random seed.");

static RANDOMIZE: NodeSpec = NodeSpec::new(
    "attribute_randomize",
    "Attribute Randomize",
    "attribute",
    "Sets an attribute to uniform random values between min and max, seeded: the same seed gives the same values on any machine and thread count.",
    &[geometry_input("geometry")],
    &[
        RANDOMIZE_NAME,
        RANDOMIZE_CLASS,
        RANDOMIZE_TYPE,
        RANDOMIZE_MIN,
        RANDOMIZE_MAX,
        RANDOMIZE_SEED,
    ],
);

fn cook_randomize(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let name = p.string(&RANDOMIZE_NAME)?;
    check_name(ctx, name)?;
    let c = class(p, &RANDOMIZE_CLASS)?;
    let (lo, hi) = (vec3(p, &RANDOMIZE_MIN)?, vec3(p, &RANDOMIZE_MAX)?);
    let seed = p.int(&RANDOMIZE_SEED)? as u64;
    let n = count(&g, c) as u64;
    let r = |e: u64, k: u64| geode_geo::random::unit(seed, e, k);
    let (data, info) = match p.string(&RANDOMIZE_TYPE)? {
        "float" => (
            AttribData::Float((0..n).map(|e| lo.x + (hi.x - lo.x) * r(e, 0)).collect()),
            TypeInfo::None,
        ),
        ty => (
            AttribData::Vec3(
                (0..n)
                    .map(|e| lo + (hi - lo) * Vec3::new(r(e, 0), r(e, 1), r(e, 2)))
                    .collect(),
            ),
            if ty == "color" {
                TypeInfo::Color
            } else {
                TypeInfo::Vector
            },
        ),
    };
    g.set_attrib(c, name, Attribute::from_data(data, info))
        .map_err(|e| ctx.kernel_at("name", e))?;
    geometry(g)
}

pub fn register(r: &mut Registry) {
    r.node(&CREATE, cook_create);
    r.node(&RANDOMIZE, cook_randomize);
}
