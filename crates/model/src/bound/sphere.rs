//! The smallest enclosing sphere, exactly, by Welzl's algorithm (1991).
//!
//! The smallest ball around points `P` with points `R` on its surface is
//! the ball through `R` when it holds `P`; otherwise the first point of
//! `P` it misses lies on the answer's surface, so the search recurses with
//! that point added to `R`. Written as Gärtner's loop (the recursion runs
//! over `R`, at most four deep, and loops over `P`), over the points in a
//! shuffled order (SplitMix64 from a fixed seed, so the same order every
//! run), which makes the expected time linear.
//!
//! Balls through two, three and four points are the diametral ball, the
//! circumcircle's ball and the circumsphere, solved in f64; four nearly
//! coplanar points fall back to the smallest ball through three of them
//! that holds the fourth. A point counts as inside within 1e-12 of the
//! squared radius. The radius returned is the greatest distance from the
//! (f32) centre to any point, rounded up, so every point is inside.

use geode_geo::glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::ModelError;

/// A sphere around points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundingSphere {
    pub center: Vec3,
    pub radius: f32,
}

#[derive(Clone, Copy, Debug)]
struct Ball {
    center: DVec3,
    radius2: f64,
}

impl Ball {
    const EMPTY: Ball = Ball {
        center: DVec3::ZERO,
        radius2: -1.0,
    };

    fn contains(&self, p: DVec3) -> bool {
        p.distance_squared(self.center) <= self.radius2 * (1.0 + 1e-12)
    }
}

/// The smallest sphere around `points` (None when there are none);
/// `cancel` is polled every 65536 points of the outer loop.
pub fn bounding_sphere(
    points: &[Vec3],
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Option<BoundingSphere>, ModelError> {
    if points.is_empty() {
        return Ok(None);
    }
    let shuffled = shuffled(points);
    let mut support = Vec::with_capacity(4);
    let mut ball = Ball::EMPTY;
    for (i, &p) in shuffled.iter().enumerate() {
        if i % 65536 == 0 && cancel() {
            return Err(ModelError::Cancelled);
        }
        if !ball.contains(p) {
            support.push(p);
            ball = with_support(&shuffled[..i], &mut support);
            support.pop();
        }
    }
    let center = ball.center.as_vec3();
    let radius = points
        .par_iter()
        .map(|p| p.as_dvec3().distance(center.as_dvec3()))
        .reduce(|| 0.0, f64::max);
    let mut radius32 = radius as f32;
    if f64::from(radius32) < radius {
        radius32 = radius32.next_up();
    }
    Ok(Some(BoundingSphere {
        center,
        radius: radius32,
    }))
}

/// The points in f64, in a fixed pseudo-random order.
fn shuffled(points: &[Vec3]) -> Vec<DVec3> {
    let mut out: Vec<DVec3> = points.par_iter().map(|p| p.as_dvec3()).collect();
    let mut state = 0x5EED_0FB0_0D5E_ED0F_u64;
    for i in (1..out.len()).rev() {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        out.swap(i, (z % (i as u64 + 1)) as usize);
    }
    out
}

/// The smallest ball around `points` with every `support` point on its
/// surface.
fn with_support(points: &[DVec3], support: &mut Vec<DVec3>) -> Ball {
    let mut ball = ball_through(support);
    if support.len() == 4 {
        return ball;
    }
    for (i, &p) in points.iter().enumerate() {
        if !ball.contains(p) {
            support.push(p);
            ball = with_support(&points[..i], support);
            support.pop();
        }
    }
    ball
}

/// The smallest ball with all of `s` (up to four points) on its surface.
fn ball_through(s: &[DVec3]) -> Ball {
    match *s {
        [] => Ball::EMPTY,
        [a] => Ball {
            center: a,
            radius2: 0.0,
        },
        [a, b] => Ball {
            center: (a + b) * 0.5,
            radius2: a.distance_squared(b) * 0.25,
        },
        [a, b, c] => circle_ball(a, b, c),
        [a, b, c, d] => sphere_ball(a, b, c, d),
        _ => unreachable!("at most four support points"),
    }
}

/// The ball of the circle through three points (the widest pair's when
/// they are collinear).
fn circle_ball(a: DVec3, b: DVec3, c: DVec3) -> Ball {
    let (ab, ac) = (b - a, c - a);
    let n = ab.cross(ac);
    let denominator = 2.0 * n.length_squared();
    if denominator <= 1e-24 * ab.length_squared() * ac.length_squared() {
        return [(a, b), (a, c), (b, c)]
            .into_iter()
            .map(|(p, q)| ball_through(&[p, q]))
            .max_by(|x, y| x.radius2.total_cmp(&y.radius2))
            .expect("three pairs");
    }
    let offset =
        (n.cross(ab) * ac.length_squared() + ac.cross(n) * ab.length_squared()) / denominator;
    Ball {
        center: a + offset,
        radius2: offset.length_squared(),
    }
}

/// The circumsphere of four points (when they are nearly coplanar: the
/// smallest circle ball of three of them that holds the fourth).
fn sphere_ball(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> Ball {
    let (ab, ac, ad) = (b - a, c - a, d - a);
    let det = ab.dot(ac.cross(ad));
    let scale = ab.length() * ac.length() * ad.length();
    if det.abs() <= 1e-12 * scale {
        let quad = [a, b, c, d];
        let triples = [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]];
        let balls = triples.map(|[i, j, k]| circle_ball(quad[i], quad[j], quad[k]));
        return balls
            .iter()
            .filter(|ball| quad.iter().all(|&p| ball.contains(p)))
            .min_by(|x, y| x.radius2.total_cmp(&y.radius2))
            .or_else(|| balls.iter().max_by(|x, y| x.radius2.total_cmp(&y.radius2)))
            .copied()
            .expect("four triples");
    }
    // 2 (q - a) · x = |q - a|² for q = b, c, d, by Cramer's rule.
    let rhs = DVec3::new(
        ab.length_squared(),
        ac.length_squared(),
        ad.length_squared(),
    ) * 0.5;
    let x = (ac.cross(ad) * rhs.x + ad.cross(ab) * rhs.y + ab.cross(ac) * rhs.z) / det;
    Ball {
        center: a + x,
        radius2: x.length_squared(),
    }
}
