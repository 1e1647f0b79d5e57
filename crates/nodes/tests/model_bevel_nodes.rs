//! The polybevel node cooked through networks: a box's edges and corners
//! bevelled closed with the closed-form volume, groups named, a point
//! group choosing edges, bad parameters named in their errors.

mod common;

use common::{cook_errors, err, geo};
use geode_geo::Geometry;
use geode_op::ErrorKind;

fn closed(g: &Geometry) -> bool {
    g.topology().manifold_report(g).is_closed_manifold()
}

fn volume(g: &Geometry) -> f64 {
    geode_geo::ops::signed_volume(g) as f64
}

#[test]
fn a_divided_box_chamfers_to_the_closed_form_volume() {
    let g = geo(
        r#""b": {"type": "box", "params": {"divisions": [3, 3, 3]}},
           "v": {"type": "polybevel", "inputs": ["b"], "params": {"offset": 0.1}}"#,
        "v",
    );
    assert!(closed(&g));
    let d = 0.1f64;
    let want = 1.0 - 6.0 * d * d + 16.0 / 3.0 * d.powi(3);
    assert!((volume(&g) - want).abs() < 1e-4, "{}", volume(&g));
    assert_eq!(g.prim_groups()["bevelCorners"].count(), 8);
    // Each of the 12 edges is three strips long.
    assert_eq!(g.prim_groups()["bevelEdges"].count(), 36);
}

#[test]
fn rounded_corners_points_and_named_groups() {
    let g = geo(
        r#""b": {"type": "box"},
           "v": {"type": "polybevel", "inputs": ["b"],
                 "params": {"offset": 0.2, "segments": 6, "edge_group": "round", "corner_group": "ball"}}"#,
        "v",
    );
    assert!(closed(&g));
    assert_eq!(g.prim_groups()["round"].count(), 72);
    assert_eq!(g.prim_groups()["ball"].count(), 8 * 36);
    let p = geo(
        r#""b": {"type": "box"},
           "v": {"type": "polybevel", "inputs": ["b"],
                 "params": {"affect": "points", "group": "0", "offset": 0.3}}"#,
        "v",
    );
    assert!(closed(&p));
    assert!(
        (volume(&p) - (1.0 - 0.027 / 6.0)).abs() < 1e-5,
        "{}",
        volume(&p)
    );
}

#[test]
fn bad_parameters_name_themselves() {
    // Out of their ranges: refused when the network loads.
    for (param, value) in [
        ("segments", "0"),
        ("profile", "2"),
        ("offset", "-1"),
        ("flat_angle", "270"),
    ] {
        let nodes = format!(
            r#""b": {{"type": "box"}},
               "v": {{"type": "polybevel", "inputs": ["b"], "params": {{"{param}": {value}}}}}"#
        );
        let e = err(&nodes, "v");
        assert!(e.contains(param), "{e}");
    }
    let e = cook_errors(
        r#""b": {"type": "box"},
           "v": {"type": "polybevel", "inputs": ["b"], "params": {"corner_group": "bevelEdges"}}"#,
        "v",
    );
    assert_eq!(e[0].param.as_deref(), Some("corner_group"));
    assert_eq!(e[0].kind, ErrorKind::Parameter);
    assert!(e[0].message.contains("name of its own"), "{}", e[0].message);
    let e = cook_errors(
        r#""b": {"type": "box"},
           "v": {"type": "polybevel", "inputs": ["b"], "params": {"group": "nothing"}}"#,
        "v",
    );
    assert!(e[0].message.contains("nothing"), "{}", e[0].message);
    // A mesh the kernel cannot bevel: its error, on the node.
    let e = cook_errors(
        r#""l": {"type": "curve_line"},
           "v": {"type": "polybevel", "inputs": ["l"]}"#,
        "v",
    );
    assert!(e[0].message.contains("polygons"), "{}", e[0].message);
}

/// One short edge lowers the clamped offset for the whole mesh: the user
/// is told, with the offset it came to.
#[test]
fn a_clamp_far_below_the_offset_is_a_warning() {
    let w = common::warnings(
        r#""b": {"type": "box", "params": {"size": [1, 1, 0.001]}},
           "v": {"type": "polybevel", "inputs": ["b"], "params": {"offset": 0.1}}"#,
        "/v",
    );
    assert!(
        w.iter()
            .any(|w| w.contains("the clamp lowered the offset from 0.1 to 0.0005")),
        "{w:?}"
    );
    // Any lowering is said (a unit box's edges allow 0.5); none at all is
    // not.
    let bevel = |offset: f32| {
        common::warnings(
            &format!(
                r#""b": {{"type": "box"}},
                   "v": {{"type": "polybevel", "inputs": ["b"], "params": {{"offset": {offset}}}}}"#
            ),
            "/v",
        )
    };
    let w = bevel(0.6);
    assert!(w.iter().any(|w| w.contains("from 0.6 to 0.5")), "{w:?}");
    assert!(bevel(0.4).is_empty());
}

/// With the clamp off, an offset past where bevels meet overlaps: said,
/// with the limit.
#[test]
fn an_unclamped_offset_past_the_limit_is_a_warning() {
    let bevel = |offset: f32| {
        common::warnings(
            &format!(
                r#""b": {{"type": "box"}},
                   "v": {{"type": "polybevel", "inputs": ["b"], "params": {{"offset": {offset}, "clamp": false}}}}"#
            ),
            "/v",
        )
    };
    let w = bevel(0.8);
    assert!(w.iter().any(|w| w.contains("passes 0.5")), "{w:?}");
    assert!(bevel(0.3).is_empty());
}

/// An inset past where a front's edges meet turns it inside out: said,
/// with how many.
#[test]
fn an_inset_that_overruns_the_fronts_is_a_warning() {
    let extrude = |inset: f32| {
        common::warnings(
            &format!(
                r#""b": {{"type": "box"}},
                   "v": {{"type": "polyextrude", "inputs": ["b"], "params": {{"distance": 0.2, "inset": {inset}, "connected": false}}}}"#
            ),
            "/v",
        )
    };
    let w = extrude(5.0);
    assert!(w.iter().any(|w| w.contains("6 front(s)")), "{w:?}");
    assert!(extrude(0.3).is_empty());
}
