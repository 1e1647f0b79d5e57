//! The modelling kernel at realistic sizes (run: cargo bench -p geode-model
//! --bench model): the boolean of two 500k-triangle spheres (the bar:
//! within 1.5x of manifold's time on the same machine; `cargo run
//! --release -p geode-model --example boolean_vs_manifold` times both in
//! one run); polyextrude of a million quads.

use divan::Bencher;
use geode_geo::glam::{Mat4, Vec3};
use geode_geo::{ops, primitives, Geometry};
use geode_model::boolean::{boolean, BooleanOp};

/// The allocator the geode binary runs with.
#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

fn main() {
    divan::main();
}

/// Two spheres of about `triangles` triangles each, overlapping.
fn sphere_pair(triangles: u32) -> (Geometry, Geometry) {
    let rows = ((triangles / 4) as f32).sqrt() as u32;
    let a = primitives::uv_sphere(1.0, 2 * rows, rows);
    let mut b = a.clone();
    ops::transform(&mut b, Mat4::from_translation(Vec3::new(0.5, 0.3, 0.2)));
    (a, b)
}

#[divan::bench(args = [BooleanOp::Union, BooleanOp::Subtract], sample_count = 3)]
fn boolean_of_two_500k_spheres(bencher: Bencher, op: BooleanOp) {
    let (a, b) = sphere_pair(500_000);
    bencher.bench(|| boolean(&a, &b, op, &|| false).unwrap());
}

/// A 1000 x 1000 grid of quads, every face extruded: as one connected
/// piece, and each face on its own.
#[divan::bench(args = [true, false], sample_count = 3)]
fn polyextrude_a_million_quads(bencher: Bencher, connected: bool) {
    let g = primitives::grid(geode_geo::glam::Vec2::ONE, 1000, 1000);
    let how = geode_model::extrude::Extrude {
        distance: 0.01,
        inset: 0.0001,
        connected,
        ..Default::default()
    };
    bencher.bench(|| {
        geode_model::extrude::extrude(&g, None, None, &how, &|| false)
            .unwrap()
            .geometry
    });
}
