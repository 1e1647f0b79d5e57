//! polyreduce at a realistic size (run: cargo bench -p geode-model --bench
//! reduce): a 2M-triangle ridged sphere to 10%. The bar is pymeshlab's
//! quadric edge collapse on the same mesh (`cargo run --release -p
//! geode-model --example reduce_vs_pymeshlab` times both in one run).

use divan::Bencher;
use geode_model::reduce::{reduce, Reduce, Target};

/// The allocator the geode binary runs with.
#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

#[path = "../tests/common/meshes.rs"]
mod meshes;
use meshes::ridged_sphere;

fn main() {
    divan::main();
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
