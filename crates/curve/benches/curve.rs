//! Curve kernels at realistic sizes: frames along a long helix, sweeping it
//! into a tube, a million packed copies of a 10k-triangle object (memory
//! per copy printed: a transform, not a mesh), and PolyPath joining a
//! million grown segments into branches.
//! Run: cargo bench -p geode-curve --bench curve

use geode_curve::frames::{frames, tangents, FrameMethod, TangentMode};
use geode_curve::shapes::helix;
use geode_curve::{copy_to_points, polypath, sweep, CopyOptions, PolyPathOptions, SweepOptions};
use geode_geo::glam::Vec3;
use geode_geo::{primitives, Geometry, PrimKind};

fn main() {
    let source = primitives::uv_sphere(1.0, 100, 51);
    let template = primitives::grid(geode_geo::glam::Vec2::splat(100.0), 999, 999);
    let opts = CopyOptions {
        packed: true,
        piece_attrib: String::new(),
        variant_attrib: String::new(),
    };
    let copies = copy_to_points(&source, &template, &opts, &|| false).unwrap();
    eprintln!(
        "{} packed copies of a {}-polygon sphere: {:.1} MB ({} bytes per copy; the sphere alone is {} bytes)",
        copies.num_prims(),
        source.num_prims(),
        copies.memory_bytes() as f64 / 1e6,
        (copies.memory_bytes() - source.memory_bytes()) / copies.num_prims(),
        source.memory_bytes()
    );
    divan::main();
}

#[divan::bench(args = [10_000, 1_000_000])]
fn frames_double_reflection(bencher: divan::Bencher, n: usize) {
    let h = helix(1.0, 0.3, 50.0, n);
    bencher.bench(|| {
        frames(
            &h.points,
            &h.tangents,
            false,
            FrameMethod::DoubleReflection,
            None,
        )
    });
}

#[divan::bench(args = [10_000, 1_000_000])]
fn frames_parallel_transport_central(bencher: divan::Bencher, n: usize) {
    let h = helix(1.0, 0.3, 50.0, n);
    bencher.bench(|| {
        let t = tangents(&h.points, false, TangentMode::Central);
        frames(&h.points, &t, false, FrameMethod::ParallelTransport, None)
    });
}

#[divan::bench(args = [10_000, 100_000])]
fn sweep_circle_16(bencher: divan::Bencher, n: usize) {
    let h = helix(1.0, 0.3, 50.0, n);
    let f = frames(
        &h.points,
        &h.tangents,
        false,
        FrameMethod::DoubleReflection,
        None,
    );
    let radii = vec![0.05; n];
    let opts = SweepOptions::circle(16, true);
    bencher.bench(|| sweep(&h.points, &f, &radii, false, &opts, &|| false));
}

#[divan::bench(args = [100_000, 1_000_000], sample_count = 5)]
fn copy_packed_10k_triangle_sphere(bencher: divan::Bencher, n: usize) {
    let source = primitives::uv_sphere(1.0, 100, 51);
    let side = (n as f64).sqrt() as u32;
    let template: Geometry =
        primitives::grid(geode_geo::glam::Vec2::splat(100.0), side - 1, side - 1);
    let opts = CopyOptions {
        packed: true,
        piece_attrib: String::new(),
        variant_attrib: String::new(),
    };
    bencher.bench(|| copy_to_points(&source, &template, &opts, &|| false).unwrap());
}

/// A tree of `n` two-point segments as a growth wrangle writes them (each
/// new point a segment from its parent): a point continues the last one,
/// every eighth branches off an earlier point.
fn grown_segments(n: usize) -> Geometry {
    let mut positions = vec![Vec3::ZERO];
    let mut vertex_points = Vec::with_capacity(2 * n);
    let mut h: u64 = 0x9E37_79B9_7F4A_7C15;
    for i in 1..=n {
        h ^= h << 13;
        h ^= h >> 7;
        h ^= h << 17;
        let parent = if i % 8 == 0 {
            (h % i as u64) as usize
        } else {
            i - 1
        };
        let step = Vec3::new(
            (h & 0xff) as f32 / 255.0 - 0.5,
            1.0,
            (h >> 8 & 0xff) as f32 / 255.0 - 0.5,
        );
        positions.push(positions[parent] + step * 0.01);
        vertex_points.extend([parent as u32, i as u32]);
    }
    Geometry::from_prims(
        positions,
        vertex_points,
        &vec![2; n],
        vec![PrimKind::Polyline; n],
    )
    .unwrap()
}

#[divan::bench(args = [100_000, 1_000_000], sample_count = 5)]
fn polypath_grown_segments(bencher: divan::Bencher, n: usize) {
    let g = grown_segments(n);
    bencher.bench(|| polypath(&g, &PolyPathOptions::default(), &|| false).unwrap());
}
