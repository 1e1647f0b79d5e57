//! Control flow lowers two ways: a batch of points runs in lockstep under
//! masks, a detail run (one lane) takes plain jumps. Each function below
//! is run both ways: as a point wrangle over 16 points (lanes diverge) and
//! from a detail loop over the same inputs, and must agree lane by lane and
//! with C's rules (the values worked out by hand for a few inputs).

mod common;
use common::*;
use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, Geometry};

/// (function of `int n`, hand-worked results for n = 0..4)
const FUNCTIONS: &[(&str, [i32; 4])] = &[
    // Early returns at several depths.
    (
        "int f(int n) { if (n == 0) return 10; if (n % 2 == 1) { if (n > 2) return 30; return 20; } return n; }",
        [10, 20, 2, 30],
    ),
    // break and continue in nested loops.
    (
        "int f(int n) { int s = 0; for (int i = 0; i < 10; i++) { if (i == n) continue; for (int j = 0; j < 10; j++) { if (j > i) break; s += 1; } if (s > 20) break; } return s; }",
        [27, 26, 25, 24],
    ),
    // while with break, do-while runs once.
    (
        "int f(int n) { int k = 0; while (1) { k++; if (k > n) break; } int d = 0; do { d += 5; } while (d < n); return k * 100 + d; }",
        [105, 205, 305, 405],
    ),
    // foreach with continue and an early return from inside it.
    (
        "int f(int n) { int a[] = {1, 2, 3, 4, 5}; int s = 0; foreach (int i; int x; a) { if (x == n) continue; if (s > 6 && n == 3) return -s; s += x * i; } return s; }",
        [40, 40, 38, -14],
    ),
    // A nested function's return does not end the caller.
    (
        "int g(int x) { if (x > 1) return x * 2; return -1; } int f(int n) { int s = 0; for (int i = 0; i <= n; i++) { s += g(i); } return s; }",
        [-1, -2, 2, 8],
    ),
    // Float conditions, compound assignments, the ternary.
    (
        "int f(int n) { float x = n * 0.5; float acc = 0; while (x) { acc += x > 1 ? 2.0 : 1.0; x -= 0.5; } return int(acc * 10); }",
        [0, 10, 20, 40],
    ),
    // A loop that never runs, then one that counts down.
    (
        "int f(int n) { int s = 0; for (int i = 0; i < 0; i++) s += 100; for (int i = n; i > 0; i--) s = s * 2 + i; return s; }",
        [0, 1, 5, 17],
    ),
    // ++/-- as values.
    (
        "int f(int n) { int i = n; int a = i++; int b = ++i; int c = i--; return a * 100 + b * 10 + c - i; }",
        [21, 131, 241, 351],
    ),
];

fn points(n: usize) -> Geometry {
    let mut g = Geometry::new();
    let p: Vec<Vec3> = (0..n).map(|i| Vec3::new(i as f32, 0.0, 0.0)).collect();
    g.add_points(&p);
    g
}

#[test]
fn masked_and_uniform_lowering_agree_with_c() {
    const N: usize = 16;
    let g = points(N);
    for (f, want) in FUNCTIONS {
        let batch = wrangle(&format!("{f} i@r = f(@ptnum);"), AttribClass::Point, &g);
        let batch = batch
            .attrib(AttribClass::Point, "r")
            .and_then(|a| a.as_i32())
            .expect("point r")
            .to_vec();
        let one = wrangle(
            &format!("{f} int rs[]; for (int n = 0; n < {N}; n++) push(rs, f(n)); i[]@r = rs;"),
            AttribClass::Detail,
            &g,
        );
        let one: Vec<i32> = match one
            .attrib(AttribClass::Detail, "r")
            .map(|a| a.data().get(0))
        {
            Some(geode_geo::AttribValue::IntArray(v)) => v,
            other => panic!("detail r: {other:?}"),
        };
        assert_eq!(batch, one, "{f}: lanes disagree");
        assert_eq!(&batch[..4], want, "{f}: against C's rules");
    }
}

/// `s += t` under a mask appends only on the lanes taking the branch.
#[test]
fn string_appends_follow_the_mask() {
    let g = points(6);
    let out = wrangle(
        "string s = \"p\"; for (int i = 0; i < @ptnum; i++) { if (i % 2 == 0) s += itoa(i); } s@r = s;",
        AttribClass::Point,
        &g,
    );
    let r = out
        .attrib(AttribClass::Point, "r")
        .unwrap()
        .as_strings()
        .unwrap();
    let got: Vec<&str> = (0..6).map(|i| r.get(i)).collect();
    assert_eq!(got, ["p", "p0", "p0", "p02", "p02", "p024"]);
}

/// Calls of numbers (noise, rand) run over the batch's live lanes only,
/// and a lane gives what one lane alone gives.
#[test]
fn calls_of_numbers_agree_on_a_batch_and_alone() {
    const N: usize = 16;
    let g = points(N);
    let f = "float f(int n) { float s = 0; for (int i = 0; i < n; i++) { if (i % 3 == 1) continue; s += snoise(set(i, n, 0.5)) + rand(i * 7 + n) + noise(float(i)) * length(vector(xnoise(set(n, i, 0.25)))); } return s; }";
    let batch = wrangle(
        &format!("{f} vector c = curlnoise(@P * 0.3); f@r = f(@ptnum) + c.x;"),
        AttribClass::Point,
        &g,
    );
    let batch = batch
        .attrib(AttribClass::Point, "r")
        .unwrap()
        .as_f32()
        .unwrap()
        .to_vec();
    let one = wrangle(
        &format!("{f} float rs[]; for (int n = 0; n < {N}; n++) {{ vector c = curlnoise(point(0, \"P\", n) * 0.3); push(rs, f(n) + c.x); }} f[]@r = rs;"),
        AttribClass::Detail,
        &g,
    );
    let one: Vec<f32> = match one
        .attrib(AttribClass::Detail, "r")
        .map(|a| a.data().get(0))
    {
        Some(geode_geo::AttribValue::FloatArray(v)) => v,
        other => panic!("detail r: {other:?}"),
    };
    assert_eq!(batch, one);
    assert!(batch.iter().any(|x| *x != 0.0));
}
