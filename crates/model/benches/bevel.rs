//! polybevel at realistic sizes (run: cargo bench -p geode-model --bench
//! bevel): a box of about 100k quads with every edge bevelled (each point
//! a four-edge corner), and the same box with only its 12 sharp edges
//! rounded in 4 segments (long welded strips through flat points).

use divan::Bencher;
use geode_geo::glam::Vec3;
use geode_geo::{primitives, Geometry};
use geode_model::bevel::{bevel, Bevel};

/// The allocator the geode binary runs with.
#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

fn main() {
    divan::main();
}

/// 6 x 130^2 = 101,400 quads.
fn divided_box() -> Geometry {
    primitives::box_mesh(Vec3::ONE, [130, 130, 130])
}

#[divan::bench(args = [1, 2], sample_count = 3)]
fn bevel_every_edge_of_100k_quads(bencher: Bencher, segments: u32) {
    let g = divided_box();
    let how = Bevel {
        offset: 0.001,
        segments,
        ..Bevel::default()
    };
    bencher.bench(|| bevel(&g, None, &how, &|| false).unwrap());
}

#[divan::bench(sample_count = 3)]
fn round_the_sharp_edges_of_100k_quads(bencher: Bencher) {
    let g = divided_box();
    let how = Bevel {
        offset: 0.05,
        segments: 4,
        flat_angle: Some(2.0),
        ..Bevel::default()
    };
    bencher.bench(|| bevel(&g, None, &how, &|| false).unwrap());
}
