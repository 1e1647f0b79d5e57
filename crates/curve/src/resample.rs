//! Resampling a curve by segment length or point count, carving a range of
//! it, and smoothing it. Results are locations on the input (segment and
//! parameter), so callers interpolate every attribute, not only P.

use crate::polyline::{arc_lengths, glam_d::DVec3};

/// A location on a curve: `t` of the way from point `segment` to the next
/// (which is point 0 again for the closing segment of a closed curve).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub segment: u32,
    pub t: f64,
}

impl Sample {
    /// The point and its successor that this sample lies between.
    pub fn ends(&self, n: usize) -> (usize, usize) {
        let a = self.segment as usize;
        (a, (a + 1) % n)
    }

    pub fn position(&self, points: &[DVec3]) -> DVec3 {
        let (a, b) = self.ends(points.len());
        points[a].lerp(points[b], self.t)
    }
}

/// Locations at the given arc lengths (ascending, within the curve).
fn at_lengths(points: &[DVec3], closed: bool, lengths: impl Iterator<Item = f64>) -> Vec<Sample> {
    let (acc, total) = arc_lengths(points, closed);
    let n = points.len();
    let segments = if closed { n } else { n - 1 };
    let mut seg = 0usize;
    let mut out = Vec::new();
    for s in lengths {
        let s = s.clamp(0.0, total);
        let end = |k: usize| if k + 1 < n { acc[k + 1] } else { total };
        while seg + 1 < segments && end(seg) < s {
            seg += 1;
        }
        let len = end(seg) - acc[seg];
        let t = if len > 0.0 {
            ((s - acc[seg]) / len).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(Sample {
            segment: seg as u32,
            t,
        });
    }
    out
}

/// `count` points evenly spaced by arc length (ends included when open; a
/// closed curve gets `count` points around, none repeated).
pub fn resample_by_count(points: &[DVec3], closed: bool, count: usize) -> Vec<Sample> {
    if points.len() < 2 || count == 0 {
        return points
            .iter()
            .take(count)
            .enumerate()
            .map(|(i, _)| Sample {
                segment: i as u32,
                t: 0.0,
            })
            .collect();
    }
    let (_, total) = arc_lengths(points, closed);
    let count = count.max(if closed { 3 } else { 2 });
    let denom = if closed { count } else { count - 1 } as f64;
    at_lengths(points, closed, (0..count).map(|i| total * i as f64 / denom))
}

/// Points every `length` along the curve, the spacing evened out so the
/// ends land exactly (the segment count is the rounded length ratio).
pub fn resample_by_length(points: &[DVec3], closed: bool, length: f64) -> Vec<Sample> {
    let (_, total) = arc_lengths(points, closed);
    let segments = if length > 0.0 && total > 0.0 {
        ((total / length).round() as usize).clamp(1, 1 << 26)
    } else {
        1
    };
    resample_by_count(points, closed, if closed { segments } else { segments + 1 })
}

/// The part of an open curve between arc-length fractions `from` and `to`
/// (0..1), keeping the original points inside the range.
pub fn carve(points: &[DVec3], from: f64, to: f64) -> Vec<Sample> {
    if points.len() < 2 {
        return Vec::new();
    }
    let (acc, total) = arc_lengths(points, false);
    let (a, b) = (
        from.min(to).clamp(0.0, 1.0) * total,
        from.max(to).clamp(0.0, 1.0) * total,
    );
    let mut lengths = vec![a];
    lengths.extend(acc.iter().copied().filter(|&s| s > a && s < b));
    lengths.push(b);
    at_lengths(points, false, lengths.into_iter())
}

/// Laplacian smoothing: each point moves `strength` (0..1) toward the mean
/// of its neighbours, `iterations` times; an open curve keeps its ends.
pub fn smooth(points: &[DVec3], closed: bool, strength: f64, iterations: usize) -> Vec<DVec3> {
    let n = points.len();
    let mut cur = points.to_vec();
    if n < 3 {
        return cur;
    }
    let mut next = cur.clone();
    for _ in 0..iterations {
        for i in 0..n {
            if !closed && (i == 0 || i == n - 1) {
                continue;
            }
            let (prev, succ) = ((i + n - 1) % n, (i + 1) % n);
            let mean = 0.5 * (cur[prev] + cur[succ]);
            next[i] = cur[i].lerp(mean, strength);
        }
        std::mem::swap(&mut cur, &mut next);
        next.copy_from_slice(&cur);
    }
    cur
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Vec<DVec3> {
        vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 0.0, 1.0), DVec3::Z]
    }

    #[test]
    fn by_count_and_length_space_points_evenly() {
        let s = resample_by_count(&square(), true, 8);
        let p: Vec<DVec3> = s.iter().map(|x| x.position(&square())).collect();
        assert_eq!(p.len(), 8);
        for i in 0..8 {
            let d = p[i].distance(p[(i + 1) % 8]);
            assert!((d - 0.5).abs() < 1e-12, "{i}: {d}");
        }
        let open = resample_by_length(&square(), false, 0.26);
        // Length 3 / 0.26 = 11.5 -> 12 segments, 13 points, ends exact.
        assert_eq!(open.len(), 13);
        assert_eq!(open[0].position(&square()), DVec3::ZERO);
        assert!(open[12].position(&square()).distance(DVec3::Z) < 1e-12);
    }

    #[test]
    fn carve_keeps_inner_points_and_smooth_keeps_ends() {
        let c = carve(&square(), 0.25, 0.75);
        let p: Vec<DVec3> = c.iter().map(|x| x.position(&square())).collect();
        assert_eq!(
            p,
            vec![
                DVec3::new(0.75, 0.0, 0.0),
                DVec3::X,
                DVec3::new(1.0, 0.0, 1.0),
                DVec3::new(0.75, 0.0, 1.0)
            ]
        );
        let s = smooth(&square(), false, 0.5, 10);
        assert_eq!(s[0], DVec3::ZERO);
        assert_eq!(s[3], DVec3::Z);
        // A closed square shrinks toward its centre symmetrically.
        let s = smooth(&square(), true, 0.5, 3);
        let c: DVec3 = s.iter().sum::<DVec3>() / 4.0;
        assert!(c.distance(DVec3::new(0.5, 0.0, 0.5)) < 1e-12);
    }
}
