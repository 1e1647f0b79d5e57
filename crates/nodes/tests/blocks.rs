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
