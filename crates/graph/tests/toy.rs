//! The engine tested with toy operators: which nodes re-ran after each edit,
//! early cut-off, frame changes, A -> B -> A cache hits, errors with exact
//! messages, bypass, subnets, solo view, determinism, and no deadlock under parallel kernels.

mod common;

use std::sync::atomic::Ordering;

use common::{geo, registry, COOKS};
use geode_geo::glam::Vec3;
use geode_graph::{load_str, Cache, CookOptions, Engine};

/// a -> b -> c, and d -> e; join(c, e).
fn chain(b_by: &str, d_count: &str) -> String {
    format!(
        r#"{{"geode": "network", "version": 1, "output": "j", "nodes": {{
            "a": {{"type": "points", "params": {{"count": 5}}}},
            "b": {{"type": "offset", "inputs": ["a"], "params": {{"by": {b_by}}}}},
            "c": {{"type": "clamp", "inputs": ["b"], "params": {{"max": 100}}}},
            "d": {{"type": "points", "params": {{"count": {d_count}}}}},
            "e": {{"type": "offset", "inputs": ["d"]}},
            "j": {{"type": "join", "inputs": ["c", "e"]}}
        }}}}"#
    )
}

fn cook(text: &str, cache: &Cache, frame: f64) -> geode_graph::CookResult {
    let net = load_str(text, &registry()).unwrap();
    Engine::new(net, cache)
        .cook_output(&CookOptions::at_frame(frame))
        .unwrap()
}

#[test]
fn editing_a_parameter_recooks_exactly_what_is_downstream() {
    let cache = Cache::new(1 << 30);
    let first = cook(&chain("[0, 0, 0]", "3"), &cache, 1.0);
    assert_eq!(first.cooked(), vec!["/a", "/b", "/c", "/d", "/e", "/j"]);
    let again = cook(&chain("[0, 0, 0]", "3"), &cache, 1.0);
    assert!(again.cooked().is_empty(), "nothing changed: all hits");
    let edited = cook(&chain("[0, 1, 0]", "3"), &cache, 1.0);
    assert_eq!(edited.cooked(), vec!["/b", "/c", "/j"]);
    let other = cook(&chain("[0, 1, 0]", "4"), &cache, 1.0);
    assert_eq!(other.cooked(), vec!["/d", "/e", "/j"]);
}

#[test]
fn identical_upstream_content_recooks_nothing_below() {
    let cache = Cache::new(1 << 30);
    // Clamping X at 0.5 hides a change of step beyond it: c's output is equal.
    let net = |step: f64| {
        format!(
            r#"{{"geode": "network", "version": 1, "output": "e", "nodes": {{
                "a": {{"type": "points", "params": {{"count": 2, "step": {step}}}}},
                "c": {{"type": "clamp", "inputs": ["a"], "params": {{"max": 0.5}}}},
                "d": {{"type": "offset", "inputs": ["c"], "params": {{"by": [0, 0, 1]}}}},
                "e": {{"type": "offset", "inputs": ["d"], "params": {{"by": [1, 0, 0]}}}}
            }}}}"#
        )
    };
    cook(&net(1.0), &cache, 1.0);
    let r = cook(&net(2.0), &cache, 1.0);
    assert_eq!(
        r.cooked(),
        vec!["/a", "/c"],
        "d and e see the same input identity: early cut-off"
    );
}

#[test]
fn frame_changes_recook_only_animated_nodes_and_dependents() {
    let cache = Cache::new(1 << 30);
    let animated = r#"[0, {"keys": [{"frame": 1, "value": 0}, {"frame": 10, "value": 9}]}, 0]"#;
    cook(&chain(animated, "3"), &cache, 1.0);
    let r = cook(&chain(animated, "3"), &cache, 2.0);
    assert_eq!(r.cooked(), vec!["/b", "/c", "/j"]);
    // Past the last key the value holds: frames 20 and 30 give one result.
    cook(&chain(animated, "3"), &cache, 20.0);
    assert!(cook(&chain(animated, "3"), &cache, 30.0)
        .cooked()
        .is_empty());
    let net = load_str(&chain(animated, "3"), &registry()).unwrap();
    assert!(net.is_animated("/b") && !net.is_animated("/c"));
}

#[test]
fn switching_a_to_b_to_a_is_a_hit_the_third_time() {
    let cache = Cache::new(1 << 30);
    let preview = chain("[0, 0, 0]", "3");
    let render = chain("[0, 0, 0]", "500");
    assert_eq!(cook(&preview, &cache, 1.0).cooked().len(), 6);
    assert_eq!(cook(&render, &cache, 1.0).cooked(), vec!["/d", "/e", "/j"]);
    assert!(
        cook(&preview, &cache, 1.0).cooked().is_empty(),
        "back to preview: every node a hit"
    );
}

#[test]
fn disabled_cache_recooks_everything() {
    let cache = Cache::disabled();
    cook(&chain("[0, 0, 0]", "3"), &cache, 1.0);
    assert_eq!(
        cook(&chain("[0, 0, 0]", "3"), &cache, 1.0).cooked().len(),
        6
    );
}

#[test]
fn diamond_dependencies_cook_once_per_run() {
    let text = r#"{"geode": "network", "version": 1, "output": "j", "nodes": {
        "a": {"type": "points", "params": {"count": 7}},
        "b": {"type": "offset", "inputs": ["a"], "params": {"by": [1, 0, 0]}},
        "c": {"type": "offset", "inputs": ["a"], "params": {"by": [2, 0, 0]}},
        "j": {"type": "join", "inputs": ["b", "c"]}}}"#;
    let before = COOKS.load(Ordering::Relaxed);
    let r = cook(text, &Cache::disabled(), 1.0);
    assert_eq!(r.events.iter().filter(|e| e.path == "/a").count(), 1);
    assert!(COOKS.load(Ordering::Relaxed) - before >= 1);
    assert_eq!(geo(&r.value).num_points(), 14);
}

#[test]
fn bypass_passes_the_first_input_through() {
    let text = r#"{"geode": "network", "version": 1, "output": "b", "nodes": {
        "a": {"type": "points", "params": {"count": 2}},
        "b": {"type": "offset", "inputs": ["a"], "params": {"by": [5, 0, 0]}, "bypass": true}}}"#;
    let r = cook(text, &Cache::disabled(), 1.0);
    assert_eq!(geo(&r.value).positions(), &[Vec3::ZERO, Vec3::X]);
    assert_eq!(r.cooked(), vec!["/a"]);
}

const SUBNET: &str = r#"{"geode": "network", "version": 1, "output": "rig", "nodes": {
    "src": {"type": "points", "params": {"count": 2}},
    "rig": {"type": "subnet", "inputs": ["src"], "promote": {"shift": "move/by"}, "params": {"shift": [0, 3, 0]},
        "network": {"output": "out", "nodes": {
            "move": {"type": "offset", "inputs": ["@0"]},
            "out": {"type": "clamp", "inputs": ["move"], "params": {"max": 0.5}}}}}}}"#;

#[test]
fn subnets_promoted_parameters_and_solo_view() {
    let cache = Cache::new(1 << 30);
    let net = load_str(SUBNET, &registry()).unwrap();
    let engine = Engine::new(net, &cache);
    let r = engine.cook_output(&CookOptions::at_frame(1.0)).unwrap();
    assert_eq!(
        geo(&r.value).positions(),
        &[Vec3::new(0.0, 3.0, 0.0), Vec3::new(0.5, 3.0, 0.0)]
    );
    // Solo: the inner node alone.
    let inner = engine
        .cook("/rig/move", &CookOptions::at_frame(1.0))
        .unwrap();
    assert_eq!(geo(&inner.value).positions()[1], Vec3::new(1.0, 3.0, 0.0));
    assert!(
        inner.cooked().is_empty(),
        "already cooked as part of the output"
    );
    // Auto mode: the promoted parameter names the inner node it drives.
    assert_eq!(
        engine.solo_target(&[("/rig", "shift")]).as_deref(),
        Some("/rig/move")
    );
    assert_eq!(
        engine
            .solo_target(&[("/rig", "shift"), ("/src", "count")])
            .as_deref(),
        Some("/src")
    );
    assert_eq!(engine.network().output(), Some("/rig"));
}

#[test]
fn bundles_travel_on_one_wire() {
    let text = r#"{"geode": "network", "version": 1, "output": "p", "nodes": {
        "a": {"type": "points", "params": {"count": 1}},
        "b": {"type": "points", "params": {"count": 2}},
        "p": {"type": "pack", "inputs": ["a", "b"]}}}"#;
    let r = cook(text, &Cache::disabled(), 1.0);
    let b = r.value.as_bundle().unwrap();
    assert_eq!(b.entries.keys().collect::<Vec<_>>(), vec!["a", "b"]);
    let wrong = r#"{"geode": "network", "version": 1, "nodes": {
        "p": {"type": "pack"},
        "o": {"type": "offset", "inputs": ["p"]}}}"#;
    let e = load_str(wrong, &registry()).err().unwrap();
    assert_eq!(
        e[0].to_string(),
        "/o: input 1 (geometry) expects geometry but /p gives bundle"
    );
}

fn errors(text: &str) -> Vec<String> {
    match load_str(text, &registry()) {
        Ok(_) => panic!("expected errors"),
        Err(e) => e.iter().map(|e| e.to_string()).collect(),
    }
}

#[test]
fn every_load_error_class_has_an_exact_message_and_all_are_reported() {
    let text = r#"{"geode": "network", "version": 1, "nodes": {
        "a": {"type": "pionts"},
        "b": {"type": "points", "params": {"cuont": 3, "step": "far", "count": 5000}},
        "c": {"type": "offset", "params": {"by": [1, 2]}},
        "d": {"type": "offset", "inputs": ["zz"]},
        "e": {"type": "points", "params": {"count": 2.5}},
        "f": {"type": "offset", "inputs": ["a"], "params": {"by": [0, {"keys": []}, 0]}}
    }}"#;
    assert_eq!(
        errors(text),
        vec![
            "/a: unknown node type `pionts` (did you mean points?)",
            "/b: unknown parameter `cuont` (did you mean `count`?)",
            "/b: parameter `count`: value 5000 is above the maximum 1000",
            "/b: parameter `step`: expected float (a number, a channel or {\"expr\": ...}), found string \"far\"",
            "/c: parameter `by`: expected vector3 (an array of 3 numbers, channels or expressions), found an array of 2",
            "/c: input 1 (geometry) is required but not connected",
            "/d: input 1 refers to `zz`, which is not a node of this network",
            "/e: parameter `count`: expected an integer, found 2.5",
            "/f: parameter `by`: bad channel: a channel needs at least one key",
        ]
    );
}

#[test]
fn a_required_input_wired_to_an_unconnected_subnet_input_is_a_load_error() {
    let text = r#"{"geode": "network", "version": 1, "output": "a", "nodes": {
        "a": {"type": "subnet", "inputs": [null],
            "network": {"output": "x", "nodes": {"x": {"type": "offset", "inputs": ["@0"]}}}}}}"#;
    assert_eq!(
        errors(text),
        vec!["/a/x: input 1 (geometry) is required but is wired to `@0`, and that input of subnet /a is not connected"]
    );
}

#[test]
fn cycles_name_their_nodes() {
    let text = r#"{"geode": "network", "version": 1, "nodes": {
        "x": {"type": "points"},
        "a": {"type": "offset", "inputs": ["c"]},
        "b": {"type": "offset", "inputs": ["a"]},
        "c": {"type": "offset", "inputs": ["b"]}}}"#;
    assert_eq!(errors(text), vec!["/a: cycle: /a -> /b -> /c -> /a"]);
}

#[test]
fn document_level_errors() {
    assert_eq!(
        errors(r#"{"geode": "network", "version": 9, "nodes": {}}"#),
        vec!["/: network version 9 is newer than this geode understands (1)"]
    );
    assert_eq!(
        errors("{\"geode\": \"network\",\n\"version\": 1,\n\"nodes\": {,}}"),
        vec!["/: line 3, column 11: key must be a string"]
    );
}

#[test]
fn cancellation_stops_a_running_cook() {
    let text =
        r#"{"geode": "network", "version": 1, "output": "s", "nodes": {"s": {"type": "slow"}}}"#;
    let net = load_str(text, &registry()).unwrap();
    let cache = Cache::disabled();
    let engine = Engine::new(net, &cache);
    let opts = CookOptions::at_frame(1.0);
    let cancel = opts.cancel.clone();
    let t = std::thread::spawn(move || {
        std::thread::sleep(std::time::Duration::from_millis(30));
        cancel.cancel();
    });
    let start = std::time::Instant::now();
    let err = engine.cook_output(&opts).err().unwrap();
    t.join().unwrap();
    assert!(err[0].is_cancelled());
    assert!(start.elapsed().as_secs_f64() < 2.0);
}

#[test]
fn same_network_same_bytes_on_any_thread_count() {
    let text = chain(
        r#"[0.1, {"keys": [{"frame": 1, "value": 0, "interp": "bezier"}, {"frame": 10, "value": 9}]}, 0]"#,
        "700",
    );
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| cook(&text, &Cache::disabled(), 3.5).value.identity())
    };
    assert_eq!(run(1), run(4));
}

/// Shared inputs read by many nodes whose cooks join on rayon: no worker may
/// wait for a node another is cooking (a cook blocked on a worker that stole
/// a job waiting for that cook's node deadlocked the engine). Many cooks on
/// four threads, each bounded by a watchdog.
#[test]
fn shared_inputs_under_parallel_kernels_never_deadlock() {
    // Five layers of six nodes, each reading three of the layer below.
    let mut nodes: Vec<String> = (0..6)
        .map(|i| format!(r#""l0_{i}": {{"type": "spin"}}"#))
        .collect();
    for layer in 1..5 {
        for i in 0..6 {
            let reads: Vec<String> = (0..3)
                .map(|k| format!(r#""l{}_{}""#, layer - 1, (i + k * (layer + 1)) % 6))
                .collect();
            nodes.push(format!(
                r#""l{layer}_{i}": {{"type": "spin", "inputs": [{}]}}"#,
                reads.join(", ")
            ));
        }
    }
    let ns: Vec<String> = (0..6).map(|i| format!(r#""l4_{i}""#)).collect();
    nodes.push(format!(
        r#""j": {{"type": "spin", "inputs": [{}]}}"#,
        ns.join(", ")
    ));
    let text = format!(
        r#"{{"geode": "network", "version": 1, "output": "j", "nodes": {{{}}}}}"#,
        nodes.join(", ")
    );
    let (done, finished) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(4)
            .build()
            .unwrap();
        for _ in 0..40 {
            pool.install(|| cook(&text, &Cache::disabled(), 1.0));
        }
        done.send(()).unwrap();
    });
    finished
        .recv_timeout(std::time::Duration::from_secs(60))
        .expect("the cooks finished (no deadlock)");
}
