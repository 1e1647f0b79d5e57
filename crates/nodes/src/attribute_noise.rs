//! attribute_noise: fractal noise written into a float or vector attribute
//! (Houdini's Attribute Noise), over Perlin, simplex, Worley or curl noise,
//! seeded and animated by frame, the same bytes on every machine and thread
//! count (each element's value depends on its position alone).

use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, Attribute, TypeInfo};
use geode_model::deform::Fractal;
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};
use rayon::prelude::*;

use crate::noise_params::{self, basis};
use crate::util::{
    attribute_name, class, element_positions, geometry, group_param, input_owned, vec3, CLASSES,
};

const NAME: P = P::new(
    "name",
    "Attribute",
    T::String,
    D::Str("Cd"),
    "The attribute written (created when missing).",
);
const CLASS: P = P::new("class", "Class", T::Menu(CLASSES), D::Str("point"), "Its class: each point by its position, each vertex by its point's, each primitive by its centroid, the detail at the points' mean.");
const GROUP: P = P::new(
    "group",
    "Group",
    T::String,
    D::Str(""),
    "Only these points or primitives (a group pattern); empty for all.",
);
const KIND: P = P::new(
    "type",
    "Type",
    T::Menu(&["float", "vector"]),
    D::Str("vector"),
    "One value, or three independent ones (curl noise is always a vector).",
);
const NOISE: P = P::new(
    "noise",
    "Noise",
    T::Menu(&["perlin", "simplex", "worley", "curl"]),
    D::Str("perlin"),
    "The basis: Perlin's improved gradient noise, simplex, Worley's cellular (1 - 2 F1), or curl (the curl of a three-channel Perlin fractal: divergence-free, for advecting points; its length varies, typically 1 to 5 times the amplitude, and the range does not apply). Positions past about 1e6 lose the noise to single precision.",
);
const OPERATION: P = P::new(
    "operation",
    "Operation",
    T::Menu(&["set", "add", "multiply", "max", "min"]),
    D::Str("set"),
    "How the noise meets the attribute's value.",
);
const AMPLITUDE: P = P::new(
    "amplitude",
    "Amplitude",
    T::Float,
    D::Float(1.0),
    "The noise's scale.",
);
const RANGE: P = P::new(
    "range",
    "Range",
    T::Menu(&["positive", "zero_centered"]),
    D::Str("positive"),
    "Values from 0 to the amplitude, or from minus to plus the amplitude (not for curl noise).",
);
const POSITION: P = P::new("position", "Position attribute", T::String, D::Str("P"), "The point attribute whose values place the noise (`rest` keeps the noise stuck to a deforming surface).");
const ANIMATE: P = P::new(
    "speed",
    "Animation speed",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "How far the noise domain slides per frame (from frame 0), added to the offset.",
);

static ATTRIBUTE_NOISE: NodeSpec = NodeSpec::new(
    "attribute_noise",
    "Attribute Noise",
    "attribute",
    "Writes fractal noise into a float or vector attribute (Houdini's Attribute Noise): Perlin, simplex, Worley or curl; octaves, roughness, lacunarity, seed, offset animated by frame; set, add, multiply, max or min. Seeded: the same bytes on every machine and thread count.",
    &[geometry_input("geometry")],
    &[
        NAME,
        CLASS,
        GROUP,
        KIND,
        NOISE,
        OPERATION,
        AMPLITUDE,
        RANGE,
        noise_params::ELEMENT_SIZE,
        noise_params::OFFSET,
        ANIMATE,
        noise_params::OCTAVES,
        noise_params::ROUGHNESS,
        noise_params::LACUNARITY,
        noise_params::SEED,
        POSITION,
    ],
);

/// Elements per cancellation poll.
const CHUNK: usize = 1 << 14;

fn cook_noise(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let name = p.string(&NAME)?;
    attribute_name(ctx, &NAME, name)?;
    let c = class(p, &CLASS)?;
    let noise_name = p.string(&NOISE)?;
    let curl = noise_name == "curl";
    let width = if curl || p.string(&KIND)? == "vector" {
        3
    } else {
        1
    };
    let mut fractal = noise_params::fractal(ctx, p, 1.0, &AMPLITUDE)?;
    fractal.offset = noise_params::animated(fractal.offset, vec3(p, &ANIMATE)?, ctx.frame);
    let amplitude = p.float(&AMPLITUDE)? as f32;
    if !amplitude.is_finite() {
        return Err(ctx.param_error(&AMPLITUDE, "the amplitude must be finite"));
    }
    let positive = p.string(&RANGE)? == "positive" && !curl;
    let op = p.string(&OPERATION)?;
    let positions = positions(ctx, p, &g, c)?;
    let selected = match c {
        AttribClass::Point | AttribClass::Primitive => group_param(ctx, p, &GROUP, &g, c)?,
        _ => None,
    };
    ctx.reserve(&NAME, positions.len() as f64 * 12.0, "noise values")?;
    let mut column = existing(ctx, &g, c, name, width)?;
    let channels: Vec<Fractal> = (0..3u64)
        .map(|k| Fractal {
            seed: fractal.seed.wrapping_mul(3).wrapping_add(k),
            ..fractal
        })
        .collect();
    let shifts: Vec<Vec<Vec3>> = channels.iter().map(|f| f.domain_shifts()).collect();
    let field = basis(if curl { "perlin" } else { noise_name });
    let channel = |k: usize, q: Vec3| channels[k].value_shifted(&shifts[k], q, &field);
    let noise_at = |q: Vec3, out: &mut [f32]| {
        if curl {
            let v = curl_at(&channel, q, fractal.element_size);
            out.copy_from_slice(&v.to_array());
        } else {
            for (k, o) in out.iter_mut().enumerate() {
                *o = channel(k, q);
            }
        }
        for o in out.iter_mut() {
            let n = if positive { 0.5 * (*o + 1.0) } else { *o };
            *o = n * amplitude;
        }
    };
    column
        .par_chunks_mut(CHUNK * width)
        .enumerate()
        .try_for_each(|(chunk, values)| {
            ctx.check()?;
            let mut n = [0.0f32; 3];
            for (j, v) in values.chunks_mut(width).enumerate() {
                let i = chunk * CHUNK + j;
                if selected.as_ref().is_some_and(|s| !s.contains(i)) {
                    continue;
                }
                noise_at(positions[i], &mut n[..width]);
                for (x, &y) in v.iter_mut().zip(&n) {
                    *x = match op {
                        "add" => *x + y,
                        "multiply" => *x * y,
                        "max" => x.max(y),
                        "min" => x.min(y),
                        _ => y,
                    };
                }
            }
            Ok::<(), CookError>(())
        })?;
    let attr = if width == 3 {
        let v: Vec<Vec3> = column.chunks(3).map(Vec3::from_slice).collect();
        Attribute::from_data(geode_geo::AttribData::Vec3(v), type_info(&g, c, name))
    } else {
        Attribute::from_data(geode_geo::AttribData::Float(column), TypeInfo::None)
    };
    g.set_attrib(c, name, attr)
        .map_err(|e| ctx.kernel_at(&NAME, e))?;
    geometry(g)
}

/// The curl of the three-channel potential at `q`, by central differences
/// a thousandth of the element size apart, scaled by the element size so
/// its size does not depend on the noise's scale.
fn curl_at(channel: &dyn Fn(usize, Vec3) -> f32, q: Vec3, element_size: f32) -> Vec3 {
    let h = element_size * 1e-3;
    let d = |axis: usize, k: usize| {
        let step = Vec3::AXES[axis] * h;
        (channel(k, q + step) - channel(k, q - step)) / (2.0 * h)
    };
    Vec3::new(d(1, 2) - d(2, 1), d(2, 0) - d(0, 2), d(0, 1) - d(1, 0)) * element_size
}

/// Where each element reads the noise: the position attribute (a point
/// attribute of three floats), carried to vertices, primitives and detail
/// as `P` is.
fn positions(
    ctx: &CookContext,
    p: &Params,
    g: &geode_geo::Geometry,
    c: AttribClass,
) -> Result<Vec<Vec3>, CookError> {
    let name = p.string(&POSITION)?;
    if name == geode_geo::P {
        return Ok(element_positions(g, c));
    }
    let Some(geode_geo::AttribData::Vec3(rest)) =
        g.attrib(AttribClass::Point, name).map(|a| a.data())
    else {
        crate::util::attribute_of(ctx, &POSITION, g, AttribClass::Point, name)?;
        return Err(ctx.param_error(
            &POSITION,
            format!("point `{name}` is not a vector of three floats"),
        ));
    };
    let mut moved = g.clone();
    moved.set_positions(rest.clone());
    Ok(element_positions(&moved, c))
}

/// The attribute's values now (for add, multiply, max, min), or zeros.
fn existing(
    ctx: &CookContext,
    g: &geode_geo::Geometry,
    c: AttribClass,
    name: &str,
    width: usize,
) -> Result<Vec<f32>, CookError> {
    let n = crate::util::count(g, c);
    match g.attrib(c, name) {
        None => Ok(vec![0.0; n * width]),
        Some(a) => match a.data().as_floats() {
            Some((f, w)) if w == width => Ok(f.to_vec()),
            _ => Err(ctx.param_error(
                &NAME,
                format!(
                    "`{name}` is a {} attribute; the noise writes {}",
                    a.attrib_type(),
                    if width == 3 {
                        "a vector of three floats"
                    } else {
                        "a float"
                    }
                ),
            )),
        },
    }
}

/// Colour for `Cd`, otherwise the existing tag (or none).
fn type_info(g: &geode_geo::Geometry, c: AttribClass, name: &str) -> TypeInfo {
    match g.attrib(c, name) {
        Some(a) => a.type_info,
        None if name == "Cd" => TypeInfo::Color,
        None => TypeInfo::None,
    }
}

pub fn register(r: &mut Registry) {
    r.node(&ATTRIBUTE_NOISE, cook_noise);
}
