//! One shared suite run against every evaluator: for every operation, the
//! batch (f32), interval and gradient evaluators agree with single-point
//! evaluation (itself checked against walking the DAG), intervals always
//! contain the point values, and simplified tapes agree inside their region.

use geode_frep::{
    BatchEval, BatchGradEval, Binary, Field, Grad, GradEval, Interval, IntervalEval, PointEval,
    Tape, Unary,
};
use proptest::prelude::*;

/// Fields exercising every operation, with arguments kept mostly in range.
fn cases() -> Vec<(String, Field)> {
    let (x, y, z) = (Field::x(), Field::y(), Field::z());
    let r = (&x * &x + &y * &y + &z * &z).sqrt();
    let smooth = &x * 0.7 + &y * 0.3 - &z * 0.2;
    let mut v: Vec<(String, Field)> = Vec::new();
    for op in Unary::ALL {
        let arg = match op {
            Unary::Sqrt | Unary::Ln => &r + 0.1,
            Unary::Asin | Unary::Acos => (&smooth * 0.3).sin(),
            Unary::Tan => &smooth * 0.4,
            Unary::Not => (&x * 2.0).round(),
            _ => smooth.clone(),
        };
        v.push((format!("{op:?}"), arg.unary(op)));
    }
    for op in Binary::ALL {
        let (a, b) = match op {
            Binary::Div => (smooth.clone(), &r + 0.5),
            Binary::Mod => (smooth.clone(), Field::constant(0.75)),
            Binary::And | Binary::Or => ((&x * 2.0).round(), y.clone()),
            _ => (smooth.clone(), &y - &z * 0.5),
        };
        v.push((format!("{op:?}"), a.binary(op, b)));
    }
    // Composite shapes: a sphere minus a box (HyperFun style) and a gyroid.
    let sphere = 1.0 - (&x * &x + &y * &y + &z * &z);
    let slab = 0.5 - x.abs().max(y.abs()).max(z.abs());
    v.push(("csg".into(), sphere.min(-slab)));
    let gyroid = (&x * 3.0).sin() * (&y * 3.0).cos()
        + (&y * 3.0).sin() * (&z * 3.0).cos()
        + (&z * 3.0).sin() * (&x * 3.0).cos();
    v.push(("gyroid".into(), gyroid));
    v
}

/// Seeded points in [-2, 2]^3.
fn points(n: usize) -> Vec<[f64; 3]> {
    let mut s: u64 = 0x2545_F491_4F6C_DD1D;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64 * 4.0 - 2.0
    };
    (0..n).map(|_| [next(), next(), next()]).collect()
}

fn same(a: f64, b: f64) -> bool {
    a == b || (a.is_nan() && b.is_nan())
}

#[test]
fn point_evaluation_matches_the_dag() {
    for (name, f) in cases() {
        let tape = Tape::compile(&f);
        let mut ev = PointEval::new(&tape);
        for p in points(500) {
            assert!(same(ev.eval(p), f.eval_tree(p)), "{name} at {p:?}");
        }
    }
}

/// Each case's evaluator takes over the register file the previous case's
/// dropped (another tape's stale values): no result may depend on them.
#[test]
fn batch_evaluation_matches_point_evaluation() {
    let pts = points(1000);
    let xs: Vec<f32> = pts.iter().map(|p| p[0] as f32).collect();
    let ys: Vec<f32> = pts.iter().map(|p| p[1] as f32).collect();
    let zs: Vec<f32> = pts.iter().map(|p| p[2] as f32).collect();
    for (name, f) in cases() {
        let tape = Tape::compile(&f);
        let mut batch = BatchEval::new(&tape);
        let mut out = vec![0.0f32; pts.len()];
        batch.eval(&xs, &ys, &zs, &mut out);
        let mut point = PointEval::new(&tape);
        let mut mismatches = 0;
        for (i, _) in pts.iter().enumerate() {
            // Evaluate the f64 path at the f32-rounded point the batch saw.
            let want = point.eval([xs[i] as f64, ys[i] as f64, zs[i] as f64]);
            let got = out[i] as f64;
            let ok = same(got, want)
                || (got - want).abs() <= 2e-4 * (1.0 + want.abs())
                || (want.is_infinite() && got.is_infinite());
            if !ok {
                mismatches += 1;
            }
        }
        // Steps (floor, round, compare, mod) may flip where f32 and f64 round
        // differently right at a boundary: allow a handful in a thousand.
        assert!(
            mismatches <= 3,
            "{name}: {mismatches} of 1000 points differ"
        );
    }
}

#[test]
fn gradients_are_exact() {
    for (name, f) in cases() {
        let tape = Tape::compile(&f);
        let mut g = GradEval::new(&tape);
        let mut p = PointEval::new(&tape);
        for pt in points(200) {
            let gr = g.eval(pt);
            assert!(same(gr.v, p.eval(pt)), "{name}: value");
            let h = 1e-6;
            for axis in 0..3 {
                let (mut a, mut b) = (pt, pt);
                a[axis] -= h;
                b[axis] += h;
                let (fa, fb) = (p.eval(a), p.eval(b));
                let fd = (fb - fa) / (2.0 * h);
                // Compare only where the function is smooth around the point.
                let smooth = fa.is_finite()
                    && fb.is_finite()
                    && ((fb - gr.v) - (gr.v - fa)).abs() < 1e-9 * (1.0 + gr.v.abs());
                if smooth && gr.d[axis].is_finite() {
                    assert!(
                        (gr.d[axis] - fd).abs() < 1e-4 * (1.0 + fd.abs()),
                        "{name} d/d{axis} at {pt:?}: {} vs {fd}",
                        gr.d[axis]
                    );
                }
            }
        }
    }
}

/// Also with one evaluator moved from tape to tape, in blocks of every
/// length the mesher asks (one point, a brick's crossings, several full
/// blocks): a block's registers must not leak into the next.
#[test]
fn batch_gradients_equal_point_gradients() {
    let pts = points(700);
    let cases = cases();
    let tapes: Vec<Tape> = cases.iter().map(|(_, f)| Tape::compile(f)).collect();
    let mut shared = BatchGradEval::new(&tapes[0]);
    for ((name, _), tape) in cases.iter().zip(&tapes) {
        let mut one = GradEval::new(tape);
        shared.set_tape(tape);
        // Blocks of every width the evaluator runs (4, 8, 16 lanes) and
        // partial ones.
        for chunk in [700, 1, 3, 6, 16, 37, 300] {
            let mut out = vec![Grad::default(); pts.len()];
            for (p, o) in pts.chunks(chunk).zip(out.chunks_mut(chunk)) {
                shared.eval(p, o);
            }
            let mut fresh = vec![Grad::default(); pts.len()];
            BatchGradEval::new(tape).eval(&pts, &mut fresh);
            for ((pt, got), again) in pts.iter().zip(&out).zip(&fresh) {
                let want = one.eval(*pt);
                for (got, label) in [(got, "shared"), (again, "fresh")] {
                    assert!(
                        same(got.v, want.v),
                        "{name} {label} {chunk}: value at {pt:?}"
                    );
                    for k in 0..3 {
                        assert!(
                            same(got.d[k], want.d[k]),
                            "{name} {label} {chunk}: d{k} at {pt:?}"
                        );
                    }
                }
            }
        }
    }
}

/// Where the rules branch (a kink, a tie, a zero under a root, a NaN),
/// the batch evaluator's row-wise forms of `abs`, `sqrt`, `square`, `neg`,
/// `min` and `max` give the point evaluator's bits.
#[test]
fn batch_gradients_hold_the_rules_at_kinks_ties_and_nans() {
    let (x, y) = (Field::x(), Field::y());
    let nan_below_five = (&x - 5.0).ln();
    let fields = [
        x.abs(),
        (&x * &x + &y * &y).sqrt(),
        x.sqrt(),
        x.square(),
        -(&x * 2.0),
        x.max(&y),
        x.min(&y),
        y.min(&nan_below_five),
        nan_below_five.max(&y),
        (&x * &y).max(0.0).sqrt(),
    ];
    let values = [-1.0, -0.5, -0.0, 0.0, 0.5, 1.0];
    let pts: Vec<[f64; 3]> = values
        .iter()
        .flat_map(|&a| values.iter().map(move |&b| [a, b, 0.25]))
        .collect();
    for field in &fields {
        let tape = Tape::compile(field);
        let mut one = GradEval::new(&tape);
        // 36 points: full blocks of 16 and a short one of 4.
        let mut out = vec![Grad::default(); pts.len()];
        BatchGradEval::new(&tape).eval(&pts, &mut out);
        for (pt, got) in pts.iter().zip(&out) {
            let want = one.eval(*pt);
            let parts = |g: &Grad| [g.v, g.d[0], g.d[1], g.d[2]];
            let agree = (parts(got).iter().zip(parts(&want)))
                .all(|(a, b)| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()));
            assert!(agree, "{field:?} at {pt:?}: {got:?}, want {want:?}");
        }
    }
}

#[test]
fn tanglecube_from_fidget_matches_its_formula() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../corpus/fidget-models/tanglecube.vm"
    ))
    .unwrap();
    let f = geode_frep::parse_vm(&text).unwrap();
    let tape = Tape::compile(&f);
    let mut ev = PointEval::new(&tape);
    for [x, y, z] in points(100) {
        let fidget =
            x.powi(4) - 5.0 * x * x + y.powi(4) - 5.0 * y * y + z.powi(4) - 5.0 * z * z + 10.0;
        assert!(
            (ev.eval([x, y, z]) + fidget).abs() < 1e-9,
            "negated for f >= 0 inside"
        );
    }
}

#[test]
fn every_corpus_model_imports_and_evaluates() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../corpus/fidget-models");
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "vm") {
            continue;
        }
        let f = geode_frep::parse_vm(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let tape = Tape::compile(&f);
        let mut ev = PointEval::new(&tape);
        let mut iv = IntervalEval::new(&tape);
        let bound = iv.eval(
            Interval::new(-1.0, 1.0),
            Interval::new(-1.0, 1.0),
            Interval::new(-1.0, 1.0),
        );
        for p in points(50).into_iter().map(|p| p.map(|c| c * 0.5)) {
            let v = ev.eval(p);
            assert!(same(v, f.eval_tree(p)), "{}", path.display());
            assert!(
                bound.has_nan() || v.is_nan() || bound.contains(v),
                "{}: {v} outside {bound:?}",
                path.display()
            );
        }
    }
    let e = geode_frep::parse_vm("_0 var-x\n_1 frobnicate _0\n").unwrap_err();
    assert_eq!(e.to_string(), "line 2: unknown opcode `frobnicate`");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn intervals_contain_point_values_and_simplified_tapes_agree(
        case in 0usize..29,
        c in (-2.0f64..2.0, -2.0f64..2.0, -2.0f64..2.0),
        h in 0.001f64..1.0,
        samples in prop::collection::vec((0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0), 20),
    ) {
        let all = cases();
        let (name, f) = &all[case % all.len()];
        let tape = Tape::compile(f);
        let mut iv = IntervalEval::new(&tape);
        let bx = [Interval::new(c.0 - h, c.0 + h), Interval::new(c.1 - h, c.1 + h), Interval::new(c.2 - h, c.2 + h)];
        let bound = iv.eval(bx[0], bx[1], bx[2]);
        let simplified = tape.simplify(iv.choices());
        prop_assert!(simplified.len() <= tape.len());
        let mut full = PointEval::new(&tape);
        let mut short = PointEval::new(&simplified);
        for s in samples {
            let p = [c.0 - h + 2.0 * h * s.0, c.1 - h + 2.0 * h * s.1, c.2 - h + 2.0 * h * s.2];
            let v = full.eval(p);
            if v.is_finite() && !bound.has_nan() {
                prop_assert!(bound.contains(v), "{}: {} outside [{}, {}] at {:?}", name, v, bound.lo, bound.hi, p);
            }
            prop_assert!(same(short.eval(p), v), "{}: simplified tape differs at {:?}", name, p);
        }
    }
}

#[test]
fn simplification_prunes_decided_branches() {
    // Far from the small sphere, the union is decided: only the big one remains.
    let (x, y, z) = (Field::x(), Field::y(), Field::z());
    let big = 4.0 - (&x * &x + &y * &y + &z * &z);
    let small = 0.01 - ((&x - 1.5).square() + &y * &y + &z * &z);
    let f = big.max(small);
    let tape = Tape::compile(&f);
    let mut iv = IntervalEval::new(&tape);
    iv.eval(
        Interval::new(-1.0, -0.5),
        Interval::new(-0.2, 0.2),
        Interval::new(-0.2, 0.2),
    );
    let s = tape.simplify(iv.choices());
    assert!(
        s.len() < tape.len() - 3,
        "{} of {} instructions",
        s.len(),
        tape.len()
    );
}
