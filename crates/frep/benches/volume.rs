//! Fields as narrow-band level sets: sampling a blend of primitives over a
//! box of 256^3, 512^3 and 1024^3 voxels, a 320k-triangle mesh's field at
//! 512^3 (the sampled form of a huge mesh), and evaluating the sampled
//! field near its surface (what a mesher asks of it).
//! Run: cargo bench -p geode-frep --bench volume

use divan::counter::ItemsCount;
use divan::Bencher;
use geode_frep::{
    shapes, Field, MeshDistance, PointEval, SampleOptions, SamplePlan, Tape, VolumeField,
};

#[path = "support/uniform.rs"]
mod uniform;
#[path = "support/wavy_sphere.rs"]
mod wavy_sphere;

fn main() {
    divan::main();
}

fn blend() -> Field {
    shapes::blend_union(
        &shapes::torus([0.0; 3], 0.6, 0.2),
        &shapes::sphere([0.3, 0.3, 0.2], 0.4),
        [0.1, 1.0, 1.0],
    )
}

fn options(voxels: u32) -> SampleOptions {
    SampleOptions {
        min: [-1.0; 3],
        max: [1.0; 3],
        voxel_size: 2.0 / voxels as f64,
        half_width: 3.0,
        memory_budget: 16 << 30,
    }
}

fn sample(f: &Field, voxels: u32) -> geode_geo::volume::SparseVolume {
    let plan = SamplePlan::new(f, options(voxels), &|| false).unwrap();
    plan.sample(f, "surface", &|| false).unwrap()
}

#[divan::bench(args = [256, 512, 1024], sample_count = 3, sample_size = 1)]
fn sample_blend(bencher: Bencher, voxels: u32) {
    let f = blend();
    let leaves = sample(&f, voxels).leaves().len();
    bencher
        .counter(ItemsCount::new(leaves * 512))
        .bench(|| sample(&f, voxels));
}

#[divan::bench(sample_count = 3, sample_size = 1)]
fn sample_mesh_320k_triangles(bencher: Bencher) {
    let (p, t) = wavy_sphere::wavy_sphere(280);
    let f = Field::mesh(MeshDistance::new(p, t, &|| false).unwrap());
    let leaves = sample(&f, 512).leaves().len();
    bencher
        .counter(ItemsCount::new(leaves * 512))
        .bench(|| sample(&f, 512));
}

#[divan::bench(sample_count = 5)]
fn evaluate_near_surface(bencher: Bencher) {
    let volume = sample(&blend(), 512);
    let tape = Tape::compile(&Field::volume(VolumeField::new(volume)));
    let mut next = uniform::uniform();
    // Points on the torus's tube, a little in and out.
    let at: Vec<[f64; 3]> = (0..10_000)
        .map(|_| {
            let (a, b) = (
                next() * std::f64::consts::TAU,
                next() * std::f64::consts::TAU,
            );
            let r = 0.2 + 0.02 * (next() - 0.5);
            [
                (0.6 + r * b.cos()) * a.cos(),
                r * b.sin(),
                (0.6 + r * b.cos()) * a.sin(),
            ]
        })
        .collect();
    bencher.counter(ItemsCount::new(at.len())).bench(|| {
        let mut ev = PointEval::new(&tape);
        at.iter().map(|&q| ev.eval(q)).sum::<f64>()
    });
}
