//! The cut family's nodes (clip, mirror, polyfill, convex_hull, revolve)
//! cooked through networks: results closed where they should be, groups
//! and attributes carried, bad parameters named in their errors.

mod common;

use common::{cook_errors, err, geo};
use geode_geo::glam::Vec3;
use geode_geo::{ops, AttribClass, Geometry};
use geode_op::ErrorKind;

fn closed(g: &Geometry) -> bool {
    g.topology().manifold_report(g).is_closed_manifold()
}

fn floats<'a>(g: &'a Geometry, name: &str) -> &'a [f32] {
    g.attrib(AttribClass::Point, name)
        .unwrap()
        .as_f32()
        .unwrap()
}

const SPHERE_WITH_H_AND_TOP: &str = r#"
    "s": {"type": "sphere", "params": {"rows": 24, "columns": 48}},
    "w": {"type": "wrangle", "inputs": ["s"], "params": {"snippet": "f@h = @P.y;"}},
    "top": {"type": "group_expression", "inputs": ["w"],
            "params": {"group": "top", "class": "primitive", "expression": "y > 0.3"}}"#;

#[test]
fn clip_caps_the_cut_and_carries_groups_and_attributes() {
    let nodes = format!(
        r#"{SPHERE_WITH_H_AND_TOP},
        "c": {{"type": "clip", "inputs": ["top"],
              "params": {{"normal": [0.2, 1, 0.1], "distance": 0.1, "cap": "triangles"}}}}"#
    );
    let g = geo(&nodes, "c");
    assert!(closed(&g));
    assert!(ops::signed_volume(&g) > 0.0);
    let (cap, above, top) = (
        &g.prim_groups()["cap"],
        &g.prim_groups()["above"],
        &g.prim_groups()["top"],
    );
    assert!(cap.count() > 10 && above.count() == g.num_prims());
    assert!(top.count() > 0 && top.members().all(|p| !cap.contains(p)));
    let h = floats(&g, "h");
    for (p, h) in g.positions().iter().zip(h) {
        assert!((p.y - h).abs() < 1e-5, "h follows y on the cut");
    }
    // Both sides, points split: two closed parts.
    let both = format!(
        r#"{SPHERE_WITH_H_AND_TOP},
        "c": {{"type": "clip", "inputs": ["top"],
              "params": {{"keep": "both", "cap": "polygon", "split_points": true}}}}"#
    );
    let g = geo(&both, "c");
    assert!(closed(&g));
    assert_eq!(
        g.prim_groups()["above"].count() + g.prim_groups()["below"].count(),
        g.num_prims()
    );
}

#[test]
fn a_plane_with_no_direction_is_an_error_on_its_parameter() {
    for (node, param) in [
        ("clip", "normal"),
        ("mirror", "normal"),
        ("revolve", "axis"),
    ] {
        let nodes = format!(
            r#""b": {{"type": "box"}},
               "n": {{"type": "{node}", "inputs": ["b"], "params": {{"{param}": [0, 0, 0]}}}}"#
        );
        let e = cook_errors(&nodes, "n");
        assert_eq!(e[0].param.as_deref(), Some(param), "{node}");
        assert_eq!(e[0].kind, ErrorKind::Parameter);
        assert!(e[0].message.contains("no direction"), "{}", e[0].message);
    }
}

#[test]
fn mirror_makes_a_half_box_whole_with_normals_out() {
    let g = geo(
        r#""b": {"type": "box", "params": {"divisions": [2, 2, 2]}},
           "half": {"type": "clip", "inputs": ["b"], "params": {"normal": [1, 0, 0]}},
           "n": {"type": "normals", "inputs": ["half"], "params": {"class": "point"}},
           "m": {"type": "mirror", "inputs": ["n"]}"#,
        "m",
    );
    assert!(closed(&g));
    assert!((ops::signed_volume(&g) - 1.0).abs() < 1e-5);
    let mirrored = &g.prim_groups()["mirror"];
    assert_eq!(2 * mirrored.count(), g.num_prims());
    let n = g
        .attrib(AttribClass::Point, "N")
        .unwrap()
        .as_vec3()
        .unwrap();
    for (p, n) in g.positions().iter().zip(n) {
        assert!(n.dot(*p) > 0.0, "N at {p} points in: {n}");
    }
    // Only the image: the box's other half, reversed to face out.
    let image = geo(
        r#""b": {"type": "box"},
           "half": {"type": "clip", "inputs": ["b"], "params": {"normal": [1, 0, 0], "cap": "polygon"}},
           "m": {"type": "mirror", "inputs": ["half"], "params": {"keep_original": false}}"#,
        "m",
    );
    assert!(image.positions().iter().all(|p| p.x <= 1e-6));
    assert!((ops::signed_volume(&image) - 0.5).abs() < 1e-5);
}

#[test]
fn polyfill_closes_a_sphere_with_its_top_deleted() {
    let nodes = r#"
        "s": {"type": "sphere", "params": {"rows": 16, "columns": 32}},
        "top": {"type": "group_expression", "inputs": ["s"],
                "params": {"group": "top", "class": "primitive", "expression": "y > 0.8"}},
        "d": {"type": "delete", "inputs": ["top"], "params": {"group": "top"}},
        "f": {"type": "polyfill", "inputs": ["d"], "params": {"mode": "MODE"}}"#;
    for mode in ["triangles", "polygon", "fan"] {
        let g = geo(&nodes.replace("MODE", mode), "f");
        assert!(closed(&g), "{mode}");
        assert!(ops::signed_volume(&g) > 3.5, "{mode}");
        assert!(g.prim_groups()["polyfill"].count() > 0, "{mode}");
    }
    let e = err(&nodes.replace("MODE", "quads"), "f");
    assert!(e.contains("mode") && e.contains("quads"), "{e}");
}

#[test]
fn convex_hull_of_a_sphere_keeps_its_points_and_their_attributes() {
    let g = geo(
        r#""s": {"type": "sphere", "params": {"rows": 12, "columns": 24}},
           "w": {"type": "wrangle", "inputs": ["s"], "params": {"snippet": "f@h = @P.y;"}},
           "h": {"type": "convex_hull", "inputs": ["w"]}"#,
        "h",
    );
    assert!(closed(&g));
    // Every point of a sphere is on its hull.
    assert_eq!(g.num_points(), 12 * 24 - 24 + 2);
    assert!(ops::signed_volume(&g) > 3.9);
    for (p, h) in g.positions().iter().zip(floats(&g, "h")) {
        assert_eq!(p.y, *h);
    }
    let flat = geo(
        r#""g": {"type": "grid", "params": {"rows": 5, "columns": 7}},
           "h": {"type": "convex_hull", "inputs": ["g"]}"#,
        "h",
    );
    assert_eq!((flat.num_prims(), flat.num_points()), (1, 4));
}

#[test]
fn revolve_turns_a_line_into_a_tube_and_refuses_an_empty_sweep() {
    let g = geo(
        r#""l": {"type": "curve_line", "params": {"start": [1, 0, 0], "end": [1, 2, 0], "points": 3}},
           "r": {"type": "revolve", "inputs": ["l"], "params": {"divisions": 12, "uv": true}}"#,
        "r",
    );
    assert_eq!((g.num_points(), g.num_prims()), (36, 24));
    assert!(g.attrib(AttribClass::Vertex, "uv").is_some());
    for p in g.positions() {
        assert!((Vec3::new(p.x, 0.0, p.z).length() - 1.0).abs() < 1e-5);
    }
    let e = cook_errors(
        r#""l": {"type": "curve_line"},
           "r": {"type": "revolve", "inputs": ["l"], "params": {"start_angle": 90, "end_angle": 90}}"#,
        "r",
    );
    assert_eq!(e[0].param.as_deref(), Some("end_angle"));
    assert!(e[0].message.contains("nothing to revolve"));
}

#[test]
fn a_long_hull_stops_soon_after_a_cancel() {
    use geode_graph::{load_str, Cache, CookOptions, Engine};
    use geode_op::CancelToken;
    use std::time::{Duration, Instant};
    // Every point of a sphere is a hull vertex: about a million steps.
    let nodes = r#""s": {"type": "sphere", "params": {"rows": 700, "columns": 1400}},
        "n": {"type": "convex_hull", "inputs": ["s"]}"#;
    let net = load_str(&common::net(nodes, "n"), &geode_nodes::registry()).unwrap();
    let cache = std::sync::Arc::new(Cache::new(4 << 30));
    let engine = Engine::new(net, &cache);
    engine.cook("/s", &CookOptions::at_frame(1.0)).unwrap();
    let cancel = CancelToken::new();
    let mut opts = CookOptions::at_frame(1.0);
    opts.cancel = cancel.clone();
    std::thread::scope(|s| {
        let cook = s.spawn(|| engine.cook("/n", &opts));
        std::thread::sleep(Duration::from_millis(300));
        assert!(!cook.is_finished(), "the hull ended before the cancel");
        let t0 = Instant::now();
        cancel.cancel();
        let Err(e) = cook.join().unwrap() else {
            panic!("finished despite the cancel")
        };
        assert_eq!(e[0].kind, ErrorKind::Cancelled);
        assert!(
            t0.elapsed() < Duration::from_millis(200),
            "{:?}",
            t0.elapsed()
        );
    });
}
