//! The attach node and the hspline examples (hand with fingers attached,
//! head with locally refined eye sockets), through the engine.

mod common;

use std::sync::Arc;

use common::err;
use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, Geometry};
use geode_graph::{load_str, Cache, CookOptions, Engine};

fn cook_example(name: &str, frame: f64) -> Arc<Geometry> {
    let path = format!("{}/../../examples/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    let net = load_str(&text, &geode_nodes::registry()).unwrap();
    let cache = Cache::disabled();
    Engine::new(net, &cache)
        .cook_output(&CookOptions::at_frame(frame))
        .unwrap()
        .value
        .as_geometry()
        .unwrap()
        .clone()
}

#[test]
fn the_hand_has_five_fingers_joined_smoothly_that_follow_the_palm() {
    let (first, last) = (
        cook_example("hand.json", 1.0),
        cook_example("hand.json", 48.0),
    );
    let surface = first
        .attrib(AttribClass::Primitive, "surface")
        .and_then(|a| a.as_i32())
        .unwrap()
        .to_vec();
    for s in 0..6 {
        assert!(surface.contains(&s), "surface {s} is missing");
    }
    let report = first.topology().manifold_report(&first);
    assert_eq!(report.non_manifold_edges, 0, "{report:?}");
    assert_eq!(report.inconsistent_edges, 0, "{report:?}");
    assert_eq!(first.num_points(), last.num_points());
    // The palm vertex under the middle finger rises: the middle finger's
    // base moves with it, the little finger's tip does not.
    let moved = |s: i32| {
        let mut worst = 0.0f32;
        for (f, &k) in surface.iter().enumerate() {
            if k == s {
                for &v in first.prim_points(f) {
                    let v = v as usize;
                    worst = worst.max(first.positions()[v].distance(last.positions()[v]));
                }
            }
        }
        worst
    };
    assert!(moved(2) > 0.05, "middle finger moved {}", moved(2));
    assert!(moved(4) < 1e-4, "little finger moved {}", moved(4));
}

#[test]
fn the_head_has_mirrored_eye_sockets_on_a_local_level_that_deepen() {
    let (first, last) = (
        cook_example("head.json", 1.0),
        cook_example("head.json", 48.0),
    );
    // Mirror symmetric across X = 0 (samples around land on mirror pairs).
    let key = |p: Vec3| {
        (
            (p.x * 1e3).round() as i64,
            (p.y * 1e3).round() as i64,
            (p.z * 1e3).round() as i64,
        )
    };
    let all: std::collections::HashSet<_> = first.positions().iter().map(|&p| key(p)).collect();
    let unmatched = first
        .positions()
        .iter()
        .filter(|p| {
            let m = Vec3::new(-p.x, p.y, p.z);
            !(-1..=1).any(|dx| {
                (-1..=1).any(|dz| {
                    let k = key(m);
                    all.contains(&(k.0 + dx, k.1, k.2 + dz))
                })
            })
        })
        .count();
    assert!(
        unmatched < first.num_points() / 100,
        "{unmatched} points have no mirror"
    );
    // The sockets: points in front (z > 0.5) at eye height sit deeper at frame 48.
    let deepest = |g: &Geometry| {
        g.positions()
            .iter()
            .filter(|p| p.z > 0.3 && p.x.abs() > 0.3 && p.x.abs() < 0.7 && (p.y - 0.3).abs() < 0.4)
            .map(|p| Vec3::new(p.x, 0.0, p.z).length())
            .fold(f32::INFINITY, f32::min)
    };
    assert!(
        deepest(&last) < deepest(&first) - 0.03,
        "{} {}",
        deepest(&first),
        deepest(&last)
    );
}

const PLANE: &str = r#""p": {"type": "hspline", "params": {"topology": "plane", "rows": 8, "columns": 8, "size": [4, 4]}}"#;

#[test]
fn attach_errors_name_the_node_the_parameter_and_what_was_expected() {
    let limb = |cols: u32| {
        format!(
            r#""l": {{"type": "hspline", "params": {{"topology": "cylinder", "rows": 6, "columns": {cols}, "size": [0.5, 2]}}}}"#
        )
    };
    let e = err(
        &format!(
            r#"{PLANE}, {}, "a": {{"type": "attach", "inputs": ["p", "l"], "params": {{"regions": "2 4 2 4"}}}}"#,
            limb(6)
        ),
        "a",
    );
    assert!(
        e.contains("/a")
            && e.contains("regions")
            && e.contains("has 6 vertices around but its region's rim has 8"),
        "{e}"
    );
    let e = err(
        &format!(
            r#"{PLANE}, {}, "a": {{"type": "attach", "inputs": ["p", "l"], "params": {{"regions": "2 4 2 4; 4 5 4 5"}}}}"#,
            limb(8)
        ),
        "a",
    );
    assert!(e.contains("2 regions for 1 limb inputs"), "{e}");
    let e = err(
        &format!(
            r#"{PLANE}, "b": {{"type": "box"}}, "a": {{"type": "attach", "inputs": ["p", "b"]}}"#
        ),
        "a",
    );
    assert!(
        e.contains("limb 0") && e.contains("carries no hspline"),
        "{e}"
    );
    let e = err(
        &format!(
            r#"{PLANE}, {}, "t": {{"type": "transform", "inputs": ["l"], "params": {{"translate": [1, 0, 0]}}}}, "a": {{"type": "attach", "inputs": ["p", "t"], "params": {{"regions": [{{"u": [2, 4], "v": [2, 4]}}]}}}}"#,
            limb(8)
        ),
        "a",
    );
    assert!(e.contains("points changed after its hspline node"), "{e}");
    let e = err(
        &format!(
            r#"{PLANE}, {}, "a": {{"type": "attach", "inputs": ["p", "l"], "params": {{"regions": "2 4 x 4"}}}}"#,
            limb(8)
        ),
        "a",
    );
    assert!(
        e.contains("regions") && e.contains("expected `u0 u1 v0 v1`"),
        "{e}"
    );
}

#[test]
fn attach_outputs_the_control_mesh_with_five_edge_corners() {
    let g = common::geo(
        &format!(
            r#"{PLANE}, "l": {{"type": "hspline", "params": {{"topology": "cylinder", "rows": 6, "columns": 8, "size": [0.5, 2]}}}},
               "a": {{"type": "attach", "inputs": ["p", "l"], "params": {{"output": "control_mesh", "regions": [{{"u": [2, 4], "v": [2, 4]}}]}}}}"#
        ),
        "a",
    );
    // 64 parent vertices less 1 inside the region, plus 4 limb rows of 8.
    assert_eq!(g.num_points(), 63 + 32);
    // 49 parent faces less 4, plus 4 rows of limb faces.
    assert_eq!(g.num_prims(), 45 + 32);
    let mut valence = vec![0; g.num_points()];
    let mut edges = std::collections::HashSet::new();
    for f in 0..g.num_prims() {
        let r = g.prim_points(f);
        for k in 0..r.len() {
            let (a, b) = (r[k], r[(k + 1) % r.len()]);
            if edges.insert((a.min(b), a.max(b))) {
                valence[a as usize] += 1;
                valence[b as usize] += 1;
            }
        }
    }
    assert_eq!(valence.iter().filter(|&&n| n == 5).count(), 4);
}
