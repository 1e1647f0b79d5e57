//! Helpers shared by the polygoniser's tests (each test file uses some).
#![allow(dead_code)]

use geode_frep::{polygonise, Field, MeshOptions};
use geode_geo::Geometry;

/// Distance from `p` to the nearest vertex of `g`.
pub fn nearest_vertex(g: &Geometry, p: [f64; 3]) -> f64 {
    g.positions()
        .iter()
        .map(|v| {
            ((v.x as f64 - p[0]).powi(2)
                + (v.y as f64 - p[1]).powi(2)
                + (v.z as f64 - p[2]).powi(2))
            .sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Meshes `f` over the cube `[-half, half]^3` at `depth`.
pub fn mesh(f: &Field, half: f64, depth: u32) -> Geometry {
    polygonise(
        f,
        &MeshOptions::new([-half; 3], [half; 3], depth),
        &|| false,
        &|_| {},
    )
    .unwrap()
    .0
}

/// The accuracy bar for solids with planar faces: every vertex within 1% of
/// a cell of the surface, every corner within 2% (both in cells).
pub fn assert_sharp(worst_vertex: f64, worst_corner: f64) {
    eprintln!("worst vertex {worst_vertex:.4} cells, worst corner {worst_corner:.4} cells");
    assert!(
        worst_vertex <= 0.01,
        "a vertex lies {worst_vertex} cells off the surface"
    );
    assert!(
        worst_corner <= 0.02,
        "a corner is missed by {worst_corner} cells"
    );
}
