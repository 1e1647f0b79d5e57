//! The oriented bounding box: the smallest box with a face flush against
//! a face of the convex hull, refined by rotating calipers about its axes.
//!
//! For a direction `n`, the smallest box with a face normal to `n` is the
//! hull's extent along `n` times the smallest rectangle around the hull's
//! shadow on the plane normal to `n`, which rotating calipers find in time
//! linear in the shadow's outline (Toussaint 1983: one side of the best
//! rectangle lies on an outline edge). The outline's points are the ends
//! of silhouette edges, hull edges between a face turned toward `n` and
//! one turned away, so a direction costs one pass over the hull's edges
//! and a sort of the outline only.
//!
//! Candidate directions are the hull's distinct face normals (grouped to
//! 1e-7, largest total area first, at most `MAX_FACE_DIRECTIONS`) and the
//! hull vertices' principal axes. This is the family trimesh's
//! `bounding_box_oriented` searches (every face normal), capped for hulls
//! of millions of faces (a sphere's), where the largest faces stand in
//! for the rest. It is not O'Rourke's exact minimum (which may have no
//! face on the hull), so a refinement follows: each axis of the best box
//! is tried as `n` in turn (a rectangle in the plane of the other two),
//! kept when smaller, until nothing improves (at most four rounds).
//!
//! A flat input (every point within 1e-10 of the extent of a plane) gets
//! the smallest rectangle in its plane and zero thickness; a collinear one
//! its principal axes. The box's extents are measured last over all
//! points in its frame, so it holds every point whatever the hull did.
//! Directions are evaluated in parallel, each alone, and the smallest
//! volume wins with ties to the first: the same box on any thread count.

use geode_geo::glam::{DVec2, DVec3, Vec3};
use rayon::prelude::*;

use super::hull::{convex_hull, Hull, NoHull};
use crate::ModelError;

/// Face directions tried at most (the largest faces' first).
const MAX_FACE_DIRECTIONS: usize = 96;
const BLOCK: usize = 1 << 14;

/// A box: `center`, orthonormal right-handed `axes`, half its size along
/// each axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrientedBox {
    pub center: Vec3,
    pub axes: [Vec3; 3],
    pub half_size: Vec3,
}

impl OrientedBox {
    pub fn volume(&self) -> f64 {
        8.0 * self.half_size.as_dvec3().element_product()
    }

    /// The eight corners (bit `k` of the index picks the side along axis
    /// `k`).
    pub fn corners(&self) -> [Vec3; 8] {
        std::array::from_fn(|i| {
            let mut c = self.center.as_dvec3();
            for k in 0..3 {
                let side = if i >> k & 1 == 0 { -1.0 } else { 1.0 };
                c += self.axes[k].as_dvec3() * (side * f64::from(self.half_size[k]));
            }
            c.as_vec3()
        })
    }
}

/// Where a direction's shadow and extent are measured.
enum Source<'a> {
    Hull(&'a Hull, &'a [DVec3]),
    Points(&'a [DVec3]),
}

/// A box frame and its volume as measured on the source.
#[derive(Clone, Copy)]
struct Candidate {
    axes: [DVec3; 3],
    volume: f64,
}

/// The oriented bounding box of `points` (None when there are none).
pub fn oriented_box(
    points: &[Vec3],
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Option<OrientedBox>, ModelError> {
    if points.is_empty() {
        return Ok(None);
    }
    let pts: Vec<DVec3> = points.par_iter().map(|p| p.as_dvec3()).collect();
    let hull = convex_hull(points, cancel);
    let (source, directions) = match &hull {
        Ok(h) => {
            let vertices: Vec<DVec3> = h.vertices.iter().map(|&i| pts[i as usize]).collect();
            let mut directions = face_directions(h);
            directions.extend(principal_axes(&vertices));
            (Source::Hull(h, &pts), directions)
        }
        Err(NoHull::Cancelled) => return Err(ModelError::Cancelled),
        Err(NoHull::Flat(normal)) => (Source::Points(&pts), vec![*normal]),
        Err(NoHull::Line) => (Source::Points(&pts), principal_axes(&pts).to_vec()),
    };
    if cancel() {
        return Err(ModelError::Cancelled);
    }
    let mut best = smallest(
        directions
            .par_iter()
            .map(|&n| evaluate(n, &source))
            .collect(),
    );
    for _ in 0..4 {
        let refined = smallest(best.axes.iter().map(|&n| evaluate(n, &source)).collect());
        if refined.volume < best.volume * (1.0 - 1e-9) {
            best = refined;
        } else {
            break;
        }
    }
    Ok(Some(fit(&pts, best.axes)))
}

/// The first candidate of least volume.
fn smallest(candidates: Vec<Candidate>) -> Candidate {
    candidates
        .into_iter()
        .reduce(|a, b| if b.volume < a.volume { b } else { a })
        .expect("at least one direction")
}

/// The hull's distinct face normals (up to sign), largest area first.
fn face_directions(h: &Hull) -> Vec<DVec3> {
    let mut groups: std::collections::HashMap<[i64; 3], (f64, u32)> =
        std::collections::HashMap::new();
    for (f, n) in h.normals.iter().enumerate() {
        let n = canonical_sign(*n);
        if n == DVec3::ZERO {
            continue;
        }
        let key = (n * 1e7).round().to_array().map(|x| x as i64);
        let e = groups.entry(key).or_insert((0.0, f as u32));
        e.0 += h.double_areas[f];
    }
    let mut ranked: Vec<(f64, u32)> = groups.into_values().collect();
    ranked.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    ranked
        .iter()
        .take(MAX_FACE_DIRECTIONS)
        .map(|&(_, f)| canonical_sign(h.normals[f as usize]))
        .collect()
}

/// `n` or `-n`, whichever has its first non-zero component positive.
fn canonical_sign(n: DVec3) -> DVec3 {
    let first = n.to_array().into_iter().find(|&c| c != 0.0).unwrap_or(0.0);
    if first < 0.0 {
        -n
    } else {
        n
    }
}

/// The smallest box with a face normal to `n`.
fn evaluate(n: DVec3, source: &Source) -> Candidate {
    let n = n.normalize();
    let (u, v) = n.any_orthonormal_pair();
    let (outline, along): (Vec<DVec3>, (f64, f64)) = match source {
        Source::Hull(h, pts) => (
            silhouette(h, n).iter().map(|&i| pts[i as usize]).collect(),
            extent(h.vertices.iter().map(|&i| pts[i as usize]), n),
        ),
        Source::Points(pts) => (pts.to_vec(), extent(pts.iter().copied(), n)),
    };
    let shadow: Vec<DVec2> = outline
        .iter()
        .map(|p| DVec2::new(u.dot(*p), v.dot(*p)))
        .collect();
    let (area, dir) = min_area_rectangle(&convex_hull_2d(shadow));
    let a0 = (u * dir.x + v * dir.y).normalize();
    Candidate {
        axes: [a0, n.cross(a0), n],
        volume: area * (along.1 - along.0),
    }
}

/// Points of hull edges between a face turned toward `n` and one not.
fn silhouette(h: &Hull, n: DVec3) -> Vec<u32> {
    let mut ends: Vec<u32> = h
        .edges
        .iter()
        .filter(|(_, [f, g])| {
            (h.normals[*f as usize].dot(n) > 0.0) != (h.normals[*g as usize].dot(n) > 0.0)
        })
        .flat_map(|(ends, _)| *ends)
        .collect();
    ends.sort_unstable();
    ends.dedup();
    ends
}

/// Least and greatest `n · p`.
fn extent(points: impl Iterator<Item = DVec3>, n: DVec3) -> (f64, f64) {
    points.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
        let d = n.dot(p);
        (lo.min(d), hi.max(d))
    })
}

/// Andrew's monotone chain: the hull counter-clockwise, no collinear
/// points.
fn convex_hull_2d(mut p: Vec<DVec2>) -> Vec<DVec2> {
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<DVec2> = Vec::with_capacity(2 * p.len());
    for pass in 0..2 {
        let start = hull.len();
        let points: Box<dyn Iterator<Item = &DVec2>> = if pass == 0 {
            Box::new(p.iter())
        } else {
            Box::new(p.iter().rev())
        };
        for &q in points {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    hull
}

/// Rotating calipers over a convex counter-clockwise polygon: the least
/// area of a rectangle around it and the unit direction of that
/// rectangle's side along a polygon edge.
fn min_area_rectangle(h: &[DVec2]) -> (f64, DVec2) {
    let m = h.len();
    if m < 3 {
        let dir = if m == 2 {
            (h[1] - h[0]).normalize_or_zero()
        } else {
            DVec2::ZERO
        };
        return (0.0, if dir == DVec2::ZERO { DVec2::X } else { dir });
    }
    let edge = |i: usize| (h[(i + 1) % m] - h[i]).normalize_or_zero();
    let argmax =
        |f: &dyn Fn(DVec2) -> f64| (0..m).max_by(|&a, &b| f(h[a]).total_cmp(&f(h[b]))).unwrap();
    let e0 = edge(0);
    let (mut right, mut left, mut top) = (
        argmax(&|p| e0.dot(p)),
        argmax(&|p| -e0.dot(p)),
        argmax(&|p| e0.perp().dot(p)),
    );
    // Moves a caliper forward while `f` grows (unimodal on a convex polygon).
    let advance = |at: &mut usize, f: &dyn Fn(DVec2) -> f64| {
        for _ in 0..m {
            if f(h[(*at + 1) % m]) > f(h[*at]) {
                *at = (*at + 1) % m;
            } else {
                break;
            }
        }
    };
    let mut best = (f64::INFINITY, DVec2::X);
    for i in 0..m {
        let e = edge(i);
        if e == DVec2::ZERO {
            continue;
        }
        advance(&mut right, &|p| e.dot(p));
        advance(&mut left, &|p| -e.dot(p));
        advance(&mut top, &|p| e.perp().dot(p));
        let width = e.dot(h[right]) - e.dot(h[left]);
        let height = e.perp().dot(h[top]) - e.perp().dot(h[i]);
        let area = width * height;
        if area < best.0 {
            best = (area, e);
        }
    }
    best
}

/// The principal axes (covariance eigenvectors) of the points, right-handed.
fn principal_axes(points: &[DVec3]) -> [DVec3; 3] {
    let sums: Vec<(DVec3, [f64; 6])> = points
        .par_chunks(BLOCK)
        .map(|c| {
            let mut s = (DVec3::ZERO, [0.0; 6]);
            for p in c {
                s.0 += *p;
                let m = &mut s.1;
                (m[0], m[1], m[2]) = (m[0] + p.x * p.x, m[1] + p.y * p.y, m[2] + p.z * p.z);
                (m[3], m[4], m[5]) = (m[3] + p.x * p.y, m[4] + p.x * p.z, m[5] + p.y * p.z);
            }
            s
        })
        .collect();
    let n = points.len().max(1) as f64;
    let (mut sum, mut m) = (DVec3::ZERO, [0.0; 6]);
    for (s, q) in &sums {
        sum += *s;
        for k in 0..6 {
            m[k] += q[k];
        }
    }
    let c = sum / n;
    let cov = [
        [
            m[0] / n - c.x * c.x,
            m[3] / n - c.x * c.y,
            m[4] / n - c.x * c.z,
        ],
        [
            m[3] / n - c.x * c.y,
            m[1] / n - c.y * c.y,
            m[5] / n - c.y * c.z,
        ],
        [
            m[4] / n - c.x * c.z,
            m[5] / n - c.y * c.z,
            m[2] / n - c.z * c.z,
        ],
    ];
    let v = jacobi_eigenvectors(cov);
    [v[0], v[1], v[0].cross(v[1])]
}

/// Eigenvectors of a symmetric 3x3 matrix by cyclic Jacobi rotations.
fn jacobi_eigenvectors(mut a: [[f64; 3]; 3]) -> [DVec3; 3] {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..50 {
        let off = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
        let scale = a[0][0].powi(2) + a[1][1].powi(2) + a[2][2].powi(2);
        if off <= 1e-30 * scale.max(f64::MIN_POSITIVE) {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let (c, s) = (1.0 / (t * t + 1.0).sqrt(), t / (t * t + 1.0).sqrt());
            // A ← Jᵀ A J: columns p and q, then rows p and q.
            for row in &mut a {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (row_p, row_q) = (a[p], a[q]);
            a[p] = std::array::from_fn(|k| c * row_p[k] - s * row_q[k]);
            a[q] = std::array::from_fn(|k| s * row_p[k] + c * row_q[k]);
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    std::array::from_fn(|k| DVec3::new(v[0][k], v[1][k], v[2][k]).normalize())
}

/// The box of frame `axes` around every point.
fn fit(points: &[DVec3], axes: [DVec3; 3]) -> OrientedBox {
    let (lo, hi) = points
        .par_chunks(BLOCK)
        .map(|c| {
            c.iter().fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(lo, hi), p| {
                    let q = DVec3::new(axes[0].dot(*p), axes[1].dot(*p), axes[2].dot(*p));
                    (lo.min(q), hi.max(q))
                },
            )
        })
        .reduce(
            || (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |a, b| (a.0.min(b.0), a.1.max(b.1)),
        );
    let mid = (lo + hi) * 0.5;
    let center = axes[0] * mid.x + axes[1] * mid.y + axes[2] * mid.z;
    OrientedBox {
        center: center.as_vec3(),
        axes: axes.map(|a| a.as_vec3()),
        half_size: ((hi - lo) * 0.5).as_vec3(),
    }
}
