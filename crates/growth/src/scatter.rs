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

/// `count` points on triangles, uniform by area: returns each point and the
/// triangle it lies on. `cancel` is polled per point (an atomic load).
pub fn on_surface(
    triangles: &[[Vec3; 3]],
    count: usize,
    seed: u64,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<(Vec3, u32)>, ScatterError> {
    let mut cdf = Vec::with_capacity(triangles.len());
    let mut total = 0.0f64;
    for t in triangles {
        total += 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length() as f64;
        cdf.push(total);
    }
    if total.is_nan() || total <= 0.0 {
        return Err(ScatterError::NoArea);
    }
    // Collecting into an Option stops every worker at the first None.
    (0..count as u64)
        .into_par_iter()
        .map(|i| {
            if cancel() {
                return None;
            }
            let target = geode_geo::random::unit_f64(seed, i, 0) * total;
            let k = cdf
                .partition_point(|&c| c <= target)
                .min(triangles.len() - 1);
            let t = &triangles[k];
            // Uniform in the triangle: the square-root warp.
            let (r1, r2) = (unit(seed, i, 1).sqrt(), unit(seed, i, 2));
            let p = t[0] * (1.0 - r1) + t[1] * (r1 * (1.0 - r2)) + t[2] * (r1 * r2);
            Some((p, k as u32))
        })
        .collect::<Option<Vec<_>>>()
        .ok_or(ScatterError::Cancelled)
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
