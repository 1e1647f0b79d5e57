//! The wire family at realistic sizes: polywire on about 100k edges (a
//! 224 x 224 point grid's edges, every inner point a joint of four, and
//! 1000 polylines of 101 points, mitres only), edge_divide on a 1M-edge
//! quad sphere, divide on 100k polygons (L-shaped hexagons made convex,
//! and a 100k-quad sphere cut into bricks).
//! Run: cargo bench -p geode-model --bench wire

use std::sync::OnceLock;

use divan::counter::ItemsCount;
use divan::Bencher;
use geode_geo::glam::{Vec2, Vec3};
use geode_geo::{primitives, Geometry, PrimKind};
use geode_model::divide::{bricker, convex_polygons, DivideOptions};
use geode_model::edge_divide::{edge_divide, EdgeDivideOptions};
use geode_model::polywire::{polywire, PolywireOptions};

/// The allocator the geode binary runs with.
#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

fn main() {
    divan::main();
}

fn never() -> bool {
    false
}

/// 1000 wavy polylines of 101 points: 100k edges.
fn curves() -> Geometry {
    let mut pts = Vec::new();
    for c in 0..1000 {
        for k in 0..101 {
            let t = k as f32 * 0.05;
            pts.push(Vec3::new(
                c as f32 * 0.3 + (t * 2.0).sin() * 0.1,
                t,
                (t * 3.0 + c as f32).cos() * 0.1,
            ));
        }
    }
    let verts: Vec<u32> = (0..pts.len() as u32).collect();
    Geometry::from_prims(pts, verts, &[101; 1000], vec![PrimKind::Polyline; 1000]).unwrap()
}

#[divan::bench(sample_count = 3, args = ["grid", "curves"])]
fn polywire_100k_edges(bencher: Bencher, shape: &str) {
    let g = if shape == "grid" {
        primitives::grid(Vec2::splat(10.0), 224, 224)
    } else {
        curves()
    };
    let o = PolywireOptions {
        radius: 0.005,
        ..PolywireOptions::default()
    };
    bencher
        .counter(ItemsCount::new(g.num_vertices()))
        .bench(|| polywire(&g, None, &o, &never).unwrap());
}

/// A quad sphere of 1000 x 500: about 1M edges.
fn sphere() -> &'static Geometry {
    static G: OnceLock<Geometry> = OnceLock::new();
    G.get_or_init(|| primitives::uv_sphere(1.0, 1000, 501))
}

#[divan::bench(sample_count = 5)]
fn edge_divide_1m_edges(bencher: Bencher) {
    let g = sphere();
    let o = EdgeDivideOptions {
        divisions: 2,
        group_name: Some("new".into()),
    };
    bencher
        .counter(ItemsCount::new(g.num_vertices() / 2))
        .bench(|| edge_divide(g, None, &o, &never).unwrap());
}

/// 100k disjoint L-shaped hexagons.
fn hexagons() -> Geometry {
    let ring = [
        (0.0, 0.0),
        (2.0, 0.0),
        (2.0, 1.0),
        (1.0, 1.0),
        (1.0, 2.0),
        (0.0, 2.0),
    ];
    let mut pts = Vec::new();
    for k in 0..100_000 {
        let (x, y) = ((k % 316) as f32 * 3.0, (k / 316) as f32 * 3.0);
        pts.extend(ring.iter().map(|&(a, b)| Vec3::new(x + a, y + b, 0.0)));
    }
    let verts: Vec<u32> = (0..pts.len() as u32).collect();
    Geometry::from_prims(pts, verts, &[6; 100_000], vec![PrimKind::Polygon; 100_000]).unwrap()
}

#[divan::bench(sample_count = 5)]
fn divide_convex_100k_polygons(bencher: Bencher) {
    let g = hexagons();
    bencher
        .counter(ItemsCount::new(g.num_prims()))
        .bench(|| convex_polygons(&g, &DivideOptions::default(), &never).unwrap());
}

#[divan::bench(sample_count = 5)]
fn divide_bricker_100k_quads(bencher: Bencher) {
    let g = primitives::uv_sphere(1.0, 400, 251);
    bencher
        .counter(ItemsCount::new(g.num_prims()))
        .bench(|| bricker(&g, Vec3::splat(0.1), Vec3::ZERO, &never).unwrap());
}
