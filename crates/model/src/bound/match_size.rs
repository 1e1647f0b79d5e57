//! Match Size: a translation and a scale that put one geometry's bounds
//! onto a target box, justified per axis as Houdini's Match Size does.
//!
//! Per axis, the justification picks an anchor of each box (its min, its
//! centre or its max): the geometry is scaled (when asked) about its own
//! anchor, then moved so its anchor lands on the target's. `None` leaves
//! the axis where it is (the scale is then about the geometry's centre).
//! Per-axis scaling makes each side as long as the target's; uniform
//! scaling takes the largest factor that keeps every side within the
//! target's (the smallest of the per-axis factors: fit inside). Axes of
//! zero size keep a factor of 1 (nothing to stretch). The transform goes
//! through `ops::transform`, so normals, vectors and other tagged
//! attributes follow it.

use geode_geo::glam::{Mat4, Vec3};
use geode_geo::ops::{self, Aabb};
use geode_geo::Geometry;

use crate::ModelError;

/// Which point of each box meets the target's along an axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Justify {
    Min,
    Center,
    Max,
    /// No translation along the axis.
    None,
}

impl Justify {
    pub const NAMES: &'static [&'static str] = &["min", "center", "max", "none"];

    pub fn from_name(name: &str) -> Option<Justify> {
        Some(match name {
            "min" => Justify::Min,
            "center" => Justify::Center,
            "max" => Justify::Max,
            "none" => Justify::None,
            _ => return None,
        })
    }

    fn anchor(self, b: &Aabb, axis: usize) -> f32 {
        match self {
            Justify::Min => b.min[axis],
            Justify::Max => b.max[axis],
            Justify::Center | Justify::None => b.center()[axis],
        }
    }
}

/// Whether and how the size is matched too.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScaleMode {
    /// Translate only.
    None,
    /// One factor for every axis, fitting inside the target.
    Uniform,
    /// Each axis its own factor.
    PerAxis,
}

impl ScaleMode {
    pub const NAMES: &'static [&'static str] = &["none", "uniform", "per_axis"];

    pub fn from_name(name: &str) -> Option<ScaleMode> {
        Some(match name {
            "none" => ScaleMode::None,
            "uniform" => ScaleMode::Uniform,
            "per_axis" => ScaleMode::PerAxis,
            _ => return None,
        })
    }
}

/// The transform taking `source` onto `target`.
pub fn match_transform(
    source: &Aabb,
    target: &Aabb,
    justify: [Justify; 3],
    scale: ScaleMode,
) -> Mat4 {
    let (from, to) = (source.size(), target.size());
    let per_axis = Vec3::from_array(std::array::from_fn(|k| {
        if from[k] > 0.0 {
            to[k] / from[k]
        } else {
            1.0
        }
    }));
    let factors = match scale {
        ScaleMode::None => Vec3::ONE,
        ScaleMode::PerAxis => per_axis,
        ScaleMode::Uniform => {
            let fit = (0..3)
                .filter(|&k| from[k] > 0.0)
                .map(|k| per_axis[k])
                .fold(f32::INFINITY, f32::min);
            Vec3::splat(if fit.is_finite() { fit } else { 1.0 })
        }
    };
    let translation = Vec3::from_array(std::array::from_fn(|k| {
        let anchor = justify[k].anchor(source, k);
        let destination = if justify[k] == Justify::None {
            anchor
        } else {
            justify[k].anchor(target, k)
        };
        destination - factors[k] * anchor
    }));
    let mut m = Mat4::from_scale(factors);
    m.w_axis = translation.extend(1.0);
    m
}

/// Moves (and scales) `g` onto `target`; returns the transform applied.
pub fn match_size(
    g: &mut Geometry,
    target: &Aabb,
    justify: [Justify; 3],
    scale: ScaleMode,
) -> Result<Mat4, ModelError> {
    if target.is_empty() || !target.min.is_finite() || !target.max.is_finite() {
        return Err(ModelError::Invalid("the target box is empty".into()));
    }
    let Some(source) = ops::bounds(g) else {
        return Ok(Mat4::IDENTITY);
    };
    let m = match_transform(&source, target, justify, scale);
    ops::transform(g, m);
    Ok(m)
}
