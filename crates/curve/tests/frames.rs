//! Frames against analytic answers: orthonormality and tangents on a helix
//! and a trefoil, convergence to the helix's exact rotation-minimizing frame
//! at each method's order, closed curves that close.

use geode_curve::frames::{frames, tangents, Frame, FrameMethod, TangentMode};
use geode_curve::shapes::{helix, torus_knot, Sampled};
use geode_geo::glam::DVec3;

fn check_orthonormal(f: &[Frame]) {
    for (i, g) in f.iter().enumerate() {
        for v in [g.tangent, g.normal, g.bitangent] {
            assert!((v.length() - 1.0).abs() < 1e-6, "{i}: not unit");
        }
        assert!(g.tangent.dot(g.normal).abs() < 1e-6, "{i}");
        assert!(g.tangent.dot(g.bitangent).abs() < 1e-6, "{i}");
        assert!(g.normal.dot(g.bitangent).abs() < 1e-6, "{i}");
        assert!(
            g.normal.cross(g.tangent).distance(g.bitangent) < 1e-6,
            "{i}: right-handed"
        );
    }
}

#[test]
fn frames_are_orthonormal_and_follow_the_analytic_tangent() {
    for s in [helix(1.0, 0.4, 3.0, 600), torus_knot(2, 3, 1.0, 0.4, 900)] {
        for method in [
            FrameMethod::DoubleReflection,
            FrameMethod::ParallelTransport,
            FrameMethod::UpVector(DVec3::Y),
        ] {
            let f = frames(&s.points, &s.tangents, s.closed, method, None);
            check_orthonormal(&f);
            for (g, t) in f.iter().zip(&s.tangents) {
                assert!(g.tangent.distance(*t) < 1e-9);
            }
        }
        // Central differences approximate the analytic tangent to second order.
        let t = tangents(&s.points, s.closed, TangentMode::Central);
        let worst = t
            .iter()
            .zip(&s.tangents)
            .skip(1)
            .take(s.points.len() - 2)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max);
        assert!(worst < 1e-3, "central tangent error {worst}");
    }
}

/// The exact rotation-minimizing normal of the helix (a cos s, a sin s, b s)
/// starting from the principal normal: it turns from the Frenet normal by
/// -torsion * arc length.
fn helix_rmf_normal(a: f64, b: f64, s: f64) -> DVec3 {
    let c = (a * a + b * b).sqrt();
    let tangent = DVec3::new(-a * s.sin(), a * s.cos(), b) / c;
    let normal = DVec3::new(-s.cos(), -s.sin(), 0.0);
    let binormal = tangent.cross(normal);
    let theta = -(b / (c * c)) * (c * s);
    theta.cos() * normal + theta.sin() * binormal
}

fn helix_along_z(a: f64, b: f64, turns: f64, n: usize) -> Sampled {
    let end = std::f64::consts::TAU * turns;
    let (points, tangents) = (0..n)
        .map(|i| {
            let s = end * i as f64 / (n - 1) as f64;
            (
                DVec3::new(a * s.cos(), a * s.sin(), b * s),
                DVec3::new(-a * s.sin(), a * s.cos(), b).normalize(),
            )
        })
        .unzip();
    Sampled {
        points,
        tangents,
        closed: false,
    }
}

fn rmf_error(n: usize, method: FrameMethod, exact_tangents: bool) -> f64 {
    let (a, b, turns) = (1.0, 0.3, 2.0);
    let s = helix_along_z(a, b, turns, n);
    let t = if exact_tangents {
        s.tangents.clone()
    } else {
        tangents(&s.points, false, TangentMode::Central)
    };
    let f = frames(
        &s.points,
        &t,
        false,
        method,
        Some(helix_rmf_normal(a, b, 0.0)),
    );
    let end = std::f64::consts::TAU * turns;
    (0..n)
        .map(|i| {
            f[i].normal
                .distance(helix_rmf_normal(a, b, end * i as f64 / (n - 1) as f64))
        })
        .fold(0.0, f64::max)
}

#[test]
fn frames_converge_to_the_exact_rotation_minimizing_frame_at_their_order() {
    // Double reflection with exact tangents: fourth order (error / 16 per halving).
    let e: Vec<f64> = [50, 100, 200]
        .map(|n| rmf_error(n, FrameMethod::DoubleReflection, true))
        .to_vec();
    for w in e.windows(2) {
        let ratio = w[0] / w[1];
        assert!(ratio > 12.0 && ratio < 20.0, "double reflection: {e:?}");
    }
    assert!(e[2] < 1e-6, "{e:?}");
    // Discrete parallel transport (rotation by the arc between tangents):
    // second order with exact tangents.
    let e: Vec<f64> = [100, 200, 400]
        .map(|n| rmf_error(n, FrameMethod::ParallelTransport, true))
        .to_vec();
    for w in e.windows(2) {
        let ratio = w[0] / w[1];
        assert!(ratio > 3.5 && ratio < 4.5, "parallel transport: {e:?}");
    }
    // With finite-difference tangents the one-sided tangent at the first
    // point tilts the starting frame by O(h): first order overall.
    let e: Vec<f64> = [100, 200, 400]
        .map(|n| rmf_error(n, FrameMethod::ParallelTransport, false))
        .to_vec();
    for w in e.windows(2) {
        let ratio = w[0] / w[1];
        assert!(ratio > 1.8 && ratio < 2.2, "central tangents: {e:?}");
    }
}

#[test]
fn a_closed_curves_frame_closes() {
    let s = torus_knot(2, 3, 1.0, 0.4, 300);
    for method in [
        FrameMethod::DoubleReflection,
        FrameMethod::ParallelTransport,
    ] {
        let f = frames(&s.points, &s.tangents, true, method, None);
        // Carried one more step from the last point, the frame meets the
        // first one again: neighbours differ by as little all the way round.
        let step = |a: &Frame, b: &Frame| a.normal.distance(b.normal);
        let closing = step(&f[f.len() - 1], &f[0]);
        let typical = (1..f.len())
            .map(|i| step(&f[i - 1], &f[i]))
            .fold(0.0, f64::max);
        assert!(
            closing <= typical * 1.5,
            "{method:?}: closing {closing} vs steps up to {typical}"
        );
        check_orthonormal(&f);
    }
}
