//! Test meshes the modelling kernel's tests, benchmarks and timing
//! examples share (included by path where `common` as a whole is not).
#![allow(dead_code)]

use geode_geo::{ops, primitives, Geometry};

/// A UV sphere of about `triangles` triangles with creased ridges (the
/// absolute value of a product of sines), triangulated.
pub fn ridged_sphere(triangles: u32) -> Geometry {
    let rows = ((triangles / 4) as f32).sqrt() as u32;
    let mut g = ops::triangulate(&primitives::uv_sphere(1.0, 2 * rows, rows), None);
    for p in g.positions_mut() {
        let n = p.normalize();
        let bump = ((5.0 * n.x).sin() * (5.0 * n.y).sin() * (5.0 * n.z).cos()).abs();
        *p = n * (1.0 + 0.08 * bump);
    }
    g
}

/// About a million triangles: `box`, a unit box of right triangles (290
/// divisions a side, twelve sharp edges), or else a triangulated UV sphere
/// (1000 by 501, whose pole bands are slivers a hundred times shorter
/// than the remesh target); with the area the shape covers.
pub fn million_triangles(shape: &str) -> (Geometry, f32) {
    match shape {
        "box" => (
            ops::triangulate(
                &primitives::box_mesh(geode_geo::glam::Vec3::ONE, [290, 290, 290]),
                None,
            ),
            6.0,
        ),
        _ => (
            ops::triangulate(&primitives::uv_sphere(1.0, 1000, 501), None),
            4.0 * std::f32::consts::PI,
        ),
    }
}

/// The edge length of equilateral triangles `count` of which cover `area`.
pub fn equilateral_length(area: f32, count: f32) -> f32 {
    (area / (3f32.sqrt() / 4.0 * count)).sqrt()
}
