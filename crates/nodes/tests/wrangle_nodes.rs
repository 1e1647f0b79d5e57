//! The wrangle node in networks: spare parameters (animated too) read by
//! `ch()`, errors naming node, parameter, line and column, groups, extra
//! inputs, the frame in the key only when the snippet reads it, and outputs
//! sharing the columns they do not write with their inputs.

mod common;
use common::*;

use geode_geo::AttribClass;

#[test]
fn ch_reads_animated_spare_parameters() {
    let nodes = r#"
        "g": {"type": "grid", "params": {"rows": 4, "columns": 4}},
        "w": {"type": "wrangle", "inputs": ["g"],
              "spare": {"amp": "float", "dir": "vector", "label": "string", "steps": "int"},
              "params": {"snippet": "@P += chv(\"dir\") * ch(\"amp\") * chi(\"steps\"); s@label = chs(\"label\");",
                         "amp": {"keys": [{"frame": 1, "value": 0}, {"frame": 11, "value": 1}]},
                         "dir": [0, 1, 0], "label": "hi", "steps": 2}}"#;
    let at = |frame: f64| {
        cook_at(nodes, "w", frame)
            .unwrap()
            .as_geometry()
            .unwrap()
            .clone()
    };
    let (f1, f6) = (at(1.0), at(6.0));
    assert!(f1.positions().iter().all(|p| p.y.abs() < 1e-6));
    assert!(
        f6.positions().iter().all(|p| (p.y - 1.0).abs() < 1e-5),
        "{:?}",
        f6.positions()[0]
    );
    let label = f6
        .attrib(AttribClass::Point, "label")
        .unwrap()
        .as_strings()
        .unwrap()
        .get(0)
        .to_string();
    assert_eq!(label, "hi");
}

#[test]
fn compile_and_run_errors_carry_their_position_as_fields() {
    let position = |snippet: &str| {
        let nodes = format!(
            r#""g": {{"type": "grid"}}, "w": {{"type": "wrangle", "inputs": ["g"], "params": {{"snippet": {}}}}}"#,
            serde_json::to_string(snippet).unwrap()
        );
        let e = cook_errors(&nodes, "w");
        assert_eq!(e[0].param.as_deref(), Some("snippet"));
        assert_eq!(e[0].kind, geode_op::ErrorKind::Kernel);
        e[0].position.map(|p| (p.line, p.column))
    };
    assert_eq!(position("float speed = 1;\n@P.y += sped;"), Some((2, 9)));
    // Geometry edits applied after the run still name the call.
    assert_eq!(position("int n = 1;\n  addpoint(0, 99999);"), Some((2, 3)));
}

#[test]
fn compile_errors_name_node_parameter_line_and_column() {
    let e = err(
        r#""g": {"type": "grid"},
           "w": {"type": "wrangle", "inputs": ["g"], "params": {"snippet": "float speed = 1;\n@P.y += sped;"}}"#,
        "w",
    );
    assert!(e.contains("/w"), "{e}");
    assert!(e.contains("snippet"), "{e}");
    assert!(
        e.contains("line 2, column 9: undeclared variable 'sped' (did you mean 'speed'?)"),
        "{e}"
    );
    let e = err(
        r#""g": {"type": "grid"},
           "w": {"type": "wrangle", "inputs": ["g"], "spare": {"amp": "float"}, "params": {"snippet": "@P.y = ch(\"ampp\");"}}"#,
        "w",
    );
    assert!(
        e.contains("ch(\"ampp\"): the node has no parameter 'ampp' (did you mean 'amp'?)"),
        "{e}"
    );
}

#[test]
fn spare_declarations_are_checked_when_the_network_loads() {
    let e = err(r#""w": {"type": "grid", "spare": {"amp": "float"}}"#, "w");
    assert!(e.contains("a grid node takes no spare parameters"), "{e}");
    let e = err(
        r#""g": {"type": "grid"}, "w": {"type": "wrangle", "inputs": ["g"], "spare": {"amp": "double"}}"#,
        "w",
    );
    assert!(e.contains("unknown spare parameter type `double`"), "{e}");
    let e = err(
        r#""g": {"type": "grid"}, "w": {"type": "wrangle", "inputs": ["g"], "spare": {"group": "float"}}"#,
        "w",
    );
    assert!(e.contains("cannot reuse the name"), "{e}");
    let e = err(
        r#""g": {"type": "grid"}, "w": {"type": "wrangle", "inputs": ["g"], "spare": {"amp": "float"}, "params": {"amp": "x"}}"#,
        "w",
    );
    assert!(e.contains("amp"), "{e}");
}

#[test]
fn a_group_selects_the_elements_and_a_missing_one_is_named() {
    let g = geo(
        r#""g": {"type": "grid", "params": {"rows": 2, "columns": 2}},
           "s": {"type": "wrangle", "inputs": ["g"], "params": {"snippet": "setpointgroup(0, \"first\", @ptnum, @ptnum == 0);"}},
           "w": {"type": "wrangle", "inputs": ["s"], "params": {"group": "first", "snippet": "@P.y = 5;"}}"#,
        "w",
    );
    let ys: Vec<f32> = g.positions().iter().map(|p| p.y).collect();
    assert_eq!(ys[0], 5.0);
    assert!(ys[1..].iter().all(|y| *y == 0.0));
    let e = err(
        r#""g": {"type": "grid"}, "w": {"type": "wrangle", "inputs": ["g"], "params": {"group": "frist", "snippet": "@P.y = 5;"}}"#,
        "w",
    );
    assert!(e.contains("no point group `frist`"), "{e}");
}

#[test]
fn second_input_is_read_by_point_and_opinput() {
    let g = geo(
        r#""a": {"type": "grid", "params": {"rows": 3, "columns": 3}},
           "b": {"type": "transform", "inputs": ["a"], "params": {"translate": [0, 2, 0]}},
           "w": {"type": "wrangle", "inputs": ["a", "b"], "params": {"snippet": "@P.y = @opinput1_P.y + point(1, \"P\", @ptnum).y;"}}"#,
        "w",
    );
    assert!(g.positions().iter().all(|p| (p.y - 4.0).abs() < 1e-6));
}

#[test]
fn the_frame_keys_only_snippets_that_read_it() {
    let still = r#""g": {"type": "grid"}, "w": {"type": "wrangle", "inputs": ["g"], "params": {"snippet": "@P.y = 1;"}}"#;
    let moving = r#""g": {"type": "grid"}, "w": {"type": "wrangle", "inputs": ["g"], "params": {"snippet": "@P.y = @Frame;"}}"#;
    let y = |nodes: &str, f: f64| {
        cook_at(nodes, "w", f)
            .unwrap()
            .as_geometry()
            .unwrap()
            .positions()[0]
            .y
    };
    assert_eq!((y(still, 1.0), y(still, 3.0)), (1.0, 1.0));
    assert_eq!((y(moving, 1.0), y(moving, 3.0)), (1.0, 3.0));
    let keyed = |nodes: &str, f: f64| {
        let net = geode_graph::load_str(&net(nodes, "w"), &geode_nodes::registry()).unwrap();
        let cache = geode_graph::Cache::new(1 << 26);
        let e = geode_graph::Engine::new(net, &cache);
        e.cook_output(&geode_graph::CookOptions::at_frame(f))
            .unwrap()
            .value
            .identity()
    };
    assert_eq!(keyed(still, 1.0), keyed(still, 2.0));
    assert_ne!(keyed(moving, 1.0), keyed(moving, 2.0));
}

/// Seed 003's frames (examples/chain_vex.json) against polyframe's discrete
/// parallel transport on the same curve: both start from their own first
/// frame and turn by the same steps, so frame j relative to frame 0 must
/// agree.
#[test]
fn seed_003_frames_equal_polyframes_parallel_transport() {
    use geode_geo::glam::DQuat;
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/chain_vex.json");
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    doc["nodes"]["reference"] = serde_json::json!({
        "type": "polyframe", "inputs": ["curve"], "params": {"method": "parallel_transport", "tangent": "next"}
    });
    let net = geode_graph::load_str(&doc.to_string(), &geode_nodes::registry()).unwrap();
    let cache = geode_graph::Cache::new(1 << 28);
    let engine = geode_graph::Engine::new(net, &cache);
    let opts = geode_graph::CookOptions::at_frame(1.0);
    let orient = |node: &str| -> Vec<DQuat> {
        let v = engine.cook(node, &opts).unwrap_or_else(|e| panic!("{e:?}"));
        let g = v.value.as_geometry().unwrap().clone();
        let a = g.attrib(AttribClass::Point, "orient").expect("orient");
        let q: Vec<[f32; 4]> = match a.data() {
            geode_geo::AttribData::Vec4(v) => v.iter().map(|x| x.to_array()).collect(),
            geode_geo::AttribData::Quat(v) => v.iter().map(|x| x.to_array()).collect(),
            other => panic!("orient is {:?}", other.attrib_type()),
        };
        q.iter()
            .map(|q| {
                DQuat::from_xyzw(q[0] as f64, q[1] as f64, q[2] as f64, q[3] as f64).normalize()
            })
            .collect()
    };
    let (vex, reference) = (orient("/compute_parallel_frame"), orient("/reference"));
    assert_eq!(vex.len(), reference.len());
    let mut worst = 0.0f64;
    for j in 0..vex.len() {
        // Compare as rotation matrices (a quaternion and its negation agree).
        let a = geode_geo::glam::DMat3::from_quat(vex[j] * vex[0].inverse());
        let b = geode_geo::glam::DMat3::from_quat(reference[j] * reference[0].inverse());
        let d = (a - b)
            .to_cols_array()
            .iter()
            .fold(0.0f64, |m, x| m.max(x.abs()));
        worst = worst.max(d);
    }
    eprintln!("largest difference over {} frames: {worst:e}", vex.len());
    assert!(worst < 1e-6, "frames differ by {worst:e}");
}

/// Seed 001's solver (examples/coral_vex.json): the growth reaches a state
/// that no further frame changes, and every node of the skeleton lies within
/// the influence radius plus one step of an attractor the solid was filled
/// with (or is the birth point).
#[test]
fn seed_001_growth_terminates_inside_the_influence_region() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/coral_vex.json");
    let text = std::fs::read_to_string(path).unwrap();
    let net = geode_graph::load_str(&text, &geode_nodes::registry()).unwrap();
    let cache = geode_graph::Cache::new(1 << 29);
    let engine = geode_graph::Engine::new(net, &cache);
    let at = |node: &str, frame: f64| {
        let r = engine
            .cook(node, &geode_graph::CookOptions::at_frame(frame))
            .unwrap_or_else(|e| panic!("{e:?}"));
        r.value.as_geometry().unwrap().clone()
    };
    let food = at("/food", 1.0);
    let (late, later) = (at("/grow", 90.0), at("/grow", 120.0));
    assert_eq!(
        late.content_hash(),
        later.content_hash(),
        "the growth still changes after frame 90"
    );
    let nodes: Vec<usize> = {
        let g = late.point_groups().get("nodes").expect("the nodes group");
        (0..g.len()).filter(|&i| g.contains(i)).collect()
    };
    assert!(nodes.len() > 200, "only {} nodes grew", nodes.len());
    assert!(
        late.num_prims() + 1 >= nodes.len(),
        "every node but the birth point hangs on a branch"
    );
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    let inner = &doc["nodes"]["grow"]["network"]["nodes"];
    let reach = inner["associate"]["params"]["infrad"].as_f64().unwrap() as f32
        + inner["grow"]["params"]["rad"].as_f64().unwrap() as f32;
    let birth = geode_geo::glam::Vec3::new(0.0, 0.1, 0.0);
    for &n in &nodes {
        let p = late.positions()[n];
        let near = food
            .positions()
            .iter()
            .map(|a| a.distance(p))
            .fold(f32::INFINITY, f32::min);
        assert!(
            near <= reach + 1e-4 || p.distance(birth) < 1e-6,
            "node {n} at {p} is {near} from every attractor"
        );
    }
    // Every attractor was consumed or is out of any node's reach.
    let left = late
        .point_groups()
        .get("attractors")
        .map_or(0, |g| (0..g.len()).filter(|&i| g.contains(i)).count());
    assert!(
        left < food.num_points() / 10,
        "{left} of {} attractors left",
        food.num_points()
    );
}

/// A node's output shares every array it does not write with its input
/// (copy on write): the wrangle writing P and the transform writing P and
/// N copy those columns only, and the connectivity not at all.
#[test]
fn nodes_copy_only_the_columns_they_write() {
    use geode_graph::{load_str, Cache, CookOptions, Engine};
    let nodes = r#"
        "g": {"type": "grid", "params": {"rows": 20, "columns": 30}},
        "n": {"type": "normals", "inputs": ["g"], "params": {"class": "point"}},
        "w": {"type": "wrangle", "inputs": ["n"], "params": {"snippet": "@P += @N * 0.1;"}},
        "t": {"type": "transform", "inputs": ["n"], "params": {"rotate": [0, 30, 0]}}"#;
    let net = load_str(&net(nodes, "w"), &geode_nodes::registry()).unwrap();
    let cache = Cache::new(1 << 30);
    let engine = Engine::new(net, &cache);
    let opts = CookOptions::at_frame(1.0);
    let cook = |path: &str| {
        let r = engine.cook(path, &opts).unwrap();
        r.value.as_geometry().unwrap().clone()
    };
    let input = cook("/n");
    for (node, written) in [("/w", &["P"][..]), ("/t", &["P", "N"][..])] {
        let out = cook(node);
        assert_ne!(out.content_hash(), input.content_hash());
        for name in ["P", "N", "uv"] {
            let (a, b) = (
                input.attrib(AttribClass::Point, name).unwrap(),
                out.attrib(AttribClass::Point, name).unwrap(),
            );
            assert_eq!(
                !a.shares_values(b),
                written.contains(&name),
                "{node} {name}"
            );
        }
        assert_eq!(out.vertex_points().as_ptr(), input.vertex_points().as_ptr());
        assert_eq!(out.prim_offsets().as_ptr(), input.prim_offsets().as_ptr());
    }
    // The wrangle's P is computed from the input's, not from zeros.
    let w = cook("/w");
    let n = input
        .attrib(AttribClass::Point, "N")
        .unwrap()
        .as_vec3()
        .unwrap();
    for ((p, q), n) in input.positions().iter().zip(w.positions()).zip(n) {
        assert!((*q - (*p + *n * 0.1)).length() < 1e-6);
    }
}

/// "printf: prints a message to the console" (VEX printf): the cook's
/// messages carry it, lines joined across calls, in element order.
#[test]
fn printf_reaches_the_cook_messages() {
    let text = net(
        r#""g": {"type": "grid", "params": {"rows": 1, "columns": 1}},
           "w": {"type": "wrangle", "inputs": ["g"],
                 "params": {"snippet": "printf(\"pt %d\", @ptnum); printf(\" of %d\\n\", @numpt);"}}"#,
        "w",
    );
    let net = geode_graph::load_str(&text, &geode_nodes::registry()).unwrap();
    let cache = geode_graph::Cache::disabled();
    let r = geode_graph::Engine::new(net, &cache)
        .cook_output(&geode_graph::CookOptions::at_frame(1.0))
        .unwrap();
    let w = r.events.iter().find(|e| e.path == "/w").unwrap();
    assert_eq!(
        w.warnings.to_vec(),
        [
            "printf: pt 0 of 4",
            "printf: pt 1 of 4",
            "printf: pt 2 of 4",
            "printf: pt 3 of 4"
        ]
    );
}

/// The Group field takes Houdini's group patterns as well as a name.
#[test]
fn the_group_field_takes_a_pattern() {
    let moved = |group: &str| -> Vec<usize> {
        let nodes = format!(
            r#""g": {{"type": "grid", "params": {{"rows": 2, "columns": 2}}}},
               "w": {{"type": "wrangle", "inputs": ["g"],
                     "params": {{"snippet": "@P.y += 1;", "group": {}}}}}"#,
            serde_json::to_string(group).unwrap()
        );
        let g = geo(&nodes, "w");
        (0..g.num_points())
            .filter(|&i| g.positions()[i].y > 0.5)
            .collect()
    };
    assert_eq!(moved("0-3 ^1"), [0, 2, 3]);
    let right = moved("@P.x>0");
    assert_eq!(right.len(), 3, "{right:?}");
    assert!(moved("nosuch*").is_empty());
}
