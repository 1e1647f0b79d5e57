//! Every node type of the library, cooked through the engine and checked
//! against hand-computed or analytic answers.

mod common;

use common::{cook_at, err, geo};
use geode_geo::glam::Vec3;
use geode_geo::{ops, AttribClass, Geometry};
use geode_graph::{load_str, Cache, CookOptions, Engine};

fn closed(g: &Geometry) -> bool {
    g.topology().manifold_report(g).is_closed_manifold()
}

#[test]
fn primitives_are_closed_with_the_right_volume() {
    let b = geo(
        r#""b": {"type": "box", "params": {"size": [1, 2, 3], "divisions": [2, 3, 4], "center": [5, 0, 0]}}"#,
        "b",
    );
    assert!(closed(&b));
    assert!((ops::signed_volume(&b) - 6.0).abs() < 1e-4);
    assert_eq!(b.num_prims(), 2 * (2 * 3 + 3 * 4 + 2 * 4));
    assert_eq!(ops::bounds(&b).unwrap().center(), Vec3::new(5.0, 0.0, 0.0));

    let s = geo(
        r#""s": {"type": "sphere", "params": {"radius": 2, "rows": 64, "columns": 128}}"#,
        "s",
    );
    assert!(closed(&s));
    let v = 4.0 / 3.0 * std::f32::consts::PI * 8.0;
    assert!((ops::signed_volume(&s) - v).abs() / v < 0.005);

    let t = geo(
        r#""t": {"type": "torus", "params": {"major_radius": 2, "minor_radius": 0.5, "rows": 48, "columns": 96}}"#,
        "t",
    );
    assert!(closed(&t));
    let v = 2.0 * std::f32::consts::PI.powi(2) * 2.0 * 0.25;
    assert!((ops::signed_volume(&t) - v).abs() / v < 0.01);

    let tube = geo(
        r#""t": {"type": "tube", "params": {"radius": 1, "height": 3, "columns": 64, "caps": true}}"#,
        "t",
    );
    assert!(closed(&tube));
    let open = geo(
        r#""t": {"type": "tube", "params": {"caps": false, "columns": 8}}"#,
        "t",
    );
    assert_eq!(open.topology().boundary_edges().len(), 16);

    let g = geo(
        r#""g": {"type": "grid", "params": {"size": [4, 2], "rows": 2, "columns": 4}}"#,
        "g",
    );
    assert_eq!((g.num_points(), g.num_prims()), (15, 8));
    assert!(g.attrib(AttribClass::Point, "uv").is_some());
    assert!((ops::surface_area(&g) - 8.0).abs() < 1e-5);
}

#[test]
fn transform_order_and_pivot() {
    // Rotating 90 degrees about Y takes +X to -Z; about a pivot at +X it stays.
    let base = r#""p": {"type": "box", "params": {"size": [0, 0, 0], "center": [1, 0, 0]}},"#;
    let g = geo(
        &format!(
            r#"{base} "t": {{"type": "transform", "inputs": ["p"], "params": {{"rotate": [0, 90, 0]}}}}"#
        ),
        "t",
    );
    assert!((g.positions()[0] - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
    let g = geo(
        &format!(
            r#"{base} "t": {{"type": "transform", "inputs": ["p"], "params": {{"rotate": [0, 90, 0], "pivot": [1, 0, 0], "translate": [0, 2, 0]}}}}"#
        ),
        "t",
    );
    assert!((g.positions()[0] - Vec3::new(1.0, 2.0, 0.0)).length() < 1e-6);
    // Scale then rotate then translate.
    let g = geo(
        &format!(
            r#"{base} "t": {{"type": "transform", "inputs": ["p"], "params": {{"scale": [3, 1, 1], "uniform_scale": 2, "rotate": [0, 0, 90], "translate": [0, 0, 1]}}}}"#
        ),
        "t",
    );
    assert!((g.positions()[0] - Vec3::new(0.0, 6.0, 1.0)).length() < 1e-5);
}

#[test]
fn animated_parameters_follow_the_frame() {
    let nodes = r#""b": {"type": "box", "params": {"size": [1, 1, 1]}},
        "t": {"type": "transform", "inputs": ["b"], "params": {"translate": [{"keys": [{"frame": 1, "value": 0}, {"frame": 11, "value": 10}]}, 0, 0]}}"#;
    let at = |f: f64| {
        ops::bounds(cook_at(nodes, "t", f).unwrap().as_geometry().unwrap())
            .unwrap()
            .center()
            .x
    };
    assert_eq!(at(1.0), 0.0);
    assert!(
        (at(6.5) - 5.5).abs() < 1e-6,
        "fractional frames interpolate"
    );
    assert_eq!(at(50.0), 10.0);
}

#[test]
fn merge_switch_null() {
    let nodes = r#""a": {"type": "box"}, "b": {"type": "sphere", "params": {"rows": 4, "columns": 6}},
        "m": {"type": "merge", "inputs": ["a", "b"]},
        "s": {"type": "switch", "inputs": ["a", "b"], "params": {"index": 1}},
        "far": {"type": "switch", "inputs": ["a", "b"], "params": {"index": 7}},
        "n": {"type": "null", "inputs": ["m"]}"#;
    let a = geo(nodes, "a");
    let b = geo(nodes, "b");
    assert_eq!(
        geo(nodes, "m").num_points(),
        a.num_points() + b.num_points()
    );
    assert_eq!(geo(nodes, "s").content_hash(), b.content_hash());
    assert_eq!(
        geo(nodes, "far").content_hash(),
        b.content_hash(),
        "index clamps"
    );
    assert_eq!(
        geo(nodes, "n").content_hash(),
        geo(nodes, "m").content_hash()
    );
}

#[test]
fn attributes_create_and_randomize() {
    let nodes = r#""g": {"type": "grid", "params": {"rows": 10, "columns": 10}},
        "c": {"type": "attribute_create", "inputs": ["g"], "params": {"name": "mass", "class": "primitive", "type": "float", "value": [2.5, 0, 0, 0]}},
        "v": {"type": "attribute_create", "inputs": ["g"], "params": {"name": "up", "type": "normal", "value": [0, 1, 0, 0]}},
        "r": {"type": "attribute_randomize", "inputs": ["g"], "params": {"name": "Cd", "min": [0.5, 0, 0], "max": [1, 0.1, 0], "seed": 3}},
        "r2": {"type": "attribute_randomize", "inputs": ["g"], "params": {"name": "Cd", "min": [0.5, 0, 0], "max": [1, 0.1, 0], "seed": 4}},
        "bad": {"type": "attribute_create", "inputs": ["g"], "params": {"name": "2bad"}}"#;
    let c = geo(nodes, "c");
    assert!(c
        .attrib(AttribClass::Primitive, "mass")
        .unwrap()
        .as_f32()
        .unwrap()
        .iter()
        .all(|&m| m == 2.5));
    let v = geo(nodes, "v");
    assert_eq!(
        v.attrib(AttribClass::Point, "up").unwrap().type_info,
        geode_geo::TypeInfo::Normal
    );
    let r = geo(nodes, "r");
    let cd = r
        .attrib(AttribClass::Point, "Cd")
        .unwrap()
        .as_vec3()
        .unwrap();
    assert!(cd
        .iter()
        .all(|c| (0.5..1.0).contains(&c.x) && (0.0..0.1).contains(&c.y) && c.z == 0.0));
    assert_eq!(
        geo(nodes, "r").content_hash(),
        r.content_hash(),
        "same seed, same values"
    );
    assert_ne!(geo(nodes, "r2").content_hash(), r.content_hash());
    assert_eq!(err(nodes, "bad"), "/bad (parameter `name`): `2bad` is not a valid attribute name (letters, digits and _, not starting with a digit)");
}

#[test]
fn groups_and_delete() {
    let nodes = r#""g": {"type": "grid", "params": {"size": [10, 10], "rows": 10, "columns": 10}},
        "box": {"type": "group_bbox", "inputs": ["g"], "params": {"group": "mid", "min": [-1.1, -1, -1.1], "max": [1.1, 1, 1.1]}},
        "ex": {"type": "group_expression", "inputs": ["g"], "params": {"group": "east", "class": "primitive", "expression": "x > 0 && abs(z) < 2"}},
        "del": {"type": "delete", "inputs": ["ex"], "params": {"group": "east", "class": "primitive"}},
        "keep": {"type": "delete", "inputs": ["ex"], "params": {"group": "east", "class": "primitive", "invert": true}},
        "delp": {"type": "delete", "inputs": ["box"], "params": {"group": "mid", "class": "point"}},
        "typo": {"type": "delete", "inputs": ["ex"], "params": {"group": "west", "class": "primitive"}},
        "badex": {"type": "group_expression", "inputs": ["g"], "params": {"expression": "x >"}}"#;
    // Points at x, z in {-1, 0, 1}: 9 of them.
    assert_eq!(geo(nodes, "box").point_groups()["mid"].count(), 9);
    // Primitive centroids at x in {0.5..4.5} (5 columns) and z in {-1.5..1.5} (4 rows).
    assert_eq!(geo(nodes, "ex").prim_groups()["east"].count(), 20);
    assert_eq!(geo(nodes, "del").num_prims(), 80);
    assert_eq!(geo(nodes, "keep").num_prims(), 20);
    // Deleting 9 interior points removes the 16 quads around them.
    let d = geo(nodes, "delp");
    assert_eq!((d.num_points(), d.num_prims()), (112, 84));
    assert_eq!(
        err(nodes, "typo"),
        "/typo (parameter `group`): no primitive group `west` (primitive groups: east)"
    );
    assert_eq!(
        err(nodes, "badex"),
        "/badex (parameter `expression`): column 4: expected a value, found the end"
    );
}

#[test]
fn normals_fuse_triangulate() {
    let nodes = r#""b": {"type": "box", "params": {"size": [2, 2, 2]}},
        "pn": {"type": "normals", "inputs": ["b"], "params": {"class": "point"}},
        "vn": {"type": "normals", "inputs": ["pn"], "params": {"class": "vertex", "cusp_angle": 30}},
        "t": {"type": "triangulate", "inputs": ["b"]},
        "s": {"type": "sphere", "params": {"rows": 8, "columns": 8}},
        "m": {"type": "merge", "inputs": ["s", "s"]},
        "f": {"type": "fuse", "inputs": ["m"], "params": {"distance": 0.0001}}"#;
    let pn = geo(nodes, "pn");
    for (p, n) in pn.positions().iter().zip(
        pn.attrib(AttribClass::Point, "N")
            .unwrap()
            .as_vec3()
            .unwrap(),
    ) {
        assert!((*n - p.normalize()).length() < 1e-6);
    }
    let vn = geo(nodes, "vn");
    assert!(
        vn.attrib(AttribClass::Point, "N").is_none(),
        "one N at a time"
    );
    let n = vn
        .attrib(AttribClass::Vertex, "N")
        .unwrap()
        .as_vec3()
        .unwrap();
    assert!(
        n.iter().all(|v| v.abs().max_element() == 1.0),
        "hard cube edges keep face normals"
    );
    let t = geo(nodes, "t");
    assert_eq!(t.num_prims(), 12);
    assert!(closed(&t));
    let f = geo(nodes, "f");
    let s = geo(nodes, "s");
    assert_eq!(f.num_points(), s.num_points());
    assert_eq!(f.num_prims(), 2 * s.num_prims());
}

#[test]
fn bundles_pack_add_extract() {
    let nodes = r#""a": {"type": "box"}, "b": {"type": "sphere", "params": {"rows": 4, "columns": 4}},
        "p": {"type": "bundle_pack", "inputs": ["a", "b"], "params": {"names": "body, head"}},
        "q": {"type": "bundle_add", "inputs": ["p", "a"], "params": {"name": "spare"}},
        "x": {"type": "bundle_extract", "inputs": ["q"], "params": {"name": "head"}},
        "missing": {"type": "bundle_extract", "inputs": ["q"], "params": {"name": "tail"}}"#;
    let q = cook_at(nodes, "q", 1.0).unwrap();
    assert_eq!(
        q.as_bundle().unwrap().entries.keys().collect::<Vec<_>>(),
        vec!["body", "head", "spare"]
    );
    assert_eq!(
        geo(nodes, "x").content_hash(),
        geo(nodes, "b").content_hash()
    );
    assert_eq!(
        err(nodes, "missing"),
        "/missing (parameter `name`): the bundle has no `tail` (it has: body, head, spare)"
    );
}

#[test]
fn file_read_is_keyed_by_content_and_write_writes() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("tri.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let out = dir.path().join("copy.ply");
    let nodes = format!(
        r#""f": {{"type": "file", "params": {{"file": "{}"}}}}, "w": {{"type": "write", "inputs": ["f"], "params": {{"file": "{}"}}}}"#,
        obj.display(),
        out.display()
    );
    let text =
        format!(r#"{{"geode": "network", "version": 1, "output": "w", "nodes": {{{nodes}}}}}"#);
    let cache = Cache::new(1 << 24);
    let engine = Engine::new(load_str(&text, &geode_nodes::registry()).unwrap(), &cache);
    let first = engine.cook_output(&CookOptions::at_frame(1.0)).unwrap();
    assert_eq!(first.value.as_geometry().unwrap().num_prims(), 1);
    assert!(out.exists(), "the write node wrote its file");
    // The read is cached; the write is an output and runs again.
    std::fs::remove_file(&out).unwrap();
    let second = engine.cook_output(&CookOptions::at_frame(1.0)).unwrap();
    assert_eq!(second.cooked(), vec!["/w"]);
    assert!(out.exists(), "written again");
    // Same path, new content: the file node recooks.
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\n").unwrap();
    let again = engine.cook_output(&CookOptions::at_frame(1.0)).unwrap();
    assert_eq!(again.cooked(), vec!["/f", "/w"]);
    assert_eq!(again.value.as_geometry().unwrap().num_points(), 4);
    let missing = err(
        r#""f": {"type": "file", "params": {"file": "/nonexistent/x.obj"}}"#,
        "f",
    );
    assert_eq!(
        missing,
        "/f (parameter `file`): /nonexistent/x.obj: No such file or directory (os error 2)"
    );
}
