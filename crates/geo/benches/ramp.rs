//! Ramp evaluation: a million lookups per basis over a six-key ramp (a
//! sweep's or remap's per-point cost), and a colour ramp.
//! Run: cargo bench -p geode-geo --bench ramp

use divan::counter::ItemsCount;
use divan::Bencher;
use geode_geo::{Ramp, RampBasis, RampKey, RampKind};

const N: usize = 1_000_000;

fn main() {
    divan::main();
}

fn ramp(kind: RampKind, basis: RampBasis) -> Ramp {
    let keys = [
        (0.0, 0.1),
        (0.15, 0.9),
        (0.4, 0.3),
        (0.55, 0.8),
        (0.8, 0.2),
        (1.0, 1.0),
    ];
    Ramp::new(
        kind,
        keys.iter()
            .map(|&(p, v)| RampKey::color(p, [v, 1.0 - v, 0.5 * v], basis))
            .collect(),
    )
    .unwrap()
}

fn positions() -> Vec<f64> {
    // A fixed scramble of 0..1, so the key search is not predicted.
    (0..N)
        .map(|i| {
            ((i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11) as f64 / (1u64 << 53) as f64
        })
        .collect()
}

#[divan::bench(args = ["constant", "linear", "catmull-rom", "monotonecubic", "bspline"])]
fn float_1m(bencher: Bencher, basis: &str) {
    let r = ramp(RampKind::Float, RampBasis::from_name(basis).unwrap());
    let xs = positions();
    bencher
        .counter(ItemsCount::new(N))
        .bench(|| xs.iter().map(|&x| r.eval_float(x)).sum::<f64>());
}

#[divan::bench(args = ["linear", "catmull-rom", "bspline"])]
fn color_1m(bencher: Bencher, basis: &str) {
    let r = ramp(RampKind::Color, RampBasis::from_name(basis).unwrap());
    let xs = positions();
    bencher
        .counter(ItemsCount::new(N))
        .bench(|| xs.iter().map(|&x| r.eval(x)[1]).sum::<f64>());
}
