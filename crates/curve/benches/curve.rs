//! Curve kernels at realistic sizes: frames along a long helix, sweeping it
//! into a tube, and a million packed copies of a 10k-triangle object
//! (memory per copy printed: a transform, not a mesh).
//! Run: cargo bench -p geode-curve --bench curve

use geode_curve::frames::{frames, tangents, FrameMethod, TangentMode};
use geode_curve::shapes::helix;
use geode_curve::{copy_to_points, sweep, CopyOptions, SweepOptions};
use geode_geo::{primitives, Geometry};

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
