//! Benchmarks of the geometry operations at realistic sizes (10 million points).
//! Run: cargo bench -p geode-geo --bench geo_ops

use std::sync::OnceLock;

use divan::counter::{BytesCount, ItemsCount};
use divan::Bencher;
use geode_geo::glam::{Mat4, Quat, Vec2, Vec3};
use geode_geo::{ops, primitives, Geometry};

fn main() {
    divan::main();
}

/// A 3162 x 3162 quad grid: 10.0 million points, 10.0 million quads.
fn grid_10m() -> &'static Geometry {
    static G: OnceLock<Geometry> = OnceLock::new();
    G.get_or_init(|| {
        let mut g = primitives::grid(Vec2::splat(100.0), 3161, 3161);
        // A wavy surface so normals are not all equal.
        for p in g.positions_mut() {
            p.y = (p.x * 0.3).sin() * (p.z * 0.2).cos();
        }
        g
    })
}

fn column_bytes(g: &Geometry) -> u64 {
    (g.num_points() * 12
        + g.num_vertices() * 4
        + g.prim_offsets().len() * 4
        + g.num_prims()
        + g.num_points() * 8) as u64
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn content_hash(bencher: Bencher) {
    let g = grid_10m();
    // The clone (which drops the cached hash) happens outside the timing.
    bencher
        .counter(BytesCount::new(column_bytes(g)))
        .with_inputs(|| g.clone())
        .bench_local_values(|g| g.content_hash());
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn hash_bytes_single_thread(bencher: Bencher) {
    let data: Vec<u8> = (0..(1usize << 30)).map(|i| (i * 7) as u8).collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    bencher
        .counter(BytesCount::new(data.len()))
        .bench(|| pool.install(|| geode_geo::hash_bytes(&data)));
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn merge_two_5m(bencher: Bencher) {
    let half = {
        let mut g = primitives::grid(Vec2::splat(10.0), 2235, 2235);
        g.positions_mut()[0].y = 1.0;
        g
    };
    bencher
        .counter(ItemsCount::new(2 * half.num_points()))
        .bench(|| ops::merge(&[&half, &half]).unwrap());
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn transform_10m(bencher: Bencher) {
    let g = grid_10m();
    let m = Mat4::from_scale_rotation_translation(
        Vec3::new(1.0, 2.0, 3.0),
        Quat::from_rotation_y(0.3),
        Vec3::X,
    );
    bencher
        .counter(ItemsCount::new(g.num_points()))
        .with_inputs(|| g.clone())
        .bench_local_values(|mut g| {
            ops::transform(&mut g, m);
            assert_ne!(
                g.positions()[g.num_points() / 2],
                grid_10m().positions()[g.num_points() / 2]
            );
            g
        });
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn point_normals_10m(bencher: Bencher) {
    let g = grid_10m();
    bencher
        .counter(ItemsCount::new(g.num_points()))
        .bench(|| ops::point_normals(g));
}

#[divan::bench(sample_count = 3, sample_size = 1)]
fn triangulate_10m_quads(bencher: Bencher) {
    let g = grid_10m();
    bencher
        .counter(ItemsCount::new(g.num_prims()))
        .bench(|| ops::triangulate(g, None));
}

#[divan::bench(sample_count = 3, sample_size = 1)]
fn fuse_1m_split_triangles(bencher: Bencher) {
    // 333k triangles with unshared corners: fusing recovers the shared mesh.
    let base = ops::triangulate(&primitives::grid(Vec2::splat(10.0), 408, 408), None);
    let p = base.positions();
    let corners: Vec<Vec3> = base
        .vertex_points()
        .iter()
        .map(|&i| p[i as usize])
        .collect();
    let n = corners.len() as u32;
    let split =
        Geometry::from_polygons(corners, (0..n).collect(), &vec![3; (n / 3) as usize]).unwrap();
    bencher
        .counter(ItemsCount::new(split.num_points()))
        .with_inputs(|| split.clone())
        .bench_local_values(|mut g| {
            ops::fuse_points(&mut g, 1e-4);
            g
        });
}

#[divan::bench(sample_count = 3, sample_size = 1)]
fn topology_1m_quads(bencher: Bencher) {
    let g = primitives::grid(Vec2::splat(10.0), 1000, 1000);
    bencher
        .counter(ItemsCount::new(g.num_prims()))
        .bench(|| geode_geo::Topology::clone(&g.clone().topology()));
}

/// A sphere of 480,000 triangles (a cube's faces cut 200 x 200, pushed onto
/// the sphere) reduced within 0.001 of the radius, the distance measured
/// exactly: the collapses of adaptive meshing on their own.
#[divan::bench(sample_count = 5, sample_size = 1)]
fn reduce_sphere_480k(bencher: Bencher) {
    let cube = ops::triangulate(&primitives::box_mesh(Vec3::splat(2.0), [200; 3]), None);
    let positions: Vec<Vec3> = cube.positions().iter().map(|p| p.normalize()).collect();
    let tris: Vec<[u32; 3]> = (0..cube.num_prims())
        .map(|p| {
            let pts = cube.prim_points(p);
            [pts[0], pts[1], pts[2]]
        })
        .collect();
    let measure = |points: &[Vec3], out: &mut [f32]| {
        for (p, o) in points.iter().zip(out) {
            *o = p.length() - 1.0;
        }
    };
    let opts = ops::ReduceOptions::new(0.001);
    bencher
        .counter(ItemsCount::new(tris.len()))
        .bench(|| ops::reduce_triangles(&positions, &tris, &opts, &measure, &|| false).unwrap());
}

/// The viewport's reduction: the wavy 20-million-triangle grid clustered to
/// 3 million triangles.
#[divan::bench(sample_count = 3, sample_size = 1)]
fn cluster_20m_triangles_to_3m(bencher: Bencher) {
    let g = grid_10m();
    bencher
        .counter(ItemsCount::new(ops::fan_triangle_count(g)))
        .bench(|| ops::cluster_triangles(g, 3_000_000));
}

/// A 360k-triangle sphere's hierarchy and 100k query points: near the
/// surface (within 0.01, what transfer between similar meshes asks) or far
/// from it (1.5 to 3 radii from the centre, what ray's minimum distance
/// asks of points above a surface; boxes bound a smooth minimum loosely).
fn closest_setup(far: bool) -> (ops::TriangleBvh, Vec<Vec3>) {
    let s = ops::triangulate(&primitives::uv_sphere(1.0, 600, 300), None);
    let tris: Vec<[u32; 3]> = (0..s.num_prims())
        .map(|p| {
            let v = s.prim_points(p);
            [v[0], v[1], v[2]]
        })
        .collect();
    let bvh = ops::TriangleBvh::new(s.positions(), &tris);
    let mut state = 7u32;
    let mut r = || {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (state >> 8) as f32 / (1u32 << 24) as f32
    };
    let queries = (0..100_000)
        .map(|_| {
            let d = Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5).normalize_or(Vec3::Y);
            let radius = if far {
                1.5 + 1.5 * r()
            } else {
                1.0 + 0.02 * (r() - 0.5)
            };
            d * radius
        })
        .collect();
    (bvh, queries)
}

#[divan::bench(args = [false, true], sample_count = 5, sample_size = 1)]
fn closest_100k_on_360k_triangles(bencher: Bencher, far: bool) {
    let (bvh, queries) = closest_setup(far);
    bencher.counter(ItemsCount::new(queries.len())).bench(|| {
        use rayon::prelude::*;
        queries
            .par_iter()
            .map(|&q| bvh.closest(q, f32::INFINITY).map_or(0.0, |c| c.dist2))
            .sum::<f32>()
    });
}
