//! Test and benchmark meshes for the UV kernel: a hemisphere of nearly
//! even triangles and an open cylinder with its seam column.
#![allow(dead_code)]

use std::f64::consts::{FRAC_PI_2, TAU};

use geode_geo::glam::Vec3;
use geode_geo::Geometry;

/// A unit hemisphere (y >= 0, pole on +Y) of about `6 rings^2`
/// triangles: ring `j` (polar angle `j / rings` of a quarter turn) has
/// `6 j` points, triangles between rings as in a hexagonal disk. Open at
/// the equator; outward-facing.
pub fn hemisphere(rings: u32) -> Geometry {
    let (positions, triangles) = hemisphere_arrays(rings);
    Geometry::from_triangles(positions, &triangles).expect("valid hemisphere")
}

/// The hemisphere's positions and triangles.
pub fn hemisphere_arrays(rings: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let rings = rings.max(1);
    let mut positions = vec![Vec3::Y];
    let ring_start = |j: u32| if j == 0 { 0 } else { 1 + 3 * j * (j - 1) };
    for j in 1..=rings {
        let theta = FRAC_PI_2 * j as f64 / rings as f64;
        let count = 6 * j;
        for i in 0..count {
            let phi = TAU * i as f64 / count as f64;
            positions.push(Vec3::new(
                (theta.sin() * phi.cos()) as f32,
                theta.cos() as f32,
                (-theta.sin() * phi.sin()) as f32,
            ));
        }
    }
    let mut triangles = Vec::new();
    for j in 0..rings {
        // Walk ring j (inner) and ring j + 1 (outer) together: each
        // sextant has j inner and j + 1 outer segments.
        let (inner_n, outer_n) = (6 * j, 6 * (j + 1));
        let inner = |i: u32| ring_start(j) + if j == 0 { 0 } else { i % inner_n };
        let outer = |i: u32| ring_start(j + 1) + i % outer_n;
        let (mut a, mut b) = (0u32, 0u32);
        while a < inner_n.max(1) * u32::from(j > 0) || b < outer_n {
            // Advance on whichever ring lags in angle.
            let angle_inner = if j == 0 {
                f64::INFINITY
            } else {
                (a as f64 + 0.5) / inner_n as f64
            };
            let angle_outer = (b as f64 + 0.5) / outer_n as f64;
            if b < outer_n && (a >= inner_n || angle_outer <= angle_inner) {
                triangles.push([inner(a), outer(b), outer(b + 1)]);
                b += 1;
            } else {
                triangles.push([inner(a), outer(b), inner(a + 1)]);
                a += 1;
            }
        }
    }
    (positions, triangles)
}

/// An open cylinder of radius 1 and height `height` around Y, `segments`
/// around and `rows` up, in quads (outward-facing), with the points of
/// its seam column (angle 0) on a duplicated-free grid: point `(j, i)`
/// is `j * segments + i`. Returns the mesh and the seam edges.
pub fn cylinder(segments: u32, rows: u32, height: f32) -> (Geometry, Vec<[u32; 2]>) {
    let g = geode_geo::primitives::tube(1.0, height, segments, rows, false);
    let seams = (0..rows)
        .map(|j| [j * segments, (j + 1) * segments])
        .collect();
    (g, seams)
}
