//! Seeded scattering: points inside a solid (any inside test: a mesh's
//! winding number, a field's sign) by rejection from its bounding box, and
//! points on a surface by area. Candidate `i` depends only on (seed, i), so
//! results are exact in count and identical on any thread count. The blue
//! noise option oversamples and removes the most crowded points one at a
//! time (sample elimination, Yuksel 2015; see `eliminate`) down to the
//! exact count.

use geode_geo::glam::Vec3;
use geode_geo::random::unit;
use rayon::prelude::*;

pub use crate::eliminate::{eliminate, BYTES_PER_CANDIDATE};

#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum ScatterError {
    #[error("found only {found} of {wanted} points inside after {tried} candidates: the solid is empty or a tiny part of its bounds")]
    TooFewInside {
        wanted: usize,
        found: usize,
        tried: usize,
    },
    #[error("the surface has no area")]
    NoArea,
    #[error("cancelled")]
    Cancelled,
}

/// Candidate `i` in the box `lo..hi`: a hash of (seed, i), so any caller
/// drawing from the same stream sees the same points.
pub fn candidate(lo: Vec3, hi: Vec3, seed: u64, i: u64) -> Vec3 {
    lo + (hi - lo) * Vec3::new(unit(seed, i, 0), unit(seed, i, 1), unit(seed, i, 2))
}

/// `count` points inside the solid whose `inside` test is evaluated on
/// batches of candidates from the box `lo..hi`; also returns the fraction
/// of candidates found inside (the solid's share of the box).
pub fn inside(
    lo: Vec3,
    hi: Vec3,
    count: usize,
    seed: u64,
    inside: &(dyn Fn(&[Vec3]) -> Vec<bool> + Sync),
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<(Vec<Vec3>, f64), ScatterError> {
    let limit = count.saturating_mul(1000).max(1 << 20);
    let mut out = Vec::with_capacity(count);
    let mut tried = 0usize;
    let mut hits = 0usize;
    while out.len() < count {
        if tried >= limit {
            return Err(ScatterError::TooFewInside {
                wanted: count,
                found: out.len(),
                tried,
            });
        }
        if cancel() {
            return Err(ScatterError::Cancelled);
        }
        // Enough candidates for the rest at the rate seen so far.
        let rate = if tried == 0 {
            0.5
        } else {
            (out.len() as f64 / tried as f64).max(1e-3)
        };
        // Batches stay small enough that a cancel is seen within milliseconds.
        let batch = (((count - out.len()) as f64 / rate * 1.1) as usize).clamp(1024, 1 << 18);
        let batch = batch.min(limit - tried);
        let cands: Vec<Vec3> = (tried..tried + batch)
            .into_par_iter()
            .map(|i| candidate(lo, hi, seed, i as u64))
            .collect();
        let flags = inside(&cands);
        for (p, ok) in cands.iter().zip(flags) {
            if ok {
                hits += 1;
                if out.len() < count {
                    out.push(*p);
                }
            }
        }
        tried += batch;
    }
    let share = if tried > 0 {
        hits as f64 / tried as f64
    } else {
        0.0
    };
    Ok((out, share.min(1.0)))
}

/// Points on triangles and the triangle each lies on.
pub struct SurfacePoints {
    pub positions: Vec<Vec3>,
    pub triangles: Vec<u32>,
}

/// Points per parallel task (and per cancellation poll).
const PER_TASK: usize = 1 << 14;

/// The inverse of a piecewise-constant distribution's CDF in expected O(1):
/// a guide table of as many buckets as triangles points each bucket's start
/// at its first triangle, then a short scan finds the exact one — the same
/// triangle a binary search over the CDF finds, without its dependent loads.
struct Sampler {
    cdf: Vec<f64>,
    total: f64,
    /// Each bucket's first triangle and where the bucket starts.
    guide: Vec<(u32, f64)>,
    /// Buckets per unit of the CDF.
    per_unit: f64,
}

impl Sampler {
    fn new(triangles: &[[Vec3; 3]]) -> Sampler {
        let mut cdf = Vec::with_capacity(triangles.len());
        let mut total = 0.0f64;
        for t in triangles {
            total += 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length() as f64;
            cdf.push(total);
        }
        let buckets = cdf.len().max(1);
        let mut guide = Vec::with_capacity(buckets);
        let mut k = 0;
        for j in 0..buckets {
            let start = total * (j as f64 / buckets as f64);
            while k < cdf.len() && cdf[k] <= start {
                k += 1;
            }
            guide.push((k as u32, start));
        }
        Sampler {
            cdf,
            total,
            guide,
            per_unit: buckets as f64 / total,
        }
    }

    /// The first triangle whose CDF exceeds `target` (clamped to the last).
    fn find(&self, target: f64) -> usize {
        // The bucket from a product may be one too far by rounding: step back.
        let mut j = ((target * self.per_unit) as usize).min(self.guide.len() - 1);
        while j > 0 && self.guide[j].1 > target {
            j -= 1;
        }
        let mut k = self.guide[j].0 as usize;
        while k < self.cdf.len() && self.cdf[k] <= target {
            k += 1;
        }
        k.min(self.cdf.len() - 1)
    }
}

/// `count` points on triangles, uniform by area, each with the triangle it
/// lies on. Point `i` depends on (seed, i) alone. `cancel` is polled per
/// few thousand points.
pub fn on_surface(
    triangles: &[[Vec3; 3]],
    count: usize,
    seed: u64,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<SurfacePoints, ScatterError> {
    let sampler = Sampler::new(triangles);
    if sampler.total.is_nan() || sampler.total <= 0.0 {
        return Err(ScatterError::NoArea);
    }
    let mut out = SurfacePoints {
        positions: vec![Vec3::ZERO; count],
        triangles: vec![0; count],
    };
    let stopped = out
        .positions
        .par_chunks_mut(PER_TASK)
        .zip(out.triangles.par_chunks_mut(PER_TASK))
        .enumerate()
        .any(|(c, (positions, tris))| {
            if cancel() {
                return true;
            }
            for (k, (p, tri)) in positions.iter_mut().zip(tris).enumerate() {
                let i = (c * PER_TASK + k) as u64;
                let target = geode_geo::random::unit_f64(seed, i, 0) * sampler.total;
                let at = sampler.find(target);
                let t = &triangles[at];
                // Uniform in the triangle: the square-root warp.
                let (r1, r2) = (unit(seed, i, 1).sqrt(), unit(seed, i, 2));
                *p = t[0] * (1.0 - r1) + t[1] * (r1 * (1.0 - r2)) + t[2] * (r1 * r2);
                *tri = at as u32;
            }
            false
        });
    if stopped {
        return Err(ScatterError::Cancelled);
    }
    Ok(out)
}

/// Total area of triangles.
pub fn area(triangles: &[[Vec3; 3]]) -> f64 {
    triangles
        .iter()
        .map(|t| 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length() as f64)
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ball(points: &[Vec3]) -> Vec<bool> {
        points.iter().map(|p| p.length() <= 1.0).collect()
    }

    #[test]
    fn inside_is_exact_in_count_seeded_and_inside() {
        let (a, share) = inside(Vec3::splat(-1.0), Vec3::ONE, 5000, 3, &ball, &|| false).unwrap();
        assert_eq!(a.len(), 5000);
        assert!(a.iter().all(|p| p.length() <= 1.0));
        // The ball is pi/6 of its box.
        assert!((share - std::f64::consts::PI / 6.0).abs() < 0.03, "{share}");
        let (b, _) = inside(Vec3::splat(-1.0), Vec3::ONE, 5000, 3, &ball, &|| false).unwrap();
        assert_eq!(a, b);
        let (c, _) = inside(Vec3::splat(-1.0), Vec3::ONE, 5000, 4, &ball, &|| false).unwrap();
        assert_ne!(a, c);
        let none = inside(
            Vec3::splat(-1.0),
            Vec3::ONE,
            10,
            3,
            &|p: &[Vec3]| vec![false; p.len()],
            &|| false,
        );
        assert!(matches!(
            none,
            Err(ScatterError::TooFewInside { found: 0, .. })
        ));
    }

    #[test]
    fn the_guide_table_finds_what_a_binary_search_finds() {
        // Areas from tiny to large, zero-area slivers among them.
        let tris: Vec<[Vec3; 3]> = (0..997u64)
            .map(|i| {
                let a = if i % 13 == 0 {
                    0.0
                } else {
                    unit(5, i, 0).powi(6) * 3.0
                };
                [
                    Vec3::ZERO,
                    Vec3::new(a, 0.0, 0.0),
                    Vec3::new(0.0, 1.0, i as f32 * 1e-3),
                ]
            })
            .collect();
        let s = Sampler::new(&tris);
        let by_search = |t: f64| s.cdf.partition_point(|&c| c <= t).min(s.cdf.len() - 1);
        let mut targets: Vec<f64> = (0..200_000u64)
            .map(|i| geode_geo::random::unit_f64(9, i, 0) * s.total)
            .collect();
        // Exactly on every CDF step and bucket start, and the ends.
        targets.extend(s.cdf.iter().copied());
        targets.extend(s.guide.iter().map(|g| g.1));
        targets.extend([0.0, s.total, s.total * (1.0 - 1e-16)]);
        for t in targets {
            assert_eq!(s.find(t), by_search(t), "target {t}");
        }
    }

    #[test]
    fn elimination_spreads_points_apart() {
        let (cands, _) = inside(Vec3::splat(-1.0), Vec3::ONE, 10_000, 1, &ball, &|| false).unwrap();
        let closest = |pts: &[Vec3]| {
            let mut worst = f32::MAX;
            for i in 0..pts.len() {
                for j in i + 1..pts.len() {
                    worst = worst.min(pts[i].distance(pts[j]));
                }
            }
            worst
        };
        let kept: Vec<Vec3> =
            eliminate(&cands, 2000, 4.0 / 3.0 * std::f64::consts::PI, 3, &|| false)
                .unwrap()
                .into_iter()
                .map(|i| cands[i])
                .collect();
        assert_eq!(kept.len(), 2000);
        let random = &cands[..2000];
        assert!(
            closest(&kept) > 3.0 * closest(random),
            "{} vs {}",
            closest(&kept),
            closest(random)
        );
    }
}
