//! A triangle mesh as a signed distance field: building its hierarchy, and
//! evaluating it (closest point plus winding number) at points near the
//! surface and through the box, at 20k, 320k and 1.3M triangles (a wavy
//! sphere: every triangle different, as a scanned or sculpted part is).
//! Run: cargo bench -p geode-frep --bench mesh_field

use divan::counter::ItemsCount;
use divan::Bencher;
use geode_frep::{Field, MeshDistance, PointEval, Tape};

#[path = "support/uniform.rs"]
mod uniform;
#[path = "support/wavy_sphere.rs"]
mod wavy_sphere;
use wavy_sphere::wavy_sphere;

fn main() {
    divan::main();
}

const RINGS: [u32; 3] = [70, 280, 570];

#[divan::bench(args = RINGS, sample_count = 5)]
fn build(bencher: Bencher, rings: u32) {
    let (p, t) = wavy_sphere(rings);
    bencher
        .counter(ItemsCount::new(t.len()))
        .bench(|| MeshDistance::new(p.clone(), t.clone(), &|| false).unwrap());
}

/// Points in a shell around the surface (where a mesher evaluates), and
/// through the whole box.
fn points(near: bool) -> Vec<[f64; 3]> {
    let mut next = uniform::uniform();
    (0..10_000)
        .map(|_| {
            let d = [next() - 0.5, next() - 0.5, next() - 0.5];
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let r = if near {
                0.97 + 0.06 * next()
            } else {
                1.6 * next()
            };
            d.map(|v| v / len * r)
        })
        .collect()
}

fn eval(bencher: Bencher, rings: u32, near: bool) {
    let (p, t) = wavy_sphere(rings);
    let field = Field::mesh(MeshDistance::new(p, t, &|| false).unwrap());
    let tape = Tape::compile(&field);
    let at = points(near);
    bencher.counter(ItemsCount::new(at.len())).bench(|| {
        let mut ev = PointEval::new(&tape);
        at.iter().map(|&q| ev.eval(q)).sum::<f64>()
    });
}

#[divan::bench(args = RINGS, sample_count = 10)]
fn eval_near_surface(bencher: Bencher, rings: u32) {
    eval(bencher, rings, true);
}

#[divan::bench(args = RINGS, sample_count = 10)]
fn eval_through_box(bencher: Bencher, rings: u32) {
    eval(bencher, rings, false);
}
