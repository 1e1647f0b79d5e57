//! The remesh node through the engine: a sphere remeshed to its relative
//! target length keeps its attributes and groups and stays closed, a box
//! keeps its corners, the result is the same bytes on one and two
//! threads, and bad values name their parameter.

mod common;

use common::{cook_errors, geo};
use geode_geo::glam::Vec3;
use geode_geo::AttribClass;

const DECORATED_SPHERE: &str = r#"
    "s": {"type": "sphere", "params": {"rows": 24, "columns": 48}},
    "c": {"type": "attribute_randomize", "inputs": ["s"]},
    "top": {"type": "group_bbox", "inputs": ["c"], "params": {"group": "top", "min": [-2, 0.5, -2], "max": [2, 2, 2]}}"#;

#[test]
fn remesh_carries_attributes_and_groups_on_a_sphere() {
    let g = geo(
        &format!(
            r#"{DECORATED_SPHERE}, "r": {{"type": "remesh", "inputs": ["top"], "params": {{"target_length": 0.04}}}}"#
        ),
        "r",
    );
    assert!(g.num_prims() > 1000);
    assert!((0..g.num_prims()).all(|k| g.prim_points(k).len() == 3));
    assert_eq!(
        g.attrib(AttribClass::Point, "Cd").map(|a| a.len()),
        Some(g.num_points())
    );
    let top = &g.point_groups()["top"];
    for (i, p) in g.positions().iter().enumerate() {
        // Away from the group's edge, membership follows the position.
        if (p.y - 0.5).abs() > 0.1 {
            assert_eq!(top.contains(i), p.y > 0.5, "{p}");
        }
        assert!((p.length() - 1.0).abs() < 0.01, "{p}");
    }
}

#[test]
fn remesh_keeps_the_corners_of_a_box_and_is_deterministic() {
    let nodes = r#""b": {"type": "box", "params": {"size": [2, 1, 1]}},
        "r": {"type": "remesh", "inputs": ["b"], "params": {"relative": false, "target_length": 0.1}}"#;
    let one = common::cook_on(1, nodes, "r");
    let two = common::cook_on(2, nodes, "r");
    assert_eq!(one.content_hash(), two.content_hash());
    for x in [-1.0f32, 1.0] {
        for y in [-0.5f32, 0.5] {
            for z in [-0.5f32, 0.5] {
                assert!(
                    one.positions().contains(&Vec3::new(x, y, z)),
                    "corner {x} {y} {z}"
                );
            }
        }
    }
}

#[test]
fn remesh_names_the_parameter_at_fault() {
    for (params, param) in [
        (r#""target_length": 0"#, "target_length"),
        (
            r#""sizing": "adaptive", "min_length": 0.2, "max_length": 0.1"#,
            "min_length",
        ),
        (r#""sizing": "adaptive", "tolerance": -1"#, "tolerance"),
        (r#""feature_group": "nothing""#, "feature_group"),
    ] {
        let errors = cook_errors(
            &format!(
                r#""s": {{"type": "sphere"}}, "r": {{"type": "remesh", "inputs": ["s"], "params": {{{params}}}}}"#
            ),
            "r",
        );
        assert_eq!(errors.len(), 1, "{errors:?}");
        assert_eq!(errors[0].param.as_deref(), Some(param), "{}", errors[0]);
    }
    let errors = cook_errors(
        r#""l": {"type": "curve_line"}, "r": {"type": "remesh", "inputs": ["l"]}"#,
        "r",
    );
    assert!(errors[0].to_string().contains("polygons"), "{}", errors[0]);
}
