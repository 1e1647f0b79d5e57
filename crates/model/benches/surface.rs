//! The surface kernels at realistic sizes: smoothing a million-triangle
//! mesh for 10 iterations (topology built each time, as a cook does),
//! mountain over a million points (8 octaves of Perlin noise), and the
//! three bounds of a million points (a bumpy, tilted ellipsoid's surface,
//! where every point is on the convex hull, and a cloud inside a tilted
//! box). Run: cargo bench -p geode-model --bench surface

use divan::counter::ItemsCount;
use divan::Bencher;
use geode_geo::glam::{Mat4, Quat, Vec3};
use geode_geo::{ops, primitives, random, Geometry};
use geode_model::bound::{axis_aligned_box, bounding_sphere, oriented_box};
use geode_model::deform::{area_weighted_normals, mountain, Fractal};
use geode_model::smooth::{smooth, SmoothMethod, SmoothOptions};

#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

fn main() {
    divan::main();
}

fn never() -> bool {
    false
}

/// About a million triangles (a triangulated UV sphere, 500k points), its
/// points jittered so smoothing has work to do.
fn million_triangles() -> Geometry {
    let mut g = ops::triangulate(&primitives::uv_sphere(1.0, 1000, 501), None);
    for (i, p) in g.positions_mut().iter_mut().enumerate() {
        *p *= 1.0 + 0.01 * random::unit(1, i as u64, 0);
    }
    g
}

#[divan::bench(args = ["laplacian", "taubin"], sample_count = 3, sample_size = 1)]
fn smooth_10_iterations_1m_triangles(bencher: Bencher, method: &str) {
    let g = million_triangles();
    let method = match method {
        "laplacian" => SmoothMethod::Laplacian,
        _ => SmoothMethod::Taubin { pass_band: 0.1 },
    };
    let opts = SmoothOptions {
        method,
        strength: 0.5,
        iterations: 10,
        pin_border: true,
        pinned: None,
        keep_volume: false,
    };
    bencher
        .counter(ItemsCount::new(g.num_prims()))
        .with_inputs(|| g.clone())
        .bench_local_values(|mut g| {
            smooth(&mut g, &opts, &never).unwrap();
            g
        });
}

/// A million points (a 1000 x 1001 UV sphere).
fn million_points() -> Geometry {
    primitives::uv_sphere(1.0, 1000, 1001)
}

#[divan::bench(sample_count = 3, sample_size = 1)]
fn mountain_perlin_8_octaves_1m_points(bencher: Bencher) {
    let g = million_points();
    let normals = area_weighted_normals(&g);
    let fractal = Fractal {
        height: 0.1,
        element_size: 0.2,
        offset: Vec3::ZERO,
        octaves: 8,
        roughness: 0.5,
        lacunarity: 2.0,
        seed: 1,
    };
    let basis = |q: [f32; 3]| geode_vex::noise::perlin(q, 0);
    bencher
        .counter(ItemsCount::new(g.num_points()))
        .with_inputs(|| g.clone())
        .bench_local_values(|mut g| {
            mountain(&mut g, &normals, None, &fractal, &basis, &never).unwrap();
            g
        });
}

#[divan::bench(sample_count = 3, sample_size = 1)]
fn area_weighted_normals_1m_points(bencher: Bencher) {
    let g = million_points();
    bencher
        .counter(ItemsCount::new(g.num_points()))
        .bench_local(|| area_weighted_normals(&g));
}

fn tilt() -> Mat4 {
    Mat4::from_rotation_translation(
        Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7),
        Vec3::new(1.0, -2.0, 0.5),
    )
}

/// A million points: "surface", a bumpy tilted ellipsoid's (all on the
/// hull); "cloud", uniform inside a tilted box.
fn points(kind: &str) -> Vec<Vec3> {
    let m = tilt();
    match kind {
        "surface" => million_points()
            .positions()
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let bump = 1.0 + 0.02 * random::unit(2, i as u64, 0);
                m.transform_point3(*p * Vec3::new(2.0, 1.0, 0.5) * bump)
            })
            .collect(),
        _ => (0..1_000_000u64)
            .map(|i| {
                let u = Vec3::new(
                    random::unit(3, i, 0),
                    random::unit(3, i, 1),
                    random::unit(3, i, 2),
                );
                m.transform_point3((u - 0.5) * Vec3::new(2.0, 1.0, 0.5))
            })
            .collect(),
    }
}

#[divan::bench(args = ["surface", "cloud"], sample_count = 3, sample_size = 1)]
fn bound_box_1m_points(bencher: Bencher, kind: &str) {
    let p = points(kind);
    bencher
        .counter(ItemsCount::new(p.len()))
        .bench_local(|| axis_aligned_box(&p));
}

#[divan::bench(args = ["surface", "cloud"], sample_count = 3, sample_size = 1)]
fn bound_oriented_1m_points(bencher: Bencher, kind: &str) {
    let p = points(kind);
    bencher
        .counter(ItemsCount::new(p.len()))
        .bench_local(|| oriented_box(&p, &never).unwrap());
}

#[divan::bench(args = ["surface", "cloud"], sample_count = 3, sample_size = 1)]
fn bound_sphere_1m_points(bencher: Bencher, kind: &str) {
    let p = points(kind);
    bencher
        .counter(ItemsCount::new(p.len()))
        .bench_local(|| bounding_sphere(&p, &never).unwrap());
}
