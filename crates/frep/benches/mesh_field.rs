//! A triangle mesh as a signed distance field: building its hierarchy, and
//! evaluating it (closest point plus winding number) at points near the
//! surface and through the box, at 20k, 320k and 1.3M triangles (a wavy
//! sphere: every triangle different, as a scanned or sculpted part is).
//! Run: cargo bench -p geode-frep --bench mesh_field

use divan::counter::ItemsCount;
use divan::Bencher;
use geode_frep::{Field, MeshDistance, PointEval, Tape};

fn main() {
    divan::main();
}

/// A UV sphere of radius about 1 with `n` rings (4 n^2 triangles), its
/// radius rippled so no two rings are alike.
fn wavy_sphere(n: u32) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let pi = std::f32::consts::PI;
    let radius = |th: f32, ph: f32| 1.0 + 0.05 * (7.0 * th).sin() * (5.0 * ph).cos();
    let mut p = vec![[0.0, 0.0, radius(0.0, 0.0)]];
    for i in 1..n {
        let th = pi * i as f32 / n as f32;
        for j in 0..2 * n {
            let ph = pi * j as f32 / n as f32;
            let r = radius(th, ph);
            p.push([
                r * th.sin() * ph.cos(),
                r * th.sin() * ph.sin(),
                r * th.cos(),
            ]);
        }
    }
    p.push([0.0, 0.0, -radius(pi, 0.0)]);
    let ring = |i: u32, j: u32| 1 + (i - 1) * 2 * n + j % (2 * n);
    let last = p.len() as u32 - 1;
    let mut t = Vec::new();
    for j in 0..2 * n {
        t.push([0, ring(1, j), ring(1, j + 1)]);
        t.push([last, ring(n - 1, j + 1), ring(n - 1, j)]);
    }
    for i in 1..n - 1 {
        for j in 0..2 * n {
            t.push([ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)]);
            t.push([ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)]);
        }
    }
    (p, t)
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
    let mut s = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
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
