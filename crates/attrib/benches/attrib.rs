//! The attribute kernels at the sizes the issue names: transfer from 1M to
//! 1M points, blur of 1M points (10 iterations), curvature on 1M points,
//! promotion of 1M points to their primitives, connectivity of 1M
//! primitives (geode-geo's, timed here beside its users).
//! Run: cargo bench -p geode-attrib --bench attrib

use std::sync::OnceLock;

use divan::Bencher;
use geode_attrib::blur::{blur, point_neighbours, Mode};
use geode_attrib::kdtree::KdTree;
use geode_attrib::measure::curvature;
use geode_attrib::promote::{promote, Combine};
use geode_attrib::transfer::{apply, from_points, Reach};
use geode_geo::glam::Vec3;
use geode_geo::ops::{connectivity, Connect};
use geode_geo::{primitives, AttribClass, AttribData, Attribute, Geometry, TypeInfo};

/// The allocator the geode binary runs with.
#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

fn main() {
    divan::main();
}

const NONE: &(dyn Fn() -> bool + Sync) = &|| false;

/// A 1000 x 1000 torus of quads: 1.0M points, 1.0M primitives.
fn torus_1m() -> &'static Geometry {
    static G: OnceLock<Geometry> = OnceLock::new();
    G.get_or_init(|| primitives::torus(2.0, 0.6, 1000, 1000))
}

/// 1M scattered points (a scan's worth), seeded.
fn cloud_1m(seed: u64) -> Vec<Vec3> {
    (0..1_000_000u64)
        .map(|i| {
            Vec3::from_array(std::array::from_fn(|k| {
                geode_geo::random::unit(seed, i, k as u64) * 4.0 - 2.0
            }))
        })
        .collect()
}

fn colours(n: usize) -> Attribute {
    let v: Vec<Vec3> = (0..n)
        .map(|i| Vec3::new((i % 7) as f32, (i % 11) as f32, (i % 13) as f32) / 13.0)
        .collect();
    Attribute::from_data(AttribData::Vec3(v), TypeInfo::Color)
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn transfer_1m_to_1m_points(bencher: Bencher) {
    let src = cloud_1m(1);
    let dst = cloud_1m(2);
    let cd = colours(src.len());
    let reach = Reach {
        threshold: f32::INFINITY,
        blend_width: 0.0,
        samples: 1,
    };
    bencher.bench(|| {
        let tree = KdTree::new(&src);
        let s = from_points(&tree, &dst, &reach, NONE).unwrap();
        apply(&s, &cd, None)
    });
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn transfer_1m_to_1m_points_4_samples(bencher: Bencher) {
    let src = cloud_1m(1);
    let dst = cloud_1m(2);
    let cd = colours(src.len());
    let reach = Reach {
        threshold: 0.05,
        blend_width: 0.05,
        samples: 4,
    };
    bencher.bench(|| {
        let tree = KdTree::new(&src);
        let s = from_points(&tree, &dst, &reach, NONE).unwrap();
        apply(&s, &cd, None)
    });
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn blur_1m_points_10_iterations(bencher: Bencher) {
    let g = torus_1m();
    let cd = colours(g.num_points());
    bencher.bench(|| {
        let n = point_neighbours(g);
        blur(&cd, &n, 10, 0.5, Mode::Laplacian, None, NONE).unwrap()
    });
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn curvature_1m_points(bencher: Bencher) {
    let g = torus_1m();
    bencher.bench(|| curvature(g, NONE).unwrap());
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn promote_1m_points_to_primitives(bencher: Bencher) {
    let g = torus_1m();
    let cd = colours(g.num_points());
    bencher.bench(|| {
        promote(
            g,
            &cd,
            AttribClass::Point,
            AttribClass::Primitive,
            Combine::Average,
            NONE,
        )
        .unwrap()
    });
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn connectivity_1m_primitives(bencher: Bencher) {
    // 10,000 separate 10 x 10 grids: 1.0M primitives in 10,000 pieces.
    static G: OnceLock<Geometry> = OnceLock::new();
    let g = G.get_or_init(|| {
        let tile = primitives::grid(geode_geo::glam::Vec2::ONE, 10, 10);
        let tiles: Vec<Geometry> = (0..10_000)
            .map(|k| {
                let mut t = tile.clone();
                for p in t.positions_mut() {
                    *p += Vec3::new((k % 100) as f32 * 2.0, 0.0, (k / 100) as f32 * 2.0);
                }
                t
            })
            .collect();
        let refs: Vec<&Geometry> = tiles.iter().collect();
        geode_geo::ops::merge(&refs).unwrap()
    });
    assert_eq!(g.num_prims(), 1_000_000);
    bencher.bench(|| {
        let p = connectivity(g, Connect::SharedPoint, None);
        assert_eq!(p.count, 10_000);
        p
    });
}
