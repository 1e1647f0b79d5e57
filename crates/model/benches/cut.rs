//! The cut family at realistic sizes: a capped clip of a 1M-triangle
//! sphere, the convex hull of 1M random points (in a ball: about 10^4
//! hull vertices; in a cube: a few hundred), mirror with seam fuse of a
//! 500k-triangle half sphere, polyfill of its open side and of a cut
//! torus's two 65k-point loops.
//! Run: cargo bench -p geode-model --bench cut

use std::sync::OnceLock;

use divan::counter::ItemsCount;
use divan::Bencher;
use geode_geo::glam::Vec3;
use geode_geo::{ops, primitives, random, Geometry};
use geode_model::clip::{clip, Cap, ClipOptions, Keep};
use geode_model::fill::{polyfill, FillOptions};
use geode_model::hull::convex_hull;
use geode_model::mirror::{mirror, MirrorOptions};

/// The allocator the geode binary runs with.
#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

fn main() {
    divan::main();
}

fn never() -> bool {
    false
}

/// A UV sphere of 1000 x 501 rows: 1,000,000 triangles.
fn sphere() -> &'static Geometry {
    static G: OnceLock<Geometry> = OnceLock::new();
    G.get_or_init(|| ops::triangulate(&primitives::uv_sphere(1.0, 1000, 501), None))
}

/// The sphere's half above a tilted plane, open: about 500k triangles.
fn half_sphere() -> &'static Geometry {
    static G: OnceLock<Geometry> = OnceLock::new();
    G.get_or_init(|| {
        let o = ClipOptions {
            normal: Vec3::new(0.0, 0.0, 1.0),
            ..ClipOptions::default()
        };
        clip(sphere(), &o, &never).unwrap().geometry
    })
}

fn cloud(ball: bool) -> Geometry {
    let pts: Vec<Vec3> = (0..1_000_000u64)
        .map(|i| {
            let u = Vec3::new(
                random::unit(3, i, 0),
                random::unit(3, i, 1),
                random::unit(3, i, 2),
            ) * 2.0
                - 1.0;
            if ball {
                // Uniform in the ball: directions on the sphere, radius
                // by the cube root.
                u.normalize_or_zero() * random::unit(4, i, 0).cbrt()
            } else {
                u
            }
        })
        .collect();
    let mut g = Geometry::new();
    g.add_points(&pts);
    g
}

#[divan::bench(sample_count = 5)]
fn clip_capped_sphere_1m_triangles(bencher: Bencher) {
    let g = sphere();
    let o = ClipOptions {
        normal: Vec3::new(0.3, -0.5, 0.8),
        distance: 0.2,
        keep: Keep::Below,
        cap: Cap::Triangles,
        ..ClipOptions::default()
    };
    bencher
        .counter(ItemsCount::new(g.num_prims()))
        .bench(|| clip(g, &o, &never).unwrap());
}

#[divan::bench(sample_count = 5, args = ["ball", "cube"])]
fn convex_hull_1m_points(bencher: Bencher, shape: &str) {
    let g = cloud(shape == "ball");
    bencher
        .counter(ItemsCount::new(g.num_points()))
        .bench(|| convex_hull(&g, true, &never).unwrap());
}

#[divan::bench(sample_count = 5)]
fn mirror_fused_half_sphere_500k_triangles(bencher: Bencher) {
    let g = half_sphere();
    let o = MirrorOptions {
        normal: Vec3::Z,
        ..MirrorOptions::default()
    };
    bencher
        .counter(ItemsCount::new(g.num_prims()))
        .bench(|| mirror(g, &o, &never).unwrap());
}

#[divan::bench(sample_count = 5)]
fn polyfill_half_sphere_500k_triangles(bencher: Bencher) {
    let g = half_sphere();
    bencher
        .counter(ItemsCount::new(g.num_prims()))
        .bench(|| polyfill(g, &FillOptions::default(), &never).unwrap());
}

/// A torus of 65,536 columns cut through its middle plane: two circles of
/// 65,536 points each, filled as one ring (holes on) or as two discs. In
/// f32 such a circle has thousands of flat corners, which the ear test
/// finds through its grid.
#[divan::bench(sample_count = 3, args = [true, false])]
fn polyfill_cut_torus_two_65k_point_loops(bencher: Bencher, holes: bool) {
    static G: OnceLock<Geometry> = OnceLock::new();
    let g = G.get_or_init(|| {
        let torus = primitives::torus(1.0, 0.25, 65_536, 4);
        clip(&torus, &ClipOptions::default(), &never)
            .unwrap()
            .geometry
    });
    let o = FillOptions {
        holes,
        ..FillOptions::default()
    };
    bencher
        .counter(ItemsCount::new(2 * 65_536usize))
        .bench(|| polyfill(g, &o, &never).unwrap());
}
