//! Attribute transfer between geometries (Houdini's Attribute Transfer):
//! each destination element finds its sources (the nearest source points
//! by a k-d tree, or the nearest point of the source surface by a triangle
//! hierarchy) and takes their values, blended with its own by distance.
//!
//! A destination within `threshold` of its nearest source takes the
//! transferred value whole; from `threshold` to `threshold + blend_width`
//! the transferred value fades (smoothstep) into the destination's own (or
//! the attribute's default when it had none); beyond, it keeps its own.
//! With several samples, numbers are averaged by inverse squared distance
//! (Shepard's weights; a source at the same place wins outright); integers,
//! strings and arrays take the nearest source's value where the blend is
//! at least one half.

use geode_geo::glam::Vec3;
use geode_geo::ops::TriangleBvh;
use geode_geo::{AttribData, Attribute};
use rayon::prelude::*;

use crate::error::unless_cancelled;
use crate::kdtree::{KdTree, Neighbour};
use crate::AttribError;

/// How far, and from how many sources.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reach {
    /// Full transfer within this distance (infinite: everywhere).
    pub threshold: f32,
    /// The distance past the threshold over which the transfer fades out.
    pub blend_width: f32,
    /// Source points each destination averages (1: the nearest's value).
    pub samples: usize,
}

impl Reach {
    fn check(&self) -> Result<(), AttribError> {
        let threshold_ok = self.threshold >= 0.0; // false for NaN too
        let width_ok = self.blend_width >= 0.0 && self.blend_width.is_finite();
        if !threshold_ok || !width_ok {
            return Err(AttribError::Invalid(format!(
                "the distance threshold ({}) and blend width ({}) must not be negative",
                self.threshold, self.blend_width
            )));
        }
        if self.samples == 0 || self.samples > MAX_SAMPLES {
            return Err(AttribError::Invalid(format!(
                "the sample count must be 1 to {MAX_SAMPLES}, not {}",
                self.samples
            )));
        }
        Ok(())
    }

    fn reach(&self) -> f32 {
        self.threshold + self.blend_width
    }

    /// The share of the transferred value at distance `d`.
    fn blend(&self, d: f32) -> f32 {
        if d <= self.threshold {
            1.0
        } else if d >= self.reach() {
            0.0
        } else {
            let t = 1.0 - (d - self.threshold) / self.blend_width;
            t * t * (3.0 - 2.0 * t)
        }
    }
}

/// The most sources one destination may average.
pub const MAX_SAMPLES: usize = 64;

/// Destinations per cancellation poll.
const CHUNK: usize = 4096;

/// For each destination, its sources with weights (summing to one), and the
/// share of the transferred value.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stencil {
    pub offsets: Vec<u32>,
    pub sources: Vec<u32>,
    pub weights: Vec<f32>,
    pub blend: Vec<f32>,
}

/// The rows found for a run of destinations, in the order visited: each
/// row's sources and weights appended, its length and blend pushed (no
/// allocation per destination).
#[derive(Default)]
struct Rows {
    sources: Vec<u32>,
    weights: Vec<f32>,
    lengths: Vec<u32>,
    blend: Vec<f32>,
}

impl Rows {
    fn push(&mut self, row: impl IntoIterator<Item = (u32, f32)>, blend: f32) {
        let before = self.sources.len();
        for (s, w) in row {
            self.sources.push(s);
            self.weights.push(w);
        }
        self.lengths.push((self.sources.len() - before) as u32);
        self.blend.push(blend);
    }
}

/// The stencil from the nearest source points of `tree`.
pub fn from_points(
    tree: &KdTree,
    targets: &[Vec3],
    reach: &Reach,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Stencil, AttribError> {
    reach.check()?;
    stencil(
        targets,
        cancel,
        |q, found: &mut Vec<Neighbour>, rows: &mut Rows| {
            tree.k_nearest(q, reach.samples, reach.reach(), found);
            let Some(nearest) = found.first() else {
                return rows.push([], 0.0);
            };
            let blend = reach.blend(nearest.dist2.sqrt());
            if nearest.dist2 == 0.0 || found.len() == 1 {
                return rows.push([(nearest.index, 1.0)], blend);
            }
            let total: f32 = found.iter().map(|n| 1.0 / n.dist2).sum();
            rows.push(
                found.iter().map(|n| (n.index, 1.0 / n.dist2 / total)),
                blend,
            );
        },
    )
}

/// The stencil from the nearest point of the triangles of `bvh`: each
/// destination's source is the triangle's primitive (`prim_of_triangle`).
pub fn from_surface(
    bvh: &TriangleBvh,
    prim_of_triangle: &[u32],
    targets: &[Vec3],
    reach: &Reach,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Stencil, AttribError> {
    reach.check()?;
    stencil(
        targets,
        cancel,
        |q, _: &mut Vec<Neighbour>, rows: &mut Rows| match bvh.closest(q, reach.reach()) {
            Some(c) => rows.push(
                [(prim_of_triangle[c.triangle as usize], 1.0)],
                reach.blend(c.dist2.sqrt()),
            ),
            None => rows.push([], 0.0),
        },
    )
}

/// Queries between polls of `cancel` inside a chunk.
const POLL: usize = 64;

/// Each destination's row, found in parallel chunks, then laid out in
/// destination order. The destinations are visited in Morton order (near
/// ones one after another, so a query finds the tree where the last one
/// left it warm in cache).
fn stencil(
    targets: &[Vec3],
    cancel: &(dyn Fn() -> bool + Sync),
    find: impl Fn(Vec3, &mut Vec<Neighbour>, &mut Rows) + Sync,
) -> Result<Stencil, AttribError> {
    let visit = morton_order(targets);
    unless_cancelled(cancel)?;
    let chunks: Vec<Result<Rows, AttribError>> = visit
        .par_chunks(CHUNK)
        .map(|chunk| {
            unless_cancelled(cancel)?;
            let (mut found, mut rows) = (Vec::new(), Rows::default());
            for (k, &i) in chunk.iter().enumerate() {
                // A query far from a dense surface can take a millisecond
                // (every triangle nearly as close as the nearest).
                if k % POLL == POLL - 1 {
                    unless_cancelled(cancel)?;
                }
                find(targets[i as usize], &mut found, &mut rows);
            }
            Ok(rows)
        })
        .collect();
    let chunks: Vec<Rows> = chunks.into_iter().collect::<Result<_, _>>()?;
    // Row lengths by destination, then each row copied to its place.
    let n = targets.len();
    let mut lengths = vec![0u32; n];
    let mut blend = vec![0.0f32; n];
    let mut at = visit.iter();
    for rows in &chunks {
        for (&len, &b) in rows.lengths.iter().zip(&rows.blend) {
            let i = *at.next().expect("one row per destination") as usize;
            lengths[i] = len;
            blend[i] = b;
        }
    }
    let mut offsets = Vec::with_capacity(n + 1);
    offsets.push(0u32);
    for &len in &lengths {
        offsets.push(offsets.last().copied().unwrap_or(0) + len);
    }
    let total = offsets[n] as usize;
    let (mut sources, mut weights) = (vec![0u32; total], vec![0.0f32; total]);
    let mut at = visit.iter();
    for rows in &chunks {
        let mut from = 0usize;
        for &len in &rows.lengths {
            let i = *at.next().expect("one row per destination") as usize;
            let (to, len) = (offsets[i] as usize, len as usize);
            sources[to..to + len].copy_from_slice(&rows.sources[from..from + len]);
            weights[to..to + len].copy_from_slice(&rows.weights[from..from + len]);
            from += len;
        }
    }
    Ok(Stencil {
        offsets,
        sources,
        weights,
        blend,
    })
}

/// The indices of `points` in Morton (Z-curve) order over their bounds,
/// ties by index: a fixed order, whatever the threads.
fn morton_order(points: &[Vec3]) -> Vec<u32> {
    let (lo, hi) = points
        .iter()
        .filter(|p| p.is_finite())
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    let scale = (hi - lo).max_element();
    let spread = |x: u32| {
        // 10 bits to every third of 30.
        let mut x = u64::from(x) & 0x3ff;
        x = (x | (x << 16)) & 0x0300_00ff;
        x = (x | (x << 8)) & 0x0300_f00f;
        x = (x | (x << 4)) & 0x030c_30c3;
        (x | (x << 2)) & 0x0924_9249
    };
    let code = |p: Vec3| -> u64 {
        if scale.is_nan() || scale <= 0.0 || !p.is_finite() {
            return 0;
        }
        let q = ((p - lo) / scale * 1023.0).clamp(Vec3::ZERO, Vec3::splat(1023.0));
        spread(q.x as u32) | spread(q.y as u32) << 1 | spread(q.z as u32) << 2
    };
    let mut keyed: Vec<(u64, u32)> = points
        .par_iter()
        .enumerate()
        .map(|(i, &p)| (code(p), i as u32))
        .collect();
    keyed.par_sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}

/// `source` carried through the stencil onto the destinations, mixed with
/// `own` (the destination's attribute of that name, if it has one of the
/// same type).
pub fn apply(stencil: &Stencil, source: &Attribute, own: Option<&Attribute>) -> Attribute {
    let n = stencil.blend.len();
    let own = own.filter(|a| a.attrib_type() == source.attrib_type() && a.len() == n);
    let mut out = match own {
        Some(a) => a.clone(),
        None => Attribute::new(source.default_value().clone(), source.type_info, n),
    };
    let row = |i: usize| stencil.offsets[i] as usize..stencil.offsets[i + 1] as usize;
    if let (Some((src, w)), true) = (source.data().as_floats(), out.data().as_floats().is_some()) {
        let (dst, _) = out.floats_mut().expect("a float column");
        dst.par_chunks_mut(w).enumerate().for_each(|(i, d)| {
            let b = stencil.blend[i];
            if b <= 0.0 {
                return;
            }
            for (k, x) in d.iter_mut().enumerate() {
                let moved: f32 = row(i)
                    .map(|j| stencil.weights[j] * src[stencil.sources[j] as usize * w + k])
                    .sum();
                *x = if b >= 1.0 {
                    moved
                } else {
                    *x + (moved - *x) * b
                };
            }
        });
        return out;
    }
    // Whole values: the nearest source's, where the blend is at least half.
    let picked: Vec<(usize, u32)> = (0..n)
        .filter(|&i| stencil.blend[i] >= 0.5 && !row(i).is_empty())
        .map(|i| (i, stencil.sources[row(i).start]))
        .collect();
    let values = source.gather(&picked.iter().map(|p| p.1).collect::<Vec<_>>());
    let data: &AttribData = values.data();
    let mut writer = out.values_mut();
    for (k, &(i, _)) in picked.iter().enumerate() {
        let _ = writer.set(i, &data.get(k));
    }
    out
}
