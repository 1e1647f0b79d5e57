//! The generalized winding number of a triangle soup at a point (Jacobson,
//! Kavan and Sorkine-Hornung 2013: the sum of the triangles' signed solid
//! angles over 4π; 1 inside a closed, outward-facing mesh, 0 outside, and a
//! smooth in-between across holes and gaps, so `w > 1/2` decides inside
//! robustly), made fast by Barill et al.'s hierarchy (2018): a subtree far
//! from the query (farther than `BETA` times its radius) counts as one
//! dipole, its area-weighted normal at its area-weighted centre, so a query
//! visits the triangles near it and a few dozen far boxes.
//!
//! Everything is summed in double precision; the hierarchy is the
//! [`TriangleBvh`]'s, its nodes' dipoles computed bottom up once.

use glam::{DVec3, Vec3};

use super::raycast::TriangleBvh;

/// How far, in multiples of a subtree's radius, the query must be for the
/// subtree to count as one dipole. At 2 (Barill et al.'s choice) the
/// first-order term's error at a point is a few thousandths of a unit
/// winding number (tested below), far from the half that decides a side.
const BETA: f64 = 2.0;

/// A subtree's far-field summary.
#[derive(Clone, Copy, Debug, Default)]
struct Dipole {
    /// Area-weighted centroid of its triangles.
    centre: DVec3,
    /// Sum of its triangles' area vectors (half the cross product of two
    /// edges: normal times area).
    area_normal: DVec3,
    /// Distance from `centre` to the farthest corner of the subtree's box.
    radius: f64,
    /// Total area (weights `centre` when subtrees merge).
    area: f64,
}

/// A triangle hierarchy that answers winding numbers (and, through
/// [`WindingBvh::bvh`], closest points and ray casts).
pub struct WindingBvh {
    bvh: TriangleBvh,
    /// One per hierarchy node, in the hierarchy's order.
    dipoles: Vec<Dipole>,
}

fn dvec(v: Vec3) -> DVec3 {
    v.as_dvec3()
}

/// The signed solid angle triangle `c` subtends at `q` (Van Oosterom and
/// Strackee 1983), positive where the triangle faces away from `q` (its
/// corners run counter-clockwise seen from outside, `q` behind it).
fn solid_angle(c: &[Vec3; 3], q: DVec3) -> f64 {
    let [a, b, c] = c.map(|p| dvec(p) - q);
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let det = a.dot(b.cross(c));
    let div = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    2.0 * det.atan2(div)
}

impl WindingBvh {
    /// Adds dipoles to `bvh`'s nodes (children after their parent, so one
    /// backward pass merges children before their parent).
    pub fn new(bvh: TriangleBvh) -> WindingBvh {
        let mut dipoles = vec![Dipole::default(); bvh.nodes.len()];
        if bvh.corners.is_empty() {
            return WindingBvh { bvh, dipoles };
        }
        for n in (0..bvh.nodes.len()).rev() {
            let node = &bvh.nodes[n];
            let mut d = if node.end > node.start {
                leaf_dipole(&bvh.corners[node.start as usize..node.end as usize])
            } else {
                merge(dipoles[n + 1], dipoles[node.second as usize])
            };
            if d.area <= 0.0 {
                d.centre = dvec((node.lo + node.hi) * 0.5);
            }
            let reach = (d.centre - dvec(node.lo))
                .abs()
                .max((dvec(node.hi) - d.centre).abs());
            d.radius = reach.length();
            dipoles[n] = d;
        }
        WindingBvh { bvh, dipoles }
    }

    /// The hierarchy's triangles (for closest points and rays).
    pub fn bvh(&self) -> &TriangleBvh {
        &self.bvh
    }

    /// The generalized winding number at `q`.
    pub fn winding(&self, q: DVec3) -> f64 {
        if self.bvh.corners.is_empty() {
            return 0.0;
        }
        let mut total = 0.0;
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let n = stack[top] as usize;
            let node = &self.bvh.nodes[n];
            let d = &self.dipoles[n];
            let to_centre = d.centre - q;
            let dist2 = to_centre.length_squared();
            if dist2 > (BETA * d.radius).powi(2) {
                total += far_field(d, to_centre, dist2);
            } else if node.end > node.start {
                for c in &self.bvh.corners[node.start as usize..node.end as usize] {
                    total += solid_angle(c, q);
                }
            } else {
                stack[top] = n as u32 + 1;
                stack[top + 1] = node.second;
                top += 2;
            }
        }
        total / (4.0 * std::f64::consts::PI)
    }

    /// Whether `q` is inside: winding number above one half in magnitude,
    /// so a soup wound inside out (-1 within) has the same inside, as
    /// nested shells wound either way do.
    pub fn contains(&self, q: DVec3) -> bool {
        self.winding(q).abs() > 0.5
    }

    /// Bytes held (hierarchy and dipoles).
    pub fn memory_bytes(&self) -> usize {
        self.bvh.memory_bytes() + self.dipoles.len() * std::mem::size_of::<Dipole>()
    }
}

/// A subtree's solid angle at a query `r = centre - q` away (`dist2 =
/// |r|^2`), as a dipole: `N . r / |r|^3`.
fn far_field(d: &Dipole, r: DVec3, dist2: f64) -> f64 {
    r.dot(d.area_normal) / (dist2 * dist2.sqrt())
}

/// Whether every edge of a triangle soup is used as often in one
/// direction as in the other, edges keyed by their ends' positions (-0 and
/// 0 alike): the winding number is then an integer, constant between
/// surfaces, wherever it is off the surface.
pub fn is_closed_soup(triangles: impl IntoIterator<Item = [Vec3; 3]>) -> bool {
    let key = |p: Vec3| p.to_array().map(|v| if v == 0.0 { 0 } else { v.to_bits() });
    let mut balance: std::collections::HashMap<([u32; 3], [u32; 3]), i32> =
        std::collections::HashMap::new();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (key(t[k]), key(t[(k + 1) % 3]));
            match a.cmp(&b) {
                std::cmp::Ordering::Less => *balance.entry((a, b)).or_default() += 1,
                std::cmp::Ordering::Greater => *balance.entry((b, a)).or_default() -= 1,
                std::cmp::Ordering::Equal => {}
            }
        }
    }
    balance.values().all(|&b| b == 0)
}

fn leaf_dipole(corners: &[[Vec3; 3]]) -> Dipole {
    let mut parts = corners.iter().map(|c| {
        let [a, b, cc] = c.map(dvec);
        let area_normal = 0.5 * (b - a).cross(cc - a);
        Dipole {
            centre: (a + b + cc) / 3.0,
            area_normal,
            radius: 0.0,
            area: area_normal.length(),
        }
    });
    let first = parts.next().unwrap_or_default();
    parts.fold(first, merge)
}

/// Two subtrees as one, at their area-weighted centre.
fn merge(a: Dipole, b: Dipole) -> Dipole {
    let area = a.area + b.area;
    let centre = if area > 0.0 {
        (a.centre * a.area + b.centre * b.area) / area
    } else {
        (a.centre + b.centre) * 0.5
    };
    Dipole {
        centre,
        area_normal: a.area_normal + b.area_normal,
        radius: 0.0,
        area,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A UV sphere of radius 1, outward-facing, with `n` rings.
    fn sphere(n: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let mut p = vec![Vec3::new(0.0, 0.0, 1.0)];
        for i in 1..n {
            let th = std::f32::consts::PI * i as f32 / n as f32;
            for j in 0..2 * n {
                let ph = std::f32::consts::PI * j as f32 / n as f32;
                p.push(Vec3::new(
                    th.sin() * ph.cos(),
                    th.sin() * ph.sin(),
                    th.cos(),
                ));
            }
        }
        p.push(Vec3::new(0.0, 0.0, -1.0));
        let ring = |i: u32, j: u32| 1 + (i - 1) * 2 * n + j % (2 * n);
        let last = p.len() as u32 - 1;
        let mut t = Vec::new();
        for j in 0..2 * n {
            t.push([0, ring(1, j), ring(1, j + 1)]);
            t.push([last, ring(n - 1, j + 1), ring(n - 1, j)]);
        }
        for i in 1..n - 1 {
            for j in 0..2 * n {
                t.push([ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)]);
                t.push([ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)]);
            }
        }
        (p, t)
    }

    fn exact(p: &[Vec3], t: &[[u32; 3]], q: DVec3) -> f64 {
        t.iter()
            .map(|tri| solid_angle(&tri.map(|i| p[i as usize]), q))
            .sum::<f64>()
            / (4.0 * std::f64::consts::PI)
    }

    fn points(n: usize, half: f64) -> Vec<DVec3> {
        let mut s = 0x9e37_79b9_u64;
        let mut next = || {
            s = s.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            ((s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * half
        };
        (0..n).map(|_| DVec3::new(next(), next(), next())).collect()
    }

    #[test]
    fn the_hierarchy_agrees_with_the_exact_sum_and_decides_sides() {
        let (p, t) = sphere(48);
        let w = WindingBvh::new(TriangleBvh::new(&p, &t));
        let mut worst: f64 = 0.0;
        for q in points(3000, 1.6) {
            let (fast, slow) = (w.winding(q), exact(&p, &t, q));
            worst = worst.max((fast - slow).abs());
            // The polygonal sphere's inscribed radius is cos(pi/48) or so.
            if q.length() < 0.99 {
                assert!(w.contains(q), "{q} inside: {fast}");
            } else if q.length() > 1.0 {
                assert!(!w.contains(q), "{q} outside: {fast}");
            }
        }
        assert!(worst < 0.06, "far-field error {worst}");
    }

    #[test]
    fn a_hole_moves_the_number_smoothly_not_the_side() {
        let (p, mut t) = sphere(32);
        // Drop a few triangles around the north pole: a hole.
        t.drain(0..6);
        let w = WindingBvh::new(TriangleBvh::new(&p, &t));
        for q in points(500, 0.8).into_iter().filter(|q| q.length() < 0.8) {
            assert!(w.winding(q) > 0.9, "{q}: {}", w.winding(q));
        }
        assert!(w.winding(DVec3::new(0.0, 0.0, 0.99)) > 0.5);
        assert!(w.winding(DVec3::new(0.0, 0.0, 1.05)) < 0.5);
    }

    #[test]
    fn closed_soups_balance_their_edges() {
        let (p, t) = sphere(8);
        let soup = |t: &[[u32; 3]]| {
            t.iter()
                .map(|x| x.map(|i| p[i as usize]))
                .collect::<Vec<_>>()
        };
        assert!(is_closed_soup(soup(&t)));
        assert!(!is_closed_soup(soup(&t[1..])));
        // Flipping one triangle unbalances its edges too.
        let mut flipped = t.clone();
        flipped[3].swap(1, 2);
        assert!(!is_closed_soup(soup(&flipped)));
    }

    #[test]
    fn overlapping_copies_count_twice_and_an_empty_soup_is_outside() {
        let (p, t) = sphere(16);
        let doubled: Vec<[u32; 3]> = t.iter().chain(&t).copied().collect();
        let w = WindingBvh::new(TriangleBvh::new(&p, &doubled));
        assert!(
            (w.winding(DVec3::ZERO) - 2.0).abs() < 0.06,
            "{}",
            w.winding(DVec3::ZERO)
        );
        let none = WindingBvh::new(TriangleBvh::new(&[], &[]));
        assert_eq!(none.winding(DVec3::ZERO), 0.0);
    }
}
