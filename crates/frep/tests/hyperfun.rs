//! HyperFun programs: every library function against the definition
//! HyperFun documents for it, at seeded random points; the language
//! (arrays, conditions on constants and on the point, loops, objects
//! calling objects, case and comments); each error class with its message.

use geode_frep::{parse_hf, Field};

/// An object whose body is `body` (the value is `m`), compiled.
fn model(body: &str) -> Field {
    parse_hf(&format!("m(x[3], a[2])\n{{\n{body}\n}}\n"), None, &[])
        .unwrap_or_else(|e| panic!("{body}: {e}"))
}

/// Seeded points in [-2, 2]^3.
fn points() -> Vec<[f64; 3]> {
    let mut s = 0x5eed_u64;
    let mut next = move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64 * 4.0 - 2.0
    };
    (0..200).map(|_| [next(), next(), next()]).collect()
}

/// The program's field agrees with `expected` everywhere sampled.
fn check(body: &str, expected: impl Fn([f64; 3]) -> f64) {
    let f = model(body);
    for p in points() {
        let (got, want) = (f.eval_tree(p), expected(p));
        let tol = 1e-9 * (1.0 + want.abs());
        assert!(
            (got - want).abs() <= tol || (got.is_nan() && want.is_nan()),
            "{body}\nat {p:?}: {got} vs {want}"
        );
    }
}

const C: [f64; 3] = [0.1, -0.2, 0.3];
const CENTRE: &str = "array c[3]; c = [0.1, -0.2, 0.3];";

fn rel(p: [f64; 3]) -> [f64; 3] {
    [p[0] - C[0], p[1] - C[1], p[2] - C[2]]
}

#[test]
fn primitives_follow_their_definitions() {
    check(&format!("{CENTRE} m = hfSphere(x, c, 0.7);"), |p| {
        let t = rel(p);
        0.49 - t[0] * t[0] - t[1] * t[1] - t[2] * t[2]
    });
    check(
        &format!("{CENTRE} m = hfEllipsoid(x, c, 0.5, 0.7, 0.9);"),
        |p| {
            let t = rel(p);
            1.0 - (t[0] / 0.5).powi(2) - (t[1] / 0.7).powi(2) - (t[2] / 0.9).powi(2)
        },
    );
    for (axis, name) in ["X", "Y", "Z"].iter().enumerate() {
        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
        check(&format!("{CENTRE} m = hfCylinder{name}(x, c, 0.6);"), |p| {
            let t = rel(p);
            0.36 - t[u] * t[u] - t[w] * t[w]
        });
        check(
            &format!("{CENTRE} m = hfEllCyl{name}(x, c, 0.5, 0.8);"),
            |p| {
                let t = rel(p);
                // HyperFun's a and b go with the two axes across, in x, y, z order.
                let (a, b) = (t[u.min(w)] / 0.5, t[u.max(w)] / 0.8);
                1.0 - a * a - b * b
            },
        );
        check(
            &format!("{CENTRE} m = hfTorus{name}(x, c, 1.0, 0.3);"),
            |p| {
                let t = rel(p);
                let r2 = t[0] * t[0] + t[1] * t[1] + t[2] * t[2];
                0.09 - r2 - 1.0 + 2.0 * (t[u] * t[u] + t[w] * t[w]).sqrt()
            },
        );
        check(&format!("{CENTRE} m = hfCone{name}(x, c, 0.5);"), |p| {
            let t = rel(p);
            t[axis] * t[axis] - (t[u] / 0.5).powi(2) - (t[w] / 0.5).powi(2)
        });
    }
    check(
        "array v[3]; v = [-0.5, -0.4, -0.3]; m = hfBlock(x, v, 1.0, 0.8, 0.6);",
        |p| {
            let slab = |k: usize, v: f64, d: f64| (p[k] - v) * (v + d - p[k]);
            let i = |a: f64, b: f64| a + b - (a * a + b * b).sqrt();
            i(
                i(slab(0, -0.5, 1.0), slab(1, -0.4, 0.8)),
                slab(2, -0.3, 0.6),
            )
        },
    );
    check(
        &format!("{CENTRE} m = hfSuperell(x, c, 0.5, 0.6, 0.7, 0.4, 1.5);"),
        |p| {
            let t = rel(p);
            let (x, y, z) = ((t[0] / 0.5).abs(), (t[1] / 0.6).abs(), (t[2] / 0.7).abs());
            let xy = x.powf(2.0 / 1.5) + y.powf(2.0 / 1.5);
            1.0 - xy.powf(1.5 / 0.4) - z.powf(2.0 / 0.4)
        },
    );
    check(
        "array x0[2], y0[2], z0[2], ka[2], kb[2];
         x0 = [0.2, -0.3]; y0 = [0.1, 0.4]; z0 = [0, -0.2]; ka = [3, 5]; kb = [1, 2];
         m = hfBlobby(x, x0, y0, z0, ka, kb, 0.5);",
        |p| {
            let blob = |c: [f64; 3], a: f64, b: f64| {
                b * (-a * ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2) + (p[2] - c[2]).powi(2)))
                    .exp()
            };
            blob([0.2, 0.1, 0.0], 3.0, 1.0) + blob([-0.3, 0.4, -0.2], 5.0, 2.0) - 0.5
        },
    );
}

fn ball(p: [f64; 3], c: [f64; 3], r: f64) -> f64 {
    r * r - (p[0] - c[0]).powi(2) - (p[1] - c[1]).powi(2) - (p[2] - c[2]).powi(2)
}

const TWO_BALLS: &str = "array c1[3], c2[3]; c1 = [0, 0, 0]; c2 = [0.5, 0, 0];
                         f1 = hfSphere(x, c1, 0.6); f2 = hfSphere(x, c2, 0.4);";

#[test]
fn set_operations_and_blends_are_hyperfuns_r_functions() {
    let f1 = |p| ball(p, [0.0; 3], 0.6);
    let f2 = |p| ball(p, [0.5, 0.0, 0.0], 0.4);
    let root = |a: f64, b: f64| (a * a + b * b).sqrt();
    check(&format!("{TWO_BALLS} m = f1 | f2;"), |p| {
        f1(p) + f2(p) + root(f1(p), f2(p))
    });
    check(&format!("{TWO_BALLS} m = f1 & f2;"), |p| {
        f1(p) + f2(p) - root(f1(p), f2(p))
    });
    check(&format!("{TWO_BALLS} m = f1 \\ f2;"), |p| {
        f1(p) - f2(p) - root(f1(p), f2(p))
    });
    check(&format!("{TWO_BALLS} m = ~f1;"), |p| -f1(p));
    let bump =
        |p, a0: f64, a1: f64, a2: f64| a0 / (1.0 + (f1(p) / a1).powi(2) + (f2(p) / a2).powi(2));
    check(
        &format!("{TWO_BALLS} m = hfBlendUni(f1, f2, 0.3, 0.5, 0.7);"),
        |p| f1(p) + f2(p) + root(f1(p), f2(p)) + bump(p, 0.3, 0.5, 0.7),
    );
    check(
        &format!("{TWO_BALLS} m = hfBlendInt(f1, f2, 0.3, 0.5, 0.7);"),
        |p| f1(p) + f2(p) - root(f1(p), f2(p)) + bump(p, 0.3, 0.5, 0.7),
    );
}

/// A unit-free probe of a transformation: the field is the mapped point's
/// coordinates mixed so that each shows.
const PROBE: &str = "m = x[1] + 10 * x[2] + 100 * x[3];";

fn probe(q: [f64; 3]) -> f64 {
    q[0] + 10.0 * q[1] + 100.0 * q[2]
}

#[test]
fn transformations_are_inverse_mappings() {
    check(&format!("d = hfScale3D(x, 2, 0.5, 4); {PROBE}"), |p| {
        probe([p[0] / 2.0, p[1] / 0.5, p[2] / 4.0])
    });
    check(&format!("d = hfShift3D(x, 0.1, 0.2, 0.3); {PROBE}"), |p| {
        probe([p[0] - 0.1, p[1] - 0.2, p[2] - 0.3])
    });
    check(
        &format!("{CENTRE} d = hfStretch3D(x, c, 2, 3, 4); {PROBE}"),
        |p| {
            probe([
                C[0] + (p[0] - C[0]) / 2.0,
                C[1] + (p[1] - C[1]) / 3.0,
                C[2] + (p[2] - C[2]) / 4.0,
            ])
        },
    );
    let th = 0.7f64;
    let (c, s) = (th.cos(), th.sin());
    check(&format!("d = hfRotate3DX(x, 0.7); {PROBE}"), |p| {
        probe([p[0], p[1] * c + p[2] * s, -p[1] * s + p[2] * c])
    });
    check(&format!("d = hfRotate3DY(x, 0.7); {PROBE}"), |p| {
        probe([-p[2] * s + p[0] * c, p[1], p[2] * c + p[0] * s])
    });
    check(&format!("d = hfRotate3DZ(x, 0.7); {PROBE}"), |p| {
        probe([p[0] * c + p[1] * s, -p[0] * s + p[1] * c, p[2]])
    });
    check(&format!("d = hfTwistX(x, -1, 1, 0.2, 1.4); {PROBE}"), |p| {
        let t = (p[0] + 1.0) / 2.0;
        let th = (1.0 - t) * 0.2 + t * 1.4;
        let (c, s) = (th.cos(), th.sin());
        probe([p[0], p[1] * c + p[2] * s, -p[1] * s + p[2] * c])
    });
    check(&format!("d = hfTaperZ(x, -1, 1, 0.5, 2); {PROBE}"), |p| {
        let t = ((p[2] + 1.0) / 2.0).clamp(0.0, 1.0);
        let scale = (1.0 - t) * 0.5 + t * 2.0;
        probe([p[0] / scale, p[1] / scale, p[2]])
    });
}

#[test]
fn standard_functions_and_arithmetic() {
    check(
        "m = sqrt(abs(x[1])) + exp(x[2]) - log(1 + x[3] * x[3]) + logd(2 + x[1]);",
        |p| p[0].abs().sqrt() + p[1].exp() - (1.0 + p[2] * p[2]).ln() + (2.0 + p[0]).log10(),
    );
    check(
        "m = sin(x[1]) * cos(x[2]) - tan(x[3] / 4) + atan(x[1]) + asin(x[2] / 2) + acos(x[3] / 2);",
        |p| {
            p[0].sin() * p[1].cos() - (p[2] / 4.0).tan()
                + p[0].atan()
                + (p[1] / 2.0).asin()
                + (p[2] / 2.0).acos()
        },
    );
    check(
        "m = max(x[1], x[2]) - min(x[2], x[3]) + sign(x[3]) + mod(x[1] + 5, 3);",
        |p| {
            p[0].max(p[1]) - p[1].min(p[2])
                + if p[2] > 0.0 {
                    1.0
                } else if p[2] < 0.0 {
                    -1.0
                } else {
                    0.0
                }
                + (p[0] + 5.0).rem_euclid(3.0)
        },
    );
    check("m = x[1]^2 - x[2]^3 + 2^-1 - (x[3]^2)^0.5;", |p| {
        p[0].powi(2) - p[1].powi(3) + 0.5 - p[2].abs()
    });
}

#[test]
fn the_language_runs_at_compile_time() {
    // A loop with a constant condition unrolls: the sum of 1..10 rings.
    check(
        "i = 1; s = 0;
         while i <= 10 loop
           s = s + i;
           i = i + 1;
         endloop;
         m = s - x[1];",
        |p| 55.0 - p[0],
    );
    // An if on a constant picks its branch; names and keywords ignore case.
    check(
        "K = 3; IF k > 2 THEN m = X[1]; ELSE m = x[2]; ENDIF;",
        |p| p[0],
    );
    // An if on the point selects per point; `2 <= v < 5` is a chain.
    check(
        "if x[1] > 0 and not (x[2] < -1) then m = 1; else m = -1; endif;",
        |p| {
            if p[0] > 0.0 && p[1] >= -1.0 {
                1.0
            } else {
                -1.0
            }
        },
    );
    check(
        "v = x[1] * 3; if -1 <= v < 2 then m = v; else m = 0; endif;",
        |p| {
            let v = p[0] * 3.0;
            if (-1.0..2.0).contains(&v) {
                v
            } else {
                0.0
            }
        },
    );
    // Element assignment, a list assigned to an array, comments.
    check(
        "array q[3]; -- a comment
         q = [1, 2, 3]; q[2] = x[2]; -- another
         m = q[1] + q[2] * q[3];",
        |p| 1.0 + 3.0 * p[1],
    );
}

#[test]
fn objects_call_objects_with_their_own_coordinates() {
    let program = "
        -- a ball of radius a[1] at the origin
        Ball(xx[3], aa[1])
        {
          Ball = aa[1]^2 - xx[1]^2 - xx[2]^2 - xx[3]^2;
        }
        Scene(x[3], a[1])
        {
          array moved[3], r[1];
          moved = [x[1] - 1, x[2], x[3]];
          r = [0.5];
          Scene = Ball(moved, r) | Ball(x, r);
        }";
    let f = parse_hf(program, None, &[]).unwrap();
    let ball_at = |p: [f64; 3], cx: f64| 0.25 - (p[0] - cx).powi(2) - p[1] * p[1] - p[2] * p[2];
    for p in points() {
        let (a, b) = (ball_at(p, 1.0), ball_at(p, 0.0));
        let want = a + b + (a * a + b * b).sqrt();
        assert!((f.eval_tree(p) - want).abs() < 1e-9 * (1.0 + want.abs()));
    }
    // The object to read can be named; its parameters come from the caller.
    let ball = parse_hf(program, Some("BALL"), &[2.0]).unwrap();
    assert_eq!(ball.eval_tree([1.0, 1.0, 1.0]), 1.0);
}

fn error(program: &str) -> String {
    parse_hf(program, None, &[]).unwrap_err().to_string()
}

#[test]
fn each_error_names_its_line_and_column() {
    let cases = [
        ("m(x[3], a[1])\n{\n  m = x[1] $ 2;\n}", "line 3, column 12: unexpected character '$'"),
        ("m(x[3], a[1])\n{\n  m = x[1]\n}", "line 4, column 1: expected ';', found '}'"),
        ("m(x[3], a[1])\n{\n  m = q + 1;\n}", "line 3, column 7: 'q' is used before it is given a value"),
        ("m(x[3], a[1])\n{\n  m = hfSphere(x, 1);\n}", "line 3, column 7: hfsphere takes 3 arguments (x[3], center[3], R), given 2"),
        ("m(x[3], a[1])\n{\n  m = hfSphere(1, x, 1);\n}", "line 3, column 7: hfsphere: 'x[3]' must be an array"),
        ("m(x[3], a[1])\n{\n  m = frobnicate(x[1]);\n}", "line 3, column 7: unknown function or object 'frobnicate'"),
        ("m(x[3], a[1])\n{\n  m = x[4];\n}", "line 3, column 7: index 4 is outside 'x' (1 to 3)"),
        ("m(x[3], a[1])\n{\n  while x[1] < 0 loop m = 1; endloop;\n  m = 0;\n}", "line 3, column 3: this loop's condition depends on the point: it cannot be unrolled into a field"),
        ("m(x[3], a[1])\n{\n  i = 0;\n  while i >= 0 loop i = i + 1; endloop;\n  m = 0;\n}", "line 4, column 3: this loop runs more than 100000 times"),
        ("m(x[3], a[1])\n{\n  k = 1;\n}", "line 1, column 1: 'm' never sets its value ('m = ...;')"),
        ("m(x[2], a[1])\n{\n  m = 1;\n}", "line 1, column 1: 'm' declares x[2]: geode reads objects in 3D (x[3])"),
        ("m(x[3], a[1])\n{\n  array q[2];\n  q = [1, 2, 3];\n  m = 1;\n}", "line 4, column 3: 'q' has 2 elements, the value given 3"),
        ("", "line 1, column 1: expected an object: name(x[3], a[1]) { ... }"),
        ("m(x[3], a[1])\n{\n  m = 1;\n", "line 3, column 9: expected '}' before the end of the file"),
    ];
    for (program, message) in cases {
        assert_eq!(error(program), message, "{program}");
    }
}
