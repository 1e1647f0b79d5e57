//! Evaluation throughput of the tape evaluators on realistic fields.
//! Run: cargo bench -p geode-frep --bench eval

use divan::counter::ItemsCount;
use divan::Bencher;
use geode_frep::{
    BatchEval, BatchGradEval, Field, Grad, GradEval, Interval, IntervalEval, PointEval, Tape,
};

fn main() {
    divan::main();
}

const N: usize = 1 << 20;

fn gyroid() -> Field {
    let (x, y, z) = (Field::x() * 6.0, Field::y() * 6.0, Field::z() * 6.0);
    x.sin() * y.cos() + y.sin() * z.cos() + z.sin() * x.cos()
}

/// A union of 200 spheres placed on a spiral.
fn spheres() -> Field {
    geode_frep::shapes::union_all((0..200).map(|i| {
        let t = i as f64 * 0.1;
        let (cx, cy, cz) = (t.cos() * 0.6, t.sin() * 0.6, i as f64 / 200.0 - 0.5);
        0.01 - ((Field::x() - cx).square()
            + (Field::y() - cy).square()
            + (Field::z() - cz).square())
    }))
    .expect("200 spheres")
}

fn colonnade() -> Field {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../corpus/fidget-models/colonnade.vm"
    ))
    .unwrap();
    geode_frep::parse_vm(&text).unwrap()
}

/// The gyroid part's superellipsoid as a signed distance (symbolic
/// gradient and two Newton steps: what offsets and shells evaluate).
fn superellipsoid_distance() -> Field {
    let part = geode_frep::shapes::superellipsoid([0.0; 3], [0.9, 0.6, 0.6], 0.3, 0.3);
    geode_frep::distance::signed_distance(&part)
}

fn grid() -> (Vec<f32>, Vec<f32>, Vec<f32>) {
    let n = 128usize;
    let mut xs = Vec::with_capacity(N);
    let mut ys = Vec::with_capacity(N);
    let mut zs = Vec::with_capacity(N);
    for i in 0..N {
        xs.push((i % n) as f32 / n as f32 * 2.0 - 1.0);
        ys.push((i / n % n) as f32 / n as f32 * 2.0 - 1.0);
        zs.push((i / n / n) as f32 / 64.0 * 2.0 - 1.0);
    }
    (xs, ys, zs)
}

#[divan::bench(args = ["gyroid", "spheres200", "colonnade", "superellipsoid_distance"], sample_count = 5)]
fn batch_1m_points(bencher: Bencher, which: &str) {
    let f = match which {
        "gyroid" => gyroid(),
        "spheres200" => spheres(),
        "superellipsoid_distance" => superellipsoid_distance(),
        _ => colonnade(),
    };
    let tape = Tape::compile(&f);
    let (xs, ys, zs) = grid();
    let mut out = vec![0.0f32; N];
    let mut ev = BatchEval::new(&tape);
    bencher
        .counter(ItemsCount::new(N))
        .bench_local(|| ev.eval(&xs, &ys, &zs, &mut out));
}

#[divan::bench(args = ["gyroid", "spheres200"], sample_count = 5)]
fn point_and_gradient_64k(bencher: Bencher, which: &str) {
    let f = if which == "gyroid" {
        gyroid()
    } else {
        spheres()
    };
    let tape = Tape::compile(&f);
    let (xs, ys, zs) = grid();
    let mut p = PointEval::new(&tape);
    let mut g = GradEval::new(&tape);
    bencher
        .counter(ItemsCount::new(1usize << 16))
        .bench_local(|| {
            let mut s = 0.0;
            for i in 0..1 << 16 {
                let q = [xs[i] as f64, ys[i] as f64, zs[i] as f64];
                s += p.eval(q) + g.eval(q).d[0];
            }
            s
        });
}

/// Values and exact gradients of 64k points in batches, as the mesher asks
/// for them at edge crossings and split points.
#[divan::bench(args = ["gyroid", "spheres200", "colonnade"], sample_count = 5)]
fn batch_gradient_64k(bencher: Bencher, which: &str) {
    let f = match which {
        "gyroid" => gyroid(),
        "spheres200" => spheres(),
        _ => colonnade(),
    };
    let tape = Tape::compile(&f);
    let (xs, ys, zs) = grid();
    let points: Vec<[f64; 3]> = (0..1 << 16)
        .map(|i| [xs[i] as f64, ys[i] as f64, zs[i] as f64])
        .collect();
    let mut out = vec![Grad::default(); points.len()];
    let mut g = BatchGradEval::new(&tape);
    bencher
        .counter(ItemsCount::new(points.len()))
        .bench_local(|| g.eval(&points, &mut out));
}

#[divan::bench(sample_count = 5)]
fn interval_and_simplify_spheres200(bencher: Bencher) {
    let tape = Tape::compile(&spheres());
    let mut iv = IntervalEval::new(&tape);
    bencher.counter(ItemsCount::new(512usize)).bench_local(|| {
        let mut kept = 0;
        for i in 0..512 {
            let c = [
                (i % 8) as f64 / 4.0 - 1.0,
                (i / 8 % 8) as f64 / 4.0 - 1.0,
                (i / 64) as f64 / 4.0 - 1.0,
            ];
            iv.eval(
                Interval::new(c[0], c[0] + 0.25),
                Interval::new(c[1], c[1] + 0.25),
                Interval::new(c[2], c[2] + 0.25),
            );
            kept += tape.simplify(iv.choices()).len();
        }
        kept
    });
}

/// As the mesher asks within a brick: 64k points of a brick-sized box of
/// the colonnade in batches of 48 (a brick's crossings), with the tape
/// simplified over the box (27 of 796 instructions).
#[divan::bench(sample_count = 5)]
fn batch_gradient_brick_batches(bencher: Bencher) {
    let tape = Tape::compile(&colonnade());
    let (lo, hi) = ([0.25, 0.0, 0.0], [0.375, 0.125, 0.125]);
    let mut iv = IntervalEval::new(&tape);
    iv.eval(
        Interval::new(lo[0], hi[0]),
        Interval::new(lo[1], hi[1]),
        Interval::new(lo[2], hi[2]),
    );
    let brick = tape.simplify(iv.choices());
    let points: Vec<[f64; 3]> = (0..1 << 16)
        .map(|i| {
            let t = [i % 41, i / 41 % 43, i / 1763 % 37].map(|k| k as f64);
            [
                0.25 + t[0] / 41.0 * 0.125,
                t[1] / 43.0 * 0.125,
                t[2] / 37.0 * 0.125,
            ]
        })
        .collect();
    let mut out = vec![Grad::default(); points.len()];
    let mut g = BatchGradEval::new(&brick);
    bencher
        .counter(ItemsCount::new(points.len()))
        .bench_local(|| {
            for (p, o) in points.chunks(48).zip(out.chunks_mut(48)) {
                g.eval(p, o);
            }
        });
}
