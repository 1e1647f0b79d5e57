//! Cancellation latency per long-running node type: each workload is
//! cancelled mid-cook and must return `Cancelled` within 200 ms, with
//! nothing written. Inputs are cooked first (into the cache) so the cancel
//! lands in the node under test. The workloads run one after another (one
//! test), so each has the machine's cores to itself, as a user's cook does.

use std::sync::Arc;
use std::time::{Duration, Instant};

use geode_graph::{load_str, Cache, CookOptions, Engine};
use geode_op::{CancelToken, CookEnv, ErrorKind};

const LIMIT: Duration = Duration::from_millis(200);

/// Cooks `inputs` then, on a thread, `/n`; cancels after `after` and returns
/// how long the cook took to stop.
fn cancel_latency(nodes: &str, inputs: &[&str], after: Duration, hip: &str) -> Duration {
    let text =
        format!(r#"{{"geode": "network", "version": 1, "output": "n", "nodes": {{{nodes}}}}}"#);
    let net = load_str(&text, &geode_nodes::registry()).unwrap_or_else(|e| panic!("{e:?}"));
    let cache = Arc::new(Cache::new(8 << 30));
    let engine = Engine::new(net, &cache);
    let env = CookEnv::default().with_hip(hip);
    for i in inputs {
        let mut o = CookOptions::at_frame(1.0);
        o.env = env.clone();
        engine.cook(i, &o).unwrap_or_else(|e| panic!("{e:?}"));
    }
    let cancel = CancelToken::new();
    let mut opts = CookOptions::at_frame(1.0);
    opts.cancel = cancel.clone();
    opts.env = env;
    std::thread::scope(|s| {
        let cook = s.spawn(|| engine.cook("/n", &opts));
        std::thread::sleep(after);
        assert!(
            !cook.is_finished(),
            "the workload ended before it was cancelled: make it bigger"
        );
        let t0 = Instant::now();
        cancel.cancel();
        let r = cook.join().unwrap();
        let dt = t0.elapsed();
        match r {
            Err(e) => assert_eq!(e[0].kind, ErrorKind::Cancelled, "{}", e[0]),
            Ok(_) => panic!("finished despite the cancel"),
        }
        dt
    })
}

fn check(name: &str, nodes: &str, inputs: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let hip = dir.path().to_str().unwrap();
    let dt = cancel_latency(nodes, inputs, Duration::from_millis(300), hip);
    eprintln!(
        "{name}: stopped {:.1} ms after the cancel",
        dt.as_secs_f64() * 1e3
    );
    assert!(dt < LIMIT, "{name} took {dt:?} to stop");
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert!(left.is_empty(), "{name} left {left:?}");
}

fn scatter_with_relax_stops_promptly() {
    check(
        "scatter relax",
        r#""s": {"type": "sphere", "params": {"rows": 32, "columns": 64}},
           "n": {"type": "scatter", "params": {"count": 2000000, "relax": true}, "inputs": ["s"]}"#,
        &["/s"],
    );
}

fn surface_scatter_with_relax_stops_promptly() {
    check(
        "scatter surface relax",
        r#""s": {"type": "sphere", "params": {"rows": 32, "columns": 64}},
           "n": {"type": "scatter", "params": {"mode": "surface", "count": 1000000, "relax": true}, "inputs": ["s"]}"#,
        &["/s"],
    );
}

fn colonization_stops_promptly() {
    check(
        "space_colonize",
        r#""s": {"type": "sphere"},
           "a": {"type": "scatter", "params": {"count": 400000}, "inputs": ["s"]},
           "b": {"type": "curve_line", "params": {"points": 2, "end": [0, 0.01, 0]}},
           "n": {"type": "space_colonize", "params": {"influence": 0.05, "kill": 0.01, "step": 0.002, "iterations": 100000}, "inputs": ["a", "b"]}"#,
        &["/a", "/b"],
    );
}

fn polygonise_stops_promptly() {
    check(
        "polygonise",
        r#""f": {"type": "frep_torus", "params": {"major_radius": 0.6, "minor_radius": 0.3}},
           "n": {"type": "polygonise", "params": {"depth": 10}, "inputs": ["f"]}"#,
        &["/f"],
    );
}

fn subdivide_stops_promptly() {
    check(
        "subdivide",
        r#""s": {"type": "sphere", "params": {"rows": 64, "columns": 128}},
           "n": {"type": "subdivide", "params": {"levels": 5}, "inputs": ["s"]}"#,
        &["/s"],
    );
}

fn sweep_stops_promptly() {
    check(
        "sweep",
        r#""c": {"type": "curve_helix", "params": {"points": 500000, "turns": 1000}},
           "n": {"type": "sweep", "params": {"sides": 48, "caps": false}, "inputs": ["c"]}"#,
        &["/c"],
    );
}

fn frep_sweep_meshing_stops_promptly() {
    check(
        "frep_sweep + polygonise",
        r#""c": {"type": "curve_helix", "params": {"points": 400, "turns": 8}},
           "f": {"type": "frep_sweep", "params": {"radius": 0.05}, "inputs": ["c"]},
           "n": {"type": "polygonise", "params": {"depth": 9, "min": [-1.1, -0.1, -1.1], "max": [1.1, 4.1, 1.1]}, "inputs": ["f"]}"#,
        &["/f"],
    );
}

fn real_copies_stop_promptly() {
    check(
        "copy_to_points",
        r#""s": {"type": "sphere", "params": {"rows": 32, "columns": 64}},
           "g": {"type": "grid", "params": {"rows": 150, "columns": 150}},
           "n": {"type": "copy_to_points", "params": {"pack": false}, "inputs": ["s", "g"]}"#,
        &["/s", "/g"],
    );
}

fn writer(ext: &str) {
    check(
        &format!("write .{ext}"),
        &format!(
            r#""g": {{"type": "grid", "params": {{"rows": 4000, "columns": 4000}}}},
               "n": {{"type": "write", "params": {{"file": "$HIP/out.{ext}"}}, "inputs": ["g"]}}"#
        ),
        &["/g"],
    );
}

fn every_writer_stops_promptly_and_writes_nothing() {
    for ext in ["obj", "ply", "stl", "glb", "usda"] {
        writer(ext);
    }
}

fn unpacking_for_a_writer_stops_promptly() {
    check(
        "write .ply of packed copies",
        r#""s": {"type": "sphere", "params": {"rows": 16, "columns": 32}},
           "g": {"type": "grid", "params": {"rows": 600, "columns": 600}},
           "c": {"type": "copy_to_points", "inputs": ["s", "g"]},
           "n": {"type": "write", "params": {"file": "$HIP/out.ply"}, "inputs": ["c"]}"#,
        &["/c"],
    );
}

/// The modelling family, each on an input big enough to take seconds.
/// (Cancels at 20 ms to 1.5 s into remesh and polyreduce of a million
/// triangles, probed in this build: 1-130 ms and 11-72 ms.)
fn modelling_nodes_stop_promptly() {
    let cases = [
        (
            "boolean",
            r#""a": {"type": "sphere", "params": {"rows": 400, "columns": 800}},
               "b": {"type": "sphere", "params": {"rows": 400, "columns": 800, "center": [0.5, 0.3, 0.2]}},
               "n": {"type": "boolean", "params": {"operation": "union"}, "inputs": ["a", "b"]}"#,
            &["/a", "/b"][..],
        ),
        (
            "polybevel",
            r#""s": {"type": "box", "params": {"divisions": [150, 150, 150]}},
               "n": {"type": "polybevel", "params": {"offset": 0.001, "segments": 4, "ignore_flat": false}, "inputs": ["s"]}"#,
            &["/s"][..],
        ),
        (
            "polywire",
            r#""g": {"type": "grid", "params": {"rows": 250, "columns": 250}},
               "n": {"type": "polywire", "params": {"radius": 0.005}, "inputs": ["g"]}"#,
            &["/g"][..],
        ),
        (
            "remesh",
            r#""s": {"type": "sphere", "params": {"rows": 500, "columns": 1000}},
               "t": {"type": "triangulate", "inputs": ["s"]},
               "n": {"type": "remesh", "params": {"target_length": 0.002}, "inputs": ["t"]}"#,
            &["/t"][..],
        ),
        (
            "polyreduce",
            r#""s": {"type": "sphere", "params": {"rows": 500, "columns": 1000}},
               "t": {"type": "triangulate", "inputs": ["s"]},
               "n": {"type": "polyreduce", "params": {"percent": 5}, "inputs": ["t"]}"#,
            &["/t"][..],
        ),
        (
            "polyextrude",
            r#""g": {"type": "grid", "params": {"rows": 200, "columns": 200}},
               "n": {"type": "polyextrude", "params": {"distance": 0.1, "connected": false, "divisions": 100}, "inputs": ["g"]}"#,
            &["/g"][..],
        ),
    ];
    for (name, nodes, inputs) in cases {
        check(name, nodes, inputs);
    }
}

fn attribute_nodes_stop_promptly() {
    let cases = [
        (
            "attribute_transfer",
            r#""s": {"type": "sphere", "params": {"rows": 1000, "columns": 2000}},
               "w": {"type": "wrangle", "inputs": ["s"], "params": {"snippet": "f@w = @ptnum;"}},
               "d": {"type": "sphere", "params": {"rows": 1001, "columns": 2001, "radius": 0.9}},
               "n": {"type": "attribute_transfer", "params": {"points": "w", "samples": 16}, "inputs": ["d", "w"]}"#,
            &["/w", "/d"][..],
        ),
        (
            // Points inside a closed sphere: every triangle nearly as
            // close as the nearest, about a millisecond a query.
            "attribute_transfer from primitives inside a sphere",
            r#""g": {"type": "grid", "params": {"rows": 299, "columns": 299, "size": [1, 1]}},
               "s": {"type": "sphere", "params": {"rows": 300, "columns": 600, "radius": 5}},
               "w": {"type": "wrangle", "inputs": ["s"], "params": {"run_over": "primitives", "snippet": "f@w = @primnum;"}},
               "n": {"type": "attribute_transfer", "params": {"points": "", "primitives": "w"}, "inputs": ["g", "w"]}"#,
            &["/g", "/w"][..],
        ),
        (
            "ray minimum inside a sphere",
            r#""g": {"type": "grid", "params": {"rows": 299, "columns": 299, "size": [1, 1]}},
               "s": {"type": "sphere", "params": {"rows": 300, "columns": 600, "radius": 5}},
               "n": {"type": "ray", "params": {"method": "minimum"}, "inputs": ["g", "s"]}"#,
            &["/g", "/s"][..],
        ),
        (
            "attribute_blur",
            r#""s": {"type": "sphere", "params": {"rows": 500, "columns": 1000}},
               "n": {"type": "attribute_blur", "params": {"iterations": 100000}, "inputs": ["s"]}"#,
            &["/s"][..],
        ),
        (
            "measure curvature",
            r#""s": {"type": "sphere", "params": {"rows": 1500, "columns": 3000}},
               "n": {"type": "measure", "params": {"measure": "mean_curvature"}, "inputs": ["s"]}"#,
            &["/s"][..],
        ),
        (
            "uv_flatten",
            r#""s": {"type": "sphere", "params": {"rows": 400, "columns": 800}},
               "n": {"type": "uv_flatten", "params": {"seams": "@P.z==0"}, "inputs": ["s"]}"#,
            &["/s"][..],
        ),
        (
            "for_each",
            r#""g": {"type": "grid", "params": {"rows": 199, "columns": 199}},
               "b": {"type": "box"},
               "c": {"type": "copy_to_points", "inputs": ["b", "g"], "params": {"pack": false}},
               "n": {"type": "for_each", "inputs": ["c"], "network": {"output": "m", "nodes": {
                   "m": {"type": "subdivide", "inputs": ["@0"], "params": {"levels": 3}}}}}"#,
            &["/c"][..],
        ),
    ];
    for (name, nodes, inputs) in cases {
        check(name, nodes, inputs);
    }
}

#[test]
fn every_long_running_node_type_stops_within_200_ms_of_a_cancel() {
    scatter_with_relax_stops_promptly();
    surface_scatter_with_relax_stops_promptly();
    colonization_stops_promptly();
    polygonise_stops_promptly();
    subdivide_stops_promptly();
    sweep_stops_promptly();
    frep_sweep_meshing_stops_promptly();
    real_copies_stop_promptly();
    every_writer_stops_promptly_and_writes_nothing();
    unpacking_for_a_writer_stops_promptly();
    modelling_nodes_stop_promptly();
    attribute_nodes_stop_promptly();
}
