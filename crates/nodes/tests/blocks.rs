//! Loops and solvers around wrangles: passes on the previous result, the
//! pass numbers in `@meta`, stopping on a detail attribute, frames from the
//! start frame, errors naming the pass, and the cache making a second cook
//! (or the next frame) cheap.

mod common;
use common::*;

use geode_geo::AttribClass;

fn y0(g: &geode_geo::Geometry) -> f32 {
    g.positions()[0].y
}

const LOOP: &str = r#"
    "g": {"type": "grid", "params": {"rows": 2, "columns": 2}},
    "l": {"type": "loop", "inputs": ["g"], "params": {"iterations": 5},
          "network": {"output": "step", "nodes": {
              "step": {"type": "wrangle", "inputs": ["@0", "@meta"],
                       "params": {"snippet": "@P.y += 1; f@it = detail(1, \"iteration\"); f@n = detail(1, \"numiterations\");"}}}}}"#;

#[test]
fn a_loop_runs_its_network_on_each_result() {
    let g = geo(LOOP, "l");
    assert_eq!(y0(&g), 5.0);
    let it = g
        .attrib(AttribClass::Point, "it")
        .unwrap()
        .as_f32()
        .unwrap()[0];
    let n = g.attrib(AttribClass::Point, "n").unwrap().as_f32().unwrap()[0];
    assert_eq!((it, n), (4.0, 5.0));
}

#[test]
fn a_loop_stops_when_its_attribute_says_so() {
    let g = geo(
        r#""g": {"type": "grid", "params": {"rows": 2, "columns": 2}},
           "l": {"type": "loop", "inputs": ["g"], "params": {"iterations": 100, "stop": "done"},
                 "network": {"output": "step", "nodes": {
                     "step": {"type": "wrangle", "inputs": ["@0"], "params": {"run_over": "detail",
                              "snippet": "i@count += 1; i@done = i@count >= 7;"}}}}}"#,
        "l",
    );
    assert_eq!(
        g.attrib(AttribClass::Detail, "count")
            .unwrap()
            .as_i32()
            .unwrap()[0],
        7
    );
}

const SOLVER: &str = r#"
    "g": {"type": "grid", "params": {"rows": 2, "columns": 2}},
    "s": {"type": "solver", "inputs": ["g"], "params": {"start_frame": 1},
          "network": {"output": "step", "nodes": {
              "step": {"type": "wrangle", "inputs": ["@0", "@meta"],
                       "params": {"snippet": "@P.y += 1; f@f = detail(1, \"frame\");"}}}}}"#;

#[test]
fn a_solver_cooks_each_frame_on_the_last() {
    let at = |f: f64| {
        cook_at(SOLVER, "s", f)
            .unwrap()
            .as_geometry()
            .unwrap()
            .clone()
    };
    assert_eq!(y0(&at(1.0)), 1.0);
    let g = at(5.0);
    assert_eq!(y0(&g), 5.0);
    assert_eq!(
        g.attrib(AttribClass::Point, "f").unwrap().as_f32().unwrap()[0],
        5.0
    );
    // Before its start frame a solver passes its input through.
    assert_eq!(y0(&at(0.0)), 0.0);
}

#[test]
fn the_cache_makes_the_next_frame_one_pass() {
    let net = geode_graph::load_str(&net(SOLVER, "s"), &geode_nodes::registry()).unwrap();
    let cache = geode_graph::Cache::new(1 << 26);
    let e = geode_graph::Engine::new(net, &cache);
    let first = e
        .cook("/s", &geode_graph::CookOptions::at_frame(10.0))
        .unwrap();
    let ran = |r: &geode_graph::CookResult| {
        r.events
            .iter()
            .filter(|x| !x.hit && x.path == "/s/step")
            .count()
    };
    assert_eq!(ran(&first), 10);
    let next = e
        .cook("/s", &geode_graph::CookOptions::at_frame(11.0))
        .unwrap();
    assert_eq!(ran(&next), 1, "frames 1-10 come from the cache");
    assert_eq!(y0(next.value.as_geometry().unwrap()), 11.0);
    let again = e
        .cook("/s", &geode_graph::CookOptions::at_frame(11.0))
        .unwrap();
    assert_eq!(ran(&again), 0);
}

#[test]
fn an_error_in_a_pass_names_the_pass() {
    let e = err(
        r#""g": {"type": "grid"},
           "l": {"type": "loop", "inputs": ["g"], "params": {"iterations": 3},
                 "network": {"output": "step", "nodes": {
                     "step": {"type": "wrangle", "inputs": ["@0", "@meta"],
                              "params": {"snippet": "if (detail(1, \"iteration\") == 2) addprim(0, \"nurbs\", 0);"}}}}}"#,
        "l",
    );
    assert!(e.contains("/l/step"), "{e}");
    assert!(e.contains("(iteration 2 of /l)"), "{e}");
}

#[test]
fn blocks_are_checked_when_the_network_loads() {
    let e = err(
        r#""g": {"type": "grid"}, "l": {"type": "loop", "inputs": ["g"], "params": {"iterations": -1}, "network": {"nodes": {}}}"#,
        "l",
    );
    assert!(e.contains("below the minimum"), "{e}");
    let e = err(
        r#""g": {"type": "grid"}, "l": {"type": "loop", "inputs": ["g"], "network": {"output": "w", "nodes": {"w": {"type": "wrangle", "inputs": ["@3"]}}}}"#,
        "l",
    );
    assert!(
        e.contains("refers to `@3` but the loop has 1 inputs"),
        "{e}"
    );
}

#[test]
fn wrangles_read_an_enclosing_subnets_spare_parameters() {
    let g = geo(
        r#""g": {"type": "grid", "params": {"rows": 2, "columns": 2}},
           "l": {"type": "loop", "inputs": ["g"], "spare": {"lift": "float"},
                 "params": {"iterations": 2, "lift": {"keys": [{"frame": 1, "value": 0.25}, {"frame": 5, "value": 1}]}},
                 "network": {"output": "step", "nodes": {
                     "step": {"type": "wrangle", "inputs": ["@0"], "params": {"snippet": "@P.y += ch(\"../lift\");"}}}}}"#,
        "l",
    );
    assert_eq!(y0(&g), 0.5);
    let e = err(
        r#""g": {"type": "grid"},
           "s": {"type": "subnet", "inputs": ["g"], "spare": {"lift": "float"}, "network": {"output": "w", "nodes": {
               "w": {"type": "wrangle", "inputs": ["@0"], "params": {"snippet": "@P.y += ch(\"../lfit\");"}}}}}"#,
        "s",
    );
    assert!(
        e.contains("no parameter '../lfit' (did you mean '../lift'?)"),
        "{e}"
    );
}

/// Three separate boxes (a row), each moved up by its piece number in a
/// for-each over connected pieces.
const FOR_EACH: &str = r#"
    "b": {"type": "box", "params": {"size": [1, 1, 1]}},
    "c": {"type": "copy_to_points", "inputs": ["b", "pts"]},
    "pts": {"type": "wrangle", "inputs": ["line"], "params": {"snippet": "@P = set(@ptnum * 3, 0, 0);"}},
    "line": {"type": "curve_line", "params": {"points": 3}},
    "f": {"type": "for_each", "inputs": ["c"],
          "network": {"output": "step", "nodes": {
              "step": {"type": "wrangle", "inputs": ["@0", "@meta"],
                       "params": {"snippet": "@P.y += detail(1, \"value\"); i@n = detail(1, \"numiterations\");"}}}}}"#;

#[test]
fn for_each_piece_cooks_each_piece_and_merges_in_order() {
    let g = geo(FOR_EACH, "f");
    let whole = geo(FOR_EACH, "c");
    assert_eq!(g.num_points(), whole.num_points());
    assert_eq!(g.num_prims(), whole.num_prims());
    // Piece k (the box at x = 3k) rose by k.
    for (q, w) in g.positions().iter().zip(whole.positions()) {
        let k = (w.x / 3.0).round();
        assert_eq!(q.y - w.y, k, "{w}");
    }
    assert_eq!(
        g.attrib(AttribClass::Point, "n").unwrap().as_i32().unwrap()[0],
        3
    );
    // The same bytes on one thread and on three.
    assert_eq!(
        cook_on(1, FOR_EACH, "f").content_hash(),
        cook_on(3, FOR_EACH, "f").content_hash()
    );
}

#[test]
fn for_each_named_piece_sees_its_name() {
    let g = geo(
        r#""b": {"type": "box"},
           "n": {"type": "wrangle", "inputs": ["b"], "params": {"run_over": "primitives", "snippet": "s@name = @primnum < 2 ? \"lid\" : \"body\";"}},
           "f": {"type": "for_each", "inputs": ["n"], "params": {"method": "attribute", "attribute": "name"},
                 "network": {"output": "step", "nodes": {
                     "step": {"type": "wrangle", "inputs": ["@0", "@meta"], "params": {"run_over": "primitives",
                              "snippet": "s@seen = detail(1, \"value\"); i@it = detail(1, \"iteration\"); i@count = nprimitives(0);"}}}}}"#,
        "f",
    );
    let seen = g
        .attrib(AttribClass::Primitive, "seen")
        .unwrap()
        .as_strings()
        .unwrap();
    let it = g
        .attrib(AttribClass::Primitive, "it")
        .unwrap()
        .as_i32()
        .unwrap()
        .to_vec();
    let count = g
        .attrib(AttribClass::Primitive, "count")
        .unwrap()
        .as_i32()
        .unwrap()
        .to_vec();
    assert_eq!(
        (0..6).map(|i| seen.get(i)).collect::<Vec<_>>(),
        ["lid", "lid", "body", "body", "body", "body"]
    );
    assert_eq!(it, [0, 0, 1, 1, 1, 1]);
    assert_eq!(count, [2, 2, 4, 4, 4, 4]);
}

#[test]
fn for_each_by_count_is_a_loop_and_errors_name_the_piece() {
    let g = geo(
        r#""g": {"type": "grid", "params": {"rows": 2, "columns": 2}},
           "f": {"type": "for_each", "inputs": ["g"], "params": {"method": "count", "iterations": 4},
                 "network": {"output": "step", "nodes": {
                     "step": {"type": "wrangle", "inputs": ["@0"], "params": {"snippet": "@P.y += 1;"}}}}}"#,
        "f",
    );
    assert_eq!(y0(&g), 4.0);
    let e = err(
        &FOR_EACH.replace(
            "@P.y += detail(1, \\\"value\\\");",
            "if (detail(1, \\\"value\\\") == 2) error(\\\"bad piece\\\");",
        ),
        "f",
    );
    assert!(
        e.contains("bad piece") && e.contains("piece 2 of /f"),
        "{e}"
    );
    let e = err(
        r#""b": {"type": "box"},
           "f": {"type": "for_each", "inputs": ["b"], "params": {"method": "attribute", "attribute": "nme"},
                 "network": {"output": "step", "nodes": {"step": {"type": "null", "inputs": ["@0"]}}}}"#,
        "f",
    );
    assert!(e.contains("no primitive attribute `nme`"), "{e}");
}

/// A point that rises one unit per frame, seen through time shifts.
const SHIFT: &str = r#"
    "p": {"type": "curve_line", "params": {"points": 2}},
    "rise": {"type": "wrangle", "inputs": ["p"], "params": {"snippet": "@P.y = @Frame;"}},
    "back": {"type": "time_shift", "inputs": ["rise"], "params": {"offset": -1}},
    "at": {"type": "time_shift", "inputs": ["rise"], "params": {"method": "frame", "frame": {"expr": "$F * 2"}}},
    "held": {"type": "time_shift", "inputs": ["rise"], "params": {"offset": 10, "clamp": true, "range": [1, 12]}}"#;

#[test]
fn time_shift_cooks_its_input_at_another_frame() {
    let at = |out: &str, f: f64| {
        cook_at(SHIFT, out, f)
            .unwrap()
            .as_geometry()
            .unwrap()
            .positions()[0]
            .y
    };
    assert_eq!(at("rise", 5.0), 5.0);
    assert_eq!(at("back", 5.0), 4.0);
    assert_eq!(at("at", 5.0), 10.0);
    assert_eq!(at("held", 1.0), 11.0);
    assert_eq!(at("held", 5.0), 12.0, "clamped to the range's end");
}

#[test]
fn time_shift_inside_a_solver_reads_the_previous_frame() {
    // A solver whose pass adds the input one frame back: y sums 0 + 1 + .. + F-1.
    let g = cook_at(
        r#""p": {"type": "curve_line", "params": {"points": 2}},
           "rise": {"type": "wrangle", "inputs": ["p"], "params": {"snippet": "@P.y = @Frame;"}},
           "back": {"type": "time_shift", "inputs": ["rise"], "params": {"offset": -1}},
           "s": {"type": "solver", "inputs": ["p", "back"], "params": {"start_frame": 1},
                 "network": {"output": "add", "nodes": {
                     "add": {"type": "wrangle", "inputs": ["@0", "@1"], "params": {"snippet": "@P.y += point(1, \"P\", @ptnum).y;"}}}}}"#,
        "s",
        4.0,
    )
    .unwrap();
    // Frames 2, 3, 4 add 1, 2, 3.
    assert_eq!(g.as_geometry().unwrap().positions()[0].y, 6.0);
}

#[test]
fn object_merge_reads_nodes_by_path() {
    let nodes = r#""b": {"type": "box"},
        "s": {"type": "subnet", "network": {"output": "inner", "nodes": {
            "inner": {"type": "sphere", "params": {"rows": 4, "columns": 8}},
            "up": {"type": "object_merge", "params": {"objects": "../b inner", "translate": [0, 2, 0]}}}}},
        "om": {"type": "object_merge", "params": {"objects": "/b /s/inner"}}"#;
    let b = geo(nodes, "b");
    let om = geo(nodes, "om");
    let sphere_prims = 4 * 8;
    assert_eq!(om.num_prims(), b.num_prims() + sphere_prims);
    assert_eq!(om.positions()[0], b.positions()[0]);
    let up = cook_at(nodes, "s", 1.0).unwrap();
    let _ = up;
    let inner_up = {
        let net = geode_graph::load_str(&net(nodes, "om"), &geode_nodes::registry()).unwrap();
        let cache = geode_graph::Cache::disabled();
        geode_graph::Engine::new(net, &cache)
            .cook("/s/up", &geode_graph::CookOptions::at_frame(1.0))
            .unwrap()
            .value
    };
    let g = inner_up.as_geometry().unwrap();
    assert_eq!(g.positions()[0].y, b.positions()[0].y + 2.0);
    // A name that is no node, and a cycle, are load errors naming the parameter.
    let e = err(
        r#""om": {"type": "object_merge", "params": {"objects": "nope"}}"#,
        "om",
    );
    assert!(
        e.contains("objects") && e.contains("`nope` (/nope) is not a node"),
        "{e}"
    );
    let e = err(
        r#""a": {"type": "object_merge", "params": {"objects": "c"}},
           "c": {"type": "transform", "inputs": ["a"]}"#,
        "c",
    );
    assert!(e.contains("cycle") || e.contains("loop"), "{e}");
}

#[path = "blocks/object_merge_file.rs"]
mod object_merge_file;
