//! Isotropic remeshing at the size, default ten iterations, to the
//! edge length that gives about a million triangles back: a box of a
//! million right triangles (its twelve edges and eight corners kept), and
//! a triangulated UV sphere of a million (a hard input: its pole bands
//! are slivers a hundred times shorter than the target, so most of the
//! work is collapsing them), uniform and adaptive.
//! Run: cargo bench -p geode-model --bench remesh

use divan::counter::ItemsCount;
use divan::Bencher;
use geode_model::remesh::{remesh, RemeshOptions, Sizing};

#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

#[path = "../tests/common/meshes.rs"]
mod meshes;
use meshes::{equilateral_length, million_triangles};

fn main() {
    divan::main();
}

fn never() -> bool {
    false
}

#[divan::bench(
    args = ["box uniform", "box adaptive", "sphere uniform", "sphere adaptive"],
    sample_count = 1,
    sample_size = 1
)]
fn remesh_1m_triangles(bencher: Bencher, case: &str) {
    let (shape, sizing) = case.split_once(' ').expect("shape and sizing");
    let (g, area) = million_triangles(shape);
    let l = equilateral_length(area, 1e6);
    let sizing = match sizing {
        "uniform" => Sizing::Uniform { length: l },
        _ => Sizing::Adaptive {
            min: l * 0.5,
            max: l * 2.0,
            tolerance: 1e-5,
            gradation: 0.5,
        },
    };
    let opts = RemeshOptions {
        sizing,
        relative: false,
        ..RemeshOptions::default()
    };
    bencher
        .counter(ItemsCount::new(g.num_prims()))
        .bench_local(|| remesh(&g, &opts, &never).unwrap());
}
