//! The fractal noise parameters mountain and attribute_noise share,
//! declared once, and the noise bases (geode-vex's kernels) they name.

use geode_geo::glam::Vec3;
use geode_model::deform::{Fractal, FractalField};
use geode_op::{CookContext, CookError, ParamDefault as D, ParamSpec as P, ParamType as T, Params};
use geode_vex::noise;

use crate::util::vec3;

pub(crate) const ELEMENT_SIZE: P = P::new(
    "element_size",
    "Element size",
    T::Float,
    D::Float(1.0),
    "The size of the first octave's features (1 / frequency).",
)
.at_least(0.0);
pub(crate) const OFFSET: P = P::new(
    "offset",
    "Offset",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "Shift of the noise domain; animate it to slide the noise through the surface.",
);
pub(crate) const OCTAVES: P = P::new(
    "octaves",
    "Octaves",
    T::Int,
    D::Int(8),
    "Layers of noise summed, each finer than the last.",
)
.range(1.0, 32.0);
pub(crate) const ROUGHNESS: P = P::new(
    "roughness",
    "Roughness",
    T::Float,
    D::Float(0.5),
    "Each octave's amplitude over the previous one's.",
)
.range(0.0, 1.0);
pub(crate) const LACUNARITY: P = P::new(
    "lacunarity",
    "Lacunarity",
    T::Float,
    D::Float(2.0),
    "Each octave's frequency over the previous one's.",
)
.range(1.0, 16.0);
pub(crate) const SEED: P = P::new(
    "seed",
    "Seed",
    T::Int,
    D::Int(0),
    "Picks another, independent noise field.",
);

/// The fractal the parameters describe, of `height` (read from
/// `height_param`), checked; an error names its parameter.
pub(crate) fn fractal(
    ctx: &CookContext,
    p: &Params,
    height: f32,
    height_param: &P,
) -> Result<Fractal, CookError> {
    let fractal = Fractal {
        height,
        element_size: p.float(&ELEMENT_SIZE)? as f32,
        offset: vec3(p, &OFFSET)?,
        octaves: p.int(&OCTAVES)?.clamp(0, 64) as u32,
        roughness: p.float(&ROUGHNESS)? as f32,
        lacunarity: p.float(&LACUNARITY)? as f32,
        seed: p.int(&SEED)? as u64,
    };
    fractal.check_field().map_err(|(field, e)| {
        let param = match field {
            FractalField::ElementSize => &ELEMENT_SIZE,
            FractalField::Octaves => &OCTAVES,
            FractalField::Roughness => &ROUGHNESS,
            FractalField::Lacunarity => &LACUNARITY,
            FractalField::Offset => &OFFSET,
            FractalField::Height => height_param,
        };
        ctx.kernel_at(param, e)
    })?;
    Ok(fractal)
}

/// The basis a noise menu names: Perlin's improved noise, simplex, or
/// Worley's F1 as 1 - 2 F1 (cells raised, borders low); each in [-1, 1].
pub(crate) fn basis(name: &str) -> fn([f32; 3]) -> f32 {
    match name {
        "simplex" => |q| noise::simplex(q, 0),
        "worley" => |q| 1.0 - 2.0 * noise::worley(q, 1.0).f1.min(1.0),
        _ => |q| noise::perlin(q, 0),
    }
}

/// The offset a frame adds when the noise is animated: `speed` units per
/// frame from frame 0.
pub(crate) fn animated(offset: Vec3, speed: Vec3, frame: f64) -> Vec3 {
    offset + speed * frame as f32
}
