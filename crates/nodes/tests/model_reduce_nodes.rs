//! The polyreduce node cooked through networks: targets met on a closed
//! sphere that stays closed, attributes and groups carried, bad
//! parameters named in their errors.

mod common;

use common::{cook_errors, geo};
use geode_geo::{AttribClass, Geometry};
use geode_op::ErrorKind;

fn closed(g: &Geometry) -> bool {
    g.topology().manifold_report(g).is_closed_manifold()
}

const SPHERE: &str = r#"
    "s": {"type": "sphere", "params": {"rows": 40, "columns": 80}},
    "w": {"type": "wrangle", "inputs": ["s"], "params": {"snippet": "f@h = @P.y;"}},
    "top": {"type": "group_expression", "inputs": ["w"],
            "params": {"group": "top", "class": "primitive", "expression": "y > 0.3"}}"#;

#[test]
fn a_sphere_reduces_to_each_target_and_stays_closed() {
    let full = geo(
        &format!(r#"{SPHERE}, "t": {{"type": "triangulate", "inputs": ["top"]}}"#),
        "t",
    );
    let n = full.num_prims();
    for (params, most) in [
        (r#"{"percent": 20}"#, (n as f64 * 0.2).round() as usize),
        (r#"{"target": "count", "count": 500}"#, 500),
        (r#"{"target": "error", "max_error": 0.002}"#, n / 2),
    ] {
        let g = geo(
            &format!(
                r#"{SPHERE}, "r": {{"type": "polyreduce", "inputs": ["top"], "params": {params}}}"#
            ),
            "r",
        );
        assert!(closed(&g), "{params}");
        let exact = !params.contains("error");
        assert!(g.num_prims() <= most, "{params}: {}", g.num_prims());
        assert!(
            !exact || g.num_prims() + 2 > most,
            "{params}: {}",
            g.num_prims()
        );
        assert!((0..g.num_prims()).all(|k| g.prim_points(k).len() == 3));
        let h = g.attrib(AttribClass::Point, "h").unwrap().as_f32().unwrap();
        for (p, h) in g.positions().iter().zip(h) {
            assert!((p.y - h).abs() < 0.05, "h follows y: {h} at {p}");
        }
        assert!(g.prim_groups()["top"].count() > 0);
    }
}

#[test]
fn bad_parameters_are_named() {
    // Out of its range: the loader refuses it, naming the parameter.
    let text = common::net(
        &format!(
            r#"{SPHERE}, "r": {{"type": "polyreduce", "inputs": ["top"], "params": {{"percent": 120}}}}"#
        ),
        "r",
    );
    let e = geode_graph::load_str(&text, &geode_nodes::registry())
        .err()
        .expect("refused");
    let e = format!("{e:?}");
    assert!(e.contains("percent") && e.contains("100"), "{e}");
    // A curve is no mesh: the kernel says so.
    let e = cook_errors(
        r#""c": {"type": "curve_line"}, "r": {"type": "polyreduce", "inputs": ["c"]}"#,
        "r",
    );
    assert!(e[0].message.contains("takes polygons"), "{}", e[0].message);
    assert_ne!(e[0].kind, ErrorKind::Parameter);
}
