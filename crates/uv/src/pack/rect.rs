//! An island's minimal-area bounding rectangle: the convex hull (Andrew's
//! monotone chain), then rotating calipers over its edges (the minimal
//! rectangle has a side on a hull edge: Freeman and Shapira 1975).

/// A rectangle around a point set, in the frame of a unit direction `d`:
/// a point `p` maps to `(p . d, p . perp(d))` with `perp(d) = (-d.y,
/// d.x)` (a rotation), and the mapped points lie in `min .. min + size`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Oriented {
    pub direction: [f64; 2],
    pub min: [f64; 2],
    pub size: [f64; 2],
}

impl Oriented {
    /// `p` in the rectangle's frame.
    pub fn rotate(&self, p: [f64; 2]) -> [f64; 2] {
        let [dx, dy] = self.direction;
        [p[0] * dx + p[1] * dy, -p[0] * dy + p[1] * dx]
    }

    /// The same rectangle turned a quarter turn (its width and height
    /// swap): the direction becomes `(d.y, -d.x)`.
    pub fn turned(&self) -> Oriented {
        let [dx, dy] = self.direction;
        Oriented {
            direction: [dy, -dx],
            min: [-(self.min[1] + self.size[1]), self.min[0]],
            size: [self.size[1], self.size[0]],
        }
    }
}

/// The axis-aligned bounding rectangle of `points` (direction (1, 0)).
pub fn axis_aligned(points: &[[f64; 2]]) -> Oriented {
    bounds_along([1.0, 0.0], points)
}

/// The bounding rectangle of `points` in the frame of `direction`.
fn bounds_along(direction: [f64; 2], points: &[[f64; 2]]) -> Oriented {
    let frame = Oriented {
        direction,
        min: [0.0; 2],
        size: [0.0; 2],
    };
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for &p in points {
        let q = frame.rotate(p);
        for k in 0..2 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    if points.is_empty() {
        (lo, hi) = ([0.0; 2], [0.0; 2]);
    }
    Oriented {
        direction,
        min: lo,
        size: [hi[0] - lo[0], hi[1] - lo[1]],
    }
}

/// The bounding rectangle of least area (ties: the first hull edge).
pub fn minimal_area(points: &[[f64; 2]]) -> Oriented {
    let hull = convex_hull(points);
    let n = hull.len();
    if n < 3 {
        let direction = match hull.as_slice() {
            [a, b] => unit([b[0] - a[0], b[1] - a[1]]),
            _ => [1.0, 0.0],
        };
        return bounds_along(direction, &hull);
    }
    let dot = |p: [f64; 2], d: [f64; 2]| p[0] * d[0] + p[1] * d[1];
    let next = |i: usize| (i + 1) % n;
    // Argmax along the edge, argmax along the inward normal, argmin
    // along the edge: each moves forward around the hull as the edge does.
    let (mut far_d, mut far_n, mut near_d) = (0, 0, 0);
    let mut best: Option<(f64, usize)> = None;
    for i in 0..n {
        let d = unit([hull[next(i)][0] - hull[i][0], hull[next(i)][1] - hull[i][1]]);
        let normal = [-d[1], d[0]];
        if i == 0 {
            far_d = argmax(&hull, |p| dot(p, d));
            far_n = argmax(&hull, |p| dot(p, normal));
            near_d = argmax(&hull, |p| -dot(p, d));
        }
        advance(&hull, &mut far_d, |p| dot(p, d));
        advance(&hull, &mut far_n, |p| dot(p, normal));
        advance(&hull, &mut near_d, |p| -dot(p, d));
        let width = dot(hull[far_d], d) - dot(hull[near_d], d);
        let height = dot(hull[far_n], normal) - dot(hull[i], normal);
        let area = width * height;
        if best.is_none_or(|(a, _)| area < a) {
            best = Some((area, i));
        }
    }
    let i = best.map_or(0, |b| b.1);
    let d = unit([hull[next(i)][0] - hull[i][0], hull[next(i)][1] - hull[i][1]]);
    bounds_along(d, &hull)
}

/// Moves `j` forward while the next hull point scores higher (at most
/// once around).
fn advance(hull: &[[f64; 2]], j: &mut usize, score: impl Fn([f64; 2]) -> f64) {
    for _ in 0..hull.len() {
        let next = (*j + 1) % hull.len();
        if score(hull[next]) > score(hull[*j]) {
            *j = next;
        } else {
            break;
        }
    }
}

fn argmax(points: &[[f64; 2]], score: impl Fn([f64; 2]) -> f64) -> usize {
    let mut best = 0;
    for (i, &p) in points.iter().enumerate() {
        if score(p) > score(points[best]) {
            best = i;
        }
    }
    best
}

fn unit(v: [f64; 2]) -> [f64; 2] {
    let length = (v[0] * v[0] + v[1] * v[1]).sqrt();
    if length > 0.0 && length.is_finite() {
        [v[0] / length, v[1] / length]
    } else {
        [1.0, 0.0]
    }
}

/// The convex hull, counter-clockwise, without collinear points or
/// repeats (one point for coincident input, two for collinear).
pub fn convex_hull(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut sorted: Vec<[f64; 2]> = points
        .iter()
        .copied()
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .collect();
    sorted.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    sorted.dedup();
    if sorted.len() < 3 {
        return sorted;
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(2 * sorted.len());
    for pass in [sorted.clone(), sorted.iter().rev().copied().collect()] {
        let start = hull.len();
        for p in pass {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    if hull.len() < 3 {
        // Collinear: the two ends.
        return vec![sorted[0], sorted[sorted.len() - 1]];
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hull_of_a_square_with_inner_points() {
        let pts = [
            [0.0, 0.0],
            [1.0, 0.0],
            [0.5, 0.5],
            [1.0, 1.0],
            [0.0, 1.0],
            [0.5, 0.0],
        ];
        let hull = convex_hull(&pts);
        assert_eq!(hull, vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
    }

    #[test]
    fn a_turned_rectangle_is_found_upright() {
        // A 4 x 1 rectangle turned by 30 degrees, with an inner point.
        let (s, c) = 30f64.to_radians().sin_cos();
        let turn = |x: f64, y: f64| [c * x - s * y + 3.0, s * x + c * y - 1.0];
        let pts = [
            turn(0.0, 0.0),
            turn(4.0, 0.0),
            turn(4.0, 1.0),
            turn(0.0, 1.0),
            turn(2.0, 0.5),
        ];
        let r = minimal_area(&pts);
        let (w, h) = (r.size[0].max(r.size[1]), r.size[0].min(r.size[1]));
        assert!((w - 4.0).abs() < 1e-9 && (h - 1.0).abs() < 1e-9, "{r:?}");
        for p in pts {
            let q = r.rotate(p);
            assert!(q[0] >= r.min[0] - 1e-9 && q[0] <= r.min[0] + r.size[0] + 1e-9);
            assert!(q[1] >= r.min[1] - 1e-9 && q[1] <= r.min[1] + r.size[1] + 1e-9);
        }
        let t = r.turned();
        for p in pts {
            let q = t.rotate(p);
            assert!(
                q[0] >= t.min[0] - 1e-9 && q[0] <= t.min[0] + t.size[0] + 1e-9,
                "{q:?} {t:?}"
            );
            assert!(q[1] >= t.min[1] - 1e-9 && q[1] <= t.min[1] + t.size[1] + 1e-9);
        }
    }

    #[test]
    fn degenerate_point_sets() {
        assert_eq!(minimal_area(&[]).size, [0.0, 0.0]);
        assert_eq!(minimal_area(&[[1.0, 2.0], [1.0, 2.0]]).size, [0.0, 0.0]);
        let line = minimal_area(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]);
        assert!((line.size[0] - 8f64.sqrt()).abs() < 1e-12 && line.size[1].abs() < 1e-12);
    }
}
