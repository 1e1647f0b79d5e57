//! Attribute nodes: create an attribute with a value; randomize one (seeded,
//! thread-count independent); remap one's range through a ramp.

use geode_geo::glam::{Vec2, Vec3, Vec4};
use geode_geo::{AttribData, AttribValue, Attribute, Ramp, RampKind, TypeInfo};
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value, DEFAULT_FLOAT_RAMP,
};
use rayon::prelude::*;

use crate::util::{class, count, geometry, input_owned, vec3, CLASSES};

const TYPES: &[&str] = &[
    "float", "int", "vector2", "vector3", "vector4", "color", "normal",
];

fn check_name(ctx: &CookContext, param: &P, name: &str) -> Result<(), CookError> {
    crate::util::attribute_name(ctx, param, name)
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
    check_name(ctx, &CREATE_NAME, name)?;
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
        .map_err(|e| ctx.kernel_at(&CREATE_NAME, e))?;
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
    check_name(ctx, &RANDOMIZE_NAME, name)?;
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
        .map_err(|e| ctx.kernel_at(&RANDOMIZE_NAME, e))?;
    geometry(g)
}

const REMAP_NAME: P = P::new(
    "name",
    "Original Name",
    T::String,
    D::Str("Cd"),
    "The float or vector attribute to remap (each component on its own).",
);
const REMAP_CLASS: P = P::new(
    "class",
    "Class",
    T::Menu(CLASSES),
    D::Str("point"),
    "Element class of the attribute.",
);
const REMAP_NEW_NAME: P = P::new(
    "new_name",
    "New Name",
    T::String,
    D::Str(""),
    "Write the result to this attribute and leave the original as it was; empty: replace the original.",
);
const REMAP_INPUT_MIN: P = P::new(
    "input_min",
    "Input Min",
    T::Float,
    D::Float(0.0),
    "The value that maps to the ramp's start (position 0).",
);
const REMAP_INPUT_MAX: P = P::new(
    "input_max",
    "Input Max",
    T::Float,
    D::Float(1.0),
    "The value that maps to the ramp's end (position 1); must differ from Input Min.",
);
const REMAP_OUTPUT_MIN: P = P::new(
    "output_min",
    "Output Min",
    T::Float,
    D::Float(0.0),
    "What a ramp value of 0 becomes.",
);
const REMAP_OUTPUT_MAX: P = P::new(
    "output_max",
    "Output Max",
    T::Float,
    D::Float(1.0),
    "What a ramp value of 1 becomes.",
);
const REMAP_OUT_OF_RANGE: P = P::new(
    "out_of_range",
    "Out of Range Values",
    T::Menu(&["clamp", "cycle", "extrapolate"]),
    D::Str("clamp"),
    "Values outside the input range: clamp to the ramp's end values, cycle (the ramp repeats forward and backward), or extrapolate the output range linearly, ignoring the ramp.",
);
const REMAP_RAMP: P = P::ramp(
    "ramp",
    "Remap",
    RampKind::Float,
    DEFAULT_FLOAT_RAMP,
    "The mapping from the input range (0 to 1 along the ramp) to the output range (ramp values 0 to 1); the default is the straight line.",
);

static REMAP: NodeSpec = NodeSpec::new(
    "attribute_remap",
    "Attribute Remap",
    "attribute",
    "Remaps a float or vector attribute (Houdini's Attribute Remap): each value is fitted from the input range to 0..1, looked up in the ramp and fitted from 0..1 to the output range.",
    &[geometry_input("geometry")],
    &[
        REMAP_NAME,
        REMAP_CLASS,
        REMAP_NEW_NAME,
        REMAP_INPUT_MIN,
        REMAP_INPUT_MAX,
        REMAP_OUTPUT_MIN,
        REMAP_OUTPUT_MAX,
        REMAP_OUT_OF_RANGE,
        REMAP_RAMP,
    ],
);

/// What a value outside the input range becomes.
#[derive(Clone, Copy, PartialEq)]
enum OutOfRange {
    Clamp,
    Cycle,
    Extrapolate,
}

/// Houdini's Attribute Remap of one value: fitted to 0..1 by the input
/// range, through the ramp, fitted to the output range.
fn remap_value(
    v: f64,
    input: (f64, f64),
    output: (f64, f64),
    ramp: &Ramp,
    mode: OutOfRange,
) -> f64 {
    let t = (v - input.0) / (input.1 - input.0);
    let r = match mode {
        OutOfRange::Clamp => ramp.eval_float(t.clamp(0.0, 1.0)),
        OutOfRange::Cycle => ramp.eval_float(t - t.floor()),
        OutOfRange::Extrapolate if !(0.0..=1.0).contains(&t) => t,
        OutOfRange::Extrapolate => ramp.eval_float(t),
    };
    output.0 + r * (output.1 - output.0)
}

fn cook_remap(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let name = p.string(&REMAP_NAME)?;
    let c = class(p, &REMAP_CLASS)?;
    let new_name = match p.string(&REMAP_NEW_NAME)? {
        "" => name,
        n => {
            check_name(ctx, &REMAP_NAME, n).map_err(|_| {
                ctx.param_error(&REMAP_NEW_NAME,
                    format!("`{n}` is not a valid attribute name (letters, digits and _, not starting with a digit)"),
                )
            })?;
            n
        }
    };
    let input = (p.float(&REMAP_INPUT_MIN)?, p.float(&REMAP_INPUT_MAX)?);
    if input.0 == input.1 {
        return Err(ctx.param_error(
            &REMAP_INPUT_MAX,
            format!("the input range is empty: min and max are both {}", input.0),
        ));
    }
    let output = (p.float(&REMAP_OUTPUT_MIN)?, p.float(&REMAP_OUTPUT_MAX)?);
    let mode = match p.string(&REMAP_OUT_OF_RANGE)? {
        "cycle" => OutOfRange::Cycle,
        "extrapolate" => OutOfRange::Extrapolate,
        _ => OutOfRange::Clamp,
    };
    let ramp = p.ramp(&REMAP_RAMP)?;
    let Some(source) = g.attrib(c, name) else {
        let known: Vec<&str> = g.attribs(c).names().collect();
        return Err(ctx.param_error(
            &REMAP_NAME,
            format!(
                "no {} attribute `{name}` (there are: {})",
                p.string(&REMAP_CLASS)?,
                if known.is_empty() {
                    "none".to_owned()
                } else {
                    known.join(", ")
                }
            ),
        ));
    };
    if !matches!(
        source.data(),
        AttribData::Float(_) | AttribData::Vec2(_) | AttribData::Vec3(_) | AttribData::Vec4(_)
    ) {
        return Err(ctx.param_error(
            &REMAP_NAME,
            format!(
                "`{name}` is a {} attribute; remap takes float and vector attributes",
                source.attrib_type()
            ),
        ));
    }
    let mut out = source.clone();
    let (values, _) = out.floats_mut().expect("float columns are floats");
    // Chunks polled for cancellation; each value on its own, so the result
    // does not depend on the thread count.
    values.par_chunks_mut(1 << 16).try_for_each(|chunk| {
        ctx.check()?;
        for v in chunk {
            *v = remap_value(f64::from(*v), input, output, ramp, mode) as f32;
        }
        Ok(())
    })?;
    g.set_attrib(c, new_name, out)
        .map_err(|e| ctx.kernel_at(&REMAP_NAME, e))?;
    geometry(g)
}

pub fn register(r: &mut Registry) {
    r.node(&CREATE, cook_create);
    r.node(&RANDOMIZE, cook_randomize);
    r.node(&REMAP, cook_remap);
}

#[cfg(test)]
mod tests {
    use geode_geo::{RampBasis, RampKey};

    use super::*;

    fn ramp(keys: &[(f64, f64, RampBasis)]) -> Ramp {
        Ramp::new(
            RampKind::Float,
            keys.iter()
                .map(|&(p, v, b)| RampKey::float(p, v, b))
                .collect(),
        )
        .unwrap()
    }

    #[test]
    fn remap_fits_through_the_ramp_and_treats_out_of_range_values() {
        let line = ramp(&[(0.0, 0.0, RampBasis::Linear), (1.0, 1.0, RampBasis::Linear)]);
        // 15 in 10..20 is halfway: 0.5 on the line, so 150 in 100..200.
        let f = |v, m| remap_value(v, (10.0, 20.0), (100.0, 200.0), &line, m);
        assert_eq!(f(15.0, OutOfRange::Clamp), 150.0);
        assert_eq!(f(25.0, OutOfRange::Clamp), 200.0);
        assert_eq!(f(5.0, OutOfRange::Clamp), 100.0);
        // 25 is 1.5 ranges in: cycling gives 0.5's value, extrapolating 1.5's.
        assert_eq!(f(25.0, OutOfRange::Cycle), 150.0);
        assert_eq!(f(25.0, OutOfRange::Extrapolate), 250.0);
        assert_eq!(f(0.0, OutOfRange::Extrapolate), 0.0);
        // A reversed input range reverses the mapping.
        assert_eq!(
            remap_value(12.0, (20.0, 10.0), (0.0, 1.0), &line, OutOfRange::Clamp),
            0.8
        );
        // Through a step: below the middle 0, above it 1.
        let step = ramp(&[
            (0.0, 0.0, RampBasis::Constant),
            (0.5, 1.0, RampBasis::Constant),
        ]);
        assert_eq!(
            remap_value(0.25, (0.0, 1.0), (0.0, 1.0), &step, OutOfRange::Clamp),
            0.0
        );
        assert_eq!(
            remap_value(0.75, (0.0, 1.0), (0.0, 1.0), &step, OutOfRange::Clamp),
            1.0
        );
    }
}
