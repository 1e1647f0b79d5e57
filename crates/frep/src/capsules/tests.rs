//! Capsule sets checked against the plain maximum over every capsule, their
//! intervals, batches and gradients, and floors.

use super::*;

/// A deterministic pseudo-random walk of `n` segments.
fn walk(n: usize) -> Vec<([f64; 3], [f64; 3], f64, f64)> {
    let mut s = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut p = [0.0; 3];
    let mut r = 0.05;
    (0..n)
        .map(|_| {
            let q = [p[0] + 0.2 * rnd(), p[1] + 0.2 * rnd(), p[2] + 0.2 * rnd()];
            let r2 = (r + 0.02 * rnd()).max(0.005);
            let seg = (p, q, r, r2);
            (p, r) = (q, r2);
            seg
        })
        .collect()
}

#[test]
fn hierarchy_gives_the_plain_maximum() {
    let segs = walk(500);
    let set = CapsuleSet::new(&segs).unwrap();
    let plain = |p: [f64; 3]| {
        segs.iter()
            .map(|&(a, b, ra, rb)| Capsule::new(a, b, ra, rb).value(p))
            .fold(f64::NEG_INFINITY, f64::max)
    };
    for i in 0..2000 {
        let t = i as f64 * 0.618;
        let p = [t.sin() * 1.5, (1.3 * t).cos() * 1.5, (0.7 * t).sin() * 1.5];
        assert_eq!(set.value(p), plain(p), "at {p:?}");
    }
}

#[test]
fn intervals_bound_every_value_and_keep_every_winner() {
    let segs = walk(300);
    let set = CapsuleSet::new(&segs).unwrap();
    for i in 0..200 {
        let t = i as f64 * 0.377;
        let c = [t.sin(), (1.7 * t).cos(), (0.3 * t).sin()];
        let h = 0.02 + 0.1 * (i % 5) as f64;
        let iv = |k: usize| Interval::new(c[k] - h, c[k] + h);
        let (range, narrowed) = set.interval(iv(0), iv(1), iv(2));
        for j in 0..64 {
            let f = |s: usize| ((j >> s) & 3) as f64 / 3.0 * 2.0 - 1.0;
            let p = [c[0] + h * f(0), c[1] + h * f(2), c[2] + h * f(4)];
            let v = set.value(p);
            assert!(range.contains(v), "{v} outside {range:?}");
            if let Some(n) = &narrowed {
                assert_eq!(n.value(p), v, "the narrowed set changes the value");
            }
        }
    }
}

#[test]
fn batches_give_the_point_values() {
    let set = CapsuleSet::new(&walk(400)).unwrap();
    let n = 700;
    let coord = |i: usize, k: usize| 0.3 * (i as f32 * (0.37 + 0.21 * k as f32)).sin();
    let axes: [Vec<f32>; 3] = std::array::from_fn(|k| (0..n).map(|i| coord(i, k)).collect());
    let mut out = vec![0f32; n];
    set.values(&axes[0], &axes[1], &axes[2], &mut out);
    for i in 0..n {
        let p = [axes[0][i], axes[1][i], axes[2][i]].map(f64::from);
        let exact = set.value(p) as f32;
        assert!(
            (out[i] - exact).abs() <= 1e-5,
            "point {i}: {} vs {exact}",
            out[i]
        );
    }
}

#[test]
fn gradients_match_differences() {
    let set = CapsuleSet::new(&walk(50)).unwrap();
    let e = 1e-6;
    for i in 0..300 {
        let t = i as f64 * 0.91;
        let p = [0.4 * t.sin(), 0.4 * (1.1 * t).cos(), 0.4 * (0.5 * t).sin()];
        let (v, g) = set.value_gradient(p);
        assert_eq!(v, set.value(p));
        for k in 0..3 {
            let mut q = p;
            q[k] += e;
            let mut r = p;
            r[k] -= e;
            let fd = (set.value(q) - set.value(r)) / (2.0 * e);
            // Kinks (where the winner changes) are rare at these points.
            if (fd - g[k]).abs() > 1e-4 {
                let (_, gq) = set.value_gradient(q);
                assert!(
                    (gq[k] - g[k]).abs() > 1e-3,
                    "gradient {k} at {p:?}: {} vs {fd}",
                    g[k]
                );
            }
        }
    }
}

/// A floored set equals the plain one above the floor, reads the floor
/// below it (with no gradient), bounds the same way over boxes, and its
/// narrowed sets keep the floor.
#[test]
fn a_floor_changes_nothing_above_it() {
    let segments = walk(300);
    let plain = CapsuleSet::new(&segments).unwrap();
    let floored = plain.with_floor(-0.05);
    assert_ne!(plain.identity(), floored.identity());
    let mut seed = 11u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut above, mut below) = (0, 0);
    for _ in 0..2000 {
        // Near the walk: within 0.3 of one of its points.
        let near = segments[(next() * 300.0) as usize].0;
        let p = near.map(|c| c + 0.6 * (next() - 0.5));
        let (v, g) = plain.value_gradient(p);
        let (fv, fg) = floored.value_gradient(p);
        if v >= -0.05 {
            above += 1;
            assert_eq!((v, g), (fv, fg));
        } else {
            below += 1;
            assert_eq!((fv, fg), (-0.05, [0.0; 3]));
        }
        let lo = p.map(|c| c - 0.1);
        let hi = p.map(|c| c + 0.1);
        let iv = |s: &CapsuleSet| {
            s.interval(
                Interval::new(lo[0], hi[0]),
                Interval::new(lo[1], hi[1]),
                Interval::new(lo[2], hi[2]),
            )
        };
        let ((pi, _), (fi, narrowed)) = (iv(&plain), iv(&floored));
        assert_eq!(fi.lo, pi.lo.max(-0.05));
        assert_eq!(fi.hi, pi.hi.max(-0.05));
        if let Some(n) = narrowed {
            assert_eq!(n.value(p), fv);
        }
    }
    assert!(above > 100 && below > 100, "{above} {below}");
}
