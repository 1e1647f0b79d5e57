//! Growth kernels at scale: space colonization of 100k and 1M attractors
//! uniform in a unit ball (influence 0.1, kill 0.02, step 0.01) to
//! completion, scattering inside and on a mesh, and blue noise by sample
//! elimination (5 candidates per kept point: 1M and 100k on a sphere, and
//! the coral's 3,000 in a ball). Totals are printed once.
//! Run: cargo bench -p geode-growth --bench growth

use geode_geo::glam::Vec3;
use geode_growth::{colonize, scatter, ColonizeOptions, InsideTest};

/// The allocator the geode binary runs with.
#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

fn ball(n: usize) -> Vec<Vec3> {
    scatter::inside(
        Vec3::splat(-1.0),
        Vec3::ONE,
        n,
        1,
        &|p: &[Vec3]| p.iter().map(|q| q.length() <= 1.0).collect(),
        &|| false,
    )
    .unwrap()
    .0
}

fn opts() -> ColonizeOptions {
    ColonizeOptions {
        influence: 0.1,
        kill: 0.02,
        step: 0.01,
        max_iterations: 100_000,
        jitter: 0.0,
        seed: 0,
    }
}

fn main() {
    for n in [100_000, 1_000_000] {
        let a = ball(n);
        let t = std::time::Instant::now();
        let tree = colonize(&a, &[Vec3::ZERO], &opts(), &|| false).unwrap();
        eprintln!(
            "colonize {n} attractors: {:.2} s, {} iterations, {} nodes, {} attractors left",
            t.elapsed().as_secs_f64(),
            tree.iterations,
            tree.positions.len(),
            tree.attractors_left
        );
    }
    divan::main();
}

#[divan::bench(args = [100_000, 1_000_000], sample_count = 3)]
fn colonize_unit_ball(bencher: divan::Bencher, n: usize) {
    let a = ball(n);
    bencher.bench(|| colonize(&a, &[Vec3::ZERO], &opts(), &|| false).unwrap());
}

#[divan::bench(args = [100_000, 1_000_000], sample_count = 5)]
fn scatter_inside_torus_mesh(bencher: divan::Bencher, n: usize) {
    let torus = geode_geo::primitives::torus(1.0, 0.4, 128, 64);
    let test = InsideTest::from_geometry(&torus);
    let inside = |p: &[Vec3]| -> Vec<bool> {
        use rayon::prelude::*;
        p.par_iter().map(|q| test.contains(*q)).collect()
    };
    bencher.bench(|| {
        scatter::inside(
            Vec3::new(-1.5, -0.5, -1.5),
            Vec3::new(1.5, 0.5, 1.5),
            n,
            7,
            &inside,
            &|| false,
        )
        .unwrap()
    });
}

/// Triangles of a 32k-quad sphere.
fn sphere_triangles() -> Vec<[Vec3; 3]> {
    geode_growth::inside::triangles(&geode_geo::primitives::uv_sphere(1.0, 256, 128))
}

#[divan::bench(args = [1_000_000, 7_900_000], sample_count = 5)]
fn scatter_on_sphere_surface(bencher: divan::Bencher, n: usize) {
    let tris = sphere_triangles();
    bencher.bench(|| scatter::on_surface(&tris, n, 7, &|| false).unwrap());
}

#[divan::bench(args = [100_000, 1_000_000], sample_count = 3)]
fn blue_noise_on_sphere_surface(bencher: divan::Bencher, keep: usize) {
    let tris = sphere_triangles();
    let candidates = scatter::on_surface(&tris, 5 * keep, 7, &|| false).unwrap();
    let area = scatter::area(&tris);
    bencher.bench(|| scatter::eliminate(&candidates.positions, keep, area, 2, &|| false).unwrap());
}

/// The coral's size: 3,000 kept of 15,000 candidates in a volume.
#[divan::bench(args = [3_000], sample_count = 40)]
fn blue_noise_in_ball(bencher: divan::Bencher, keep: usize) {
    let candidates = ball(5 * keep);
    let volume = 4.0 / 3.0 * std::f64::consts::PI;
    bencher.bench(|| scatter::eliminate(&candidates, keep, volume, 3, &|| false).unwrap());
}
