//! polyreduce at a realistic size (run: cargo bench -p geode-model --bench
//! reduce): a 2M-triangle ridged sphere to 10%. The bar is pymeshlab's
//! quadric edge collapse on the same mesh (`cargo run --release -p
//! geode-model --example reduce_vs_pymeshlab` times both in one run).

use divan::Bencher;
use geode_geo::{ops, primitives, Geometry};
use geode_model::reduce::{reduce, Reduce, Target};

/// The allocator the geode binary runs with.
#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

fn main() {
    divan::main();
}

/// A UV sphere of about `triangles` triangles with creased ridges (the
/// example's mesh).
fn ridged_sphere(triangles: u32) -> Geometry {
    let rows = ((triangles / 4) as f32).sqrt() as u32;
    let mut g = ops::triangulate(&primitives::uv_sphere(1.0, 2 * rows, rows), None);
    for p in g.positions_mut() {
        let n = p.normalize();
        let bump = ((5.0 * n.x).sin() * (5.0 * n.y).sin() * (5.0 * n.z).cos()).abs();
        *p = n * (1.0 + 0.08 * bump);
    }
    g
}

#[divan::bench(sample_count = 3)]
fn polyreduce_2m_triangles_to_10_percent(bencher: Bencher) {
    let g = ridged_sphere(2_000_000);
    let how = Reduce {
        target: Target::Percent(10.0),
        ..Reduce::default()
    };
    bencher.bench(|| reduce(&g, &how, &|| false).unwrap());
}
