//! Parameter expressions in networks: `$F`, `$T`, `$FPS`, `$OS`, math,
//! `fit`, `rand`, `ch()` between nodes (cycles and bad paths refused at load
//! with the parameter named), backticks and variables in strings. Values are
//! checked against Houdini's documented definitions (`$T = ($F - 1) / $FPS`,
//! VEX's `fit`), and `rand` against the same call in a wrangle.

mod common;
use common::*;

use geode_geo::AttribClass;
use geode_graph::{load_str, Cache, CookOptions, Engine};

/// The x extent of a box whose size is `size` (JSON) at `frame`.
fn box_width(size: &str, frame: f64) -> Result<f32, String> {
    let nodes = format!(r#""b": {{"type": "box", "params": {{"size": {size}}}}}"#);
    let g = cook_at(&nodes, "b", frame)?;
    let g = g.as_geometry().unwrap();
    let xs = g.positions().iter().map(|p| p.x);
    let (lo, hi) = xs.fold((f32::MAX, f32::MIN), |(a, b), x| (a.min(x), b.max(x)));
    Ok(hi - lo)
}

#[test]
fn frame_time_and_math_follow_houdinis_definitions() {
    let w = |e: &str, f: f64| box_width(&format!(r#"[{{"expr": "{e}"}}, 1, 1]"#), f).unwrap();
    assert_eq!(w("$F", 3.0), 3.0);
    // $F is the whole frame, $FF keeps its fraction.
    assert_eq!(w("$F", 2.6), 3.0);
    assert!((w("$FF", 2.5) - 2.5).abs() < 1e-6);
    // $T = ($F - 1) / $FPS, 24 fps unless the network says otherwise.
    assert!((w("$T", 25.0) - 1.0).abs() < 1e-6);
    assert!((w("$FPS / 12", 1.0) - 2.0).abs() < 1e-6);
    assert!((w("1 + sin($F)", 4.0) - (1.0 + 4f32.sin())).abs() < 1e-5);
    // VEX's fit(value, omin, omax, nmin, nmax), clamped to the old range.
    assert!((w("fit($F, 1, 11, 0, 10)", 6.0) - 5.0).abs() < 1e-5);
    assert!((w("fit($F, 1, 11, 0, 10)", 40.0) - 10.0).abs() < 1e-5);
    assert!((w("$PI", 1.0) - std::f32::consts::PI).abs() < 1e-6);
}

#[test]
fn the_networks_frame_rate_sets_t() {
    let doc = r#"{"geode": "network", "version": 1, "output": "b", "fps": 12,
        "nodes": {"b": {"type": "box", "params": {"size": [{"expr": "$T"}, 1, 1]}}}}"#;
    let net = load_str(doc, &geode_nodes::registry()).unwrap();
    let cache = Cache::disabled();
    let g = Engine::new(net, &cache)
        .cook_output(&CookOptions::at_frame(25.0))
        .unwrap()
        .value;
    let g = g.as_geometry().unwrap();
    let hi = g.positions().iter().map(|p| p.x).fold(f32::MIN, f32::max);
    assert!((hi - 1.0).abs() < 1e-6, "24 frames at 12 fps are 2 s: {hi}");
}

#[test]
fn rand_in_a_field_is_the_wrangles_rand() {
    let nodes = r#"
        "b": {"type": "box", "params": {"size": [{"expr": "rand(7.5)"}, 1, 1]}},
        "w": {"type": "wrangle", "inputs": ["b"], "params": {"run_over": "detail", "snippet": "f@r = rand(7.5);"}}"#;
    let g = geo(nodes, "w");
    let r = g
        .attrib(AttribClass::Detail, "r")
        .unwrap()
        .data()
        .as_floats()
        .unwrap()
        .0[0];
    let xs: Vec<f32> = g.positions().iter().map(|p| p.x).collect();
    let width =
        xs.iter().cloned().fold(f32::MIN, f32::max) - xs.iter().cloned().fold(f32::MAX, f32::min);
    assert!((0.0..1.0).contains(&r));
    assert!((width - r).abs() < 1e-6, "field {width}, wrangle {r}");
}

#[test]
fn ch_reads_other_nodes_parameters_relative_to_the_node() {
    let nodes = r#"
        "a": {"type": "box", "params": {"size": [{"expr": "ch(\"../b/sizex\") * 2"}, {"expr": "chv(\"../b/size\").y + ch(\"sizez\")"}, 0.5]}},
        "b": {"type": "box", "params": {"size": [1.5, {"keys": [{"frame": 1, "value": 1}, {"frame": 11, "value": 2}]}, 1]}}"#;
    let size = |f: f64| {
        let g = cook_at(nodes, "a", f).unwrap();
        let g = g.as_geometry().unwrap();
        let ext = |k: usize| {
            let v: Vec<f32> = g.positions().iter().map(|p| p[k]).collect();
            v.iter().cloned().fold(f32::MIN, f32::max) - v.iter().cloned().fold(f32::MAX, f32::min)
        };
        (ext(0), ext(1))
    };
    assert_eq!(size(1.0), (3.0, 1.5));
    // The reference follows b's key at each frame.
    let (_, y) = size(6.0);
    assert!((y - 2.0).abs() < 1e-6, "{y}");
    let net = load_str(&net(nodes, "a"), &geode_nodes::registry()).unwrap();
    assert!(net.is_animated("/a"), "reads an animated parameter");
}

#[test]
fn a_reference_is_part_of_the_readers_cook_key() {
    let doc = |bx: f64| {
        net(
            &format!(
                r#""a": {{"type": "box", "params": {{"size": [{{"expr": "ch(\"../b/sizex\")"}}, 1, 1]}}}},
                   "b": {{"type": "box", "params": {{"size": [{bx}, 1, 1]}}}}"#
            ),
            "a",
        )
    };
    let cache = Cache::new(1 << 28);
    let width = |bx: f64| {
        let net = load_str(&doc(bx), &geode_nodes::registry()).unwrap();
        let g = Engine::new(net, &cache)
            .cook_output(&CookOptions::at_frame(1.0))
            .unwrap()
            .value;
        let g = g.as_geometry().unwrap();
        g.positions().iter().map(|p| p.x).fold(f32::MIN, f32::max) * 2.0
    };
    assert_eq!(width(2.0), 2.0);
    assert_eq!(
        width(3.0),
        3.0,
        "a changed reference recooks through the shared cache"
    );
}

#[test]
fn cycles_and_bad_paths_are_load_problems_on_the_parameter() {
    let nodes = r#"
        "a": {"type": "box", "params": {"size": [{"expr": "ch(\"../b/sizex\")"}, 1, 1]}},
        "b": {"type": "box", "params": {"size": [{"expr": "ch(\"../a/sizex\") + 1"}, 1, 1]}},
        "c": {"type": "box", "params": {"size": [{"expr": "ch(\"../nothere/sizex\")"}, 1, 1]}},
        "d": {"type": "sphere"}"#;
    let net = geode_graph::Network::load_partial(
        &geode_graph::Document::from_json(&net(nodes, "d")).unwrap(),
        &geode_nodes::registry(),
    )
    .unwrap();
    let a = net.node_problems("/a");
    assert_eq!(a[0].param.as_deref(), Some("size"));
    assert!(
        a[0].message.contains("cycle: /a/size → /b/size → /a/size"),
        "{}",
        a[0].message
    );
    assert!(net.node_problems("/b")[0].message.contains("cycle"));
    let c = &net.node_problems("/c")[0];
    assert!(
        c.message
            .contains("ch(\"../nothere/sizex\"): no such parameter"),
        "{}",
        c.message
    );
    // The rest of the network cooks.
    let cache = Cache::disabled();
    assert!(Engine::new(net, &cache)
        .cook_output(&CookOptions::at_frame(1.0))
        .is_ok());
}

#[test]
fn expression_errors_point_at_their_column() {
    let problems = |e: &str| {
        let nodes =
            format!(r#""b": {{"type": "box", "params": {{"size": [1, {{"expr": "{e}"}}, 1]}}}}"#);
        match load_str(&net(&nodes, "b"), &geode_nodes::registry()) {
            Ok(_) => panic!("{e} loaded"),
            Err(p) => p,
        }
    };
    let p = &problems("1 + $FOO")[0];
    assert_eq!(p.param.as_deref(), Some("size"));
    assert!(p.message.contains("unknown variable $FOO"), "{}", p.message);
    assert_eq!(p.position.map(|p| p.column), Some(5));
    let p = &problems("sin($F")[0];
    assert_eq!(p.position.map(|p| p.column), Some(7), "{}", p.message);
    assert!(problems("@P.x")[0].message.contains("no geometry"));
    // Type errors show at load too (an expression reading no other parameter
    // is tried once), with the column.
    let p = &problems("2 * \\\"text\\\"")[0];
    assert!(
        p.message.contains("no form for int and string"),
        "{}",
        p.message
    );
    assert!(p.position.is_some());
    // A result outside the declared range names the value and the frame.
    let nodes = r#""s": {"type": "sphere", "params": {"radius": {"expr": "$F - 5"}}}"#;
    let e = err(nodes, "s");
    assert!(e.contains("gives -4 at frame 1, below the minimum"), "{e}");
}

#[test]
fn deeply_nested_expressions_are_refused_not_overflowed() {
    let deep = format!("{}1{}", "(".repeat(5000), ")".repeat(5000));
    let nodes =
        format!(r#""b": {{"type": "box", "params": {{"size": [1, {{"expr": "{deep}"}}, 1]}}}}"#);
    let refused = |nodes: &str| match load_str(&net(nodes, "b"), &geode_nodes::registry()) {
        Ok(_) => panic!("loaded"),
        Err(e) => e[0].message.clone(),
    };
    let e = refused(&nodes);
    assert!(e.contains("nested too deeply"), "{e}");
    let long = vec!["1"; 20000].join("+");
    let nodes =
        format!(r#""b": {{"type": "box", "params": {{"size": [1, {{"expr": "{long}"}}, 1]}}}}"#);
    let e = refused(&nodes);
    assert!(e.contains("nested too deeply"), "{e}");
}

#[test]
fn strings_expand_variables_and_backticks_but_code_does_not() {
    let nodes = r#"
        "g": {"type": "grid", "params": {"rows": 2, "columns": 2}},
        "w": {"type": "wrangle", "inputs": ["g"], "spare": {"label": "string"},
              "params": {"run_over": "detail", "snippet": "s@label = chs(\"label\");",
                         "label": "f`$F * 2`_${F3}_${OS}_\\$F"}}"#;
    let g = cook_at(nodes, "w", 3.0).unwrap();
    let g = g.as_geometry().unwrap();
    let label = g
        .attrib(AttribClass::Detail, "label")
        .unwrap()
        .as_strings()
        .unwrap()
        .get(0)
        .to_string();
    assert_eq!(label, "f6_003_w_$F");
    // In a snippet `$F` is not VEX: the error says what to write instead.
    let nodes = r#"
        "g": {"type": "grid"},
        "w": {"type": "wrangle", "inputs": ["g"], "params": {"snippet": "@P.y = $F;"}}"#;
    let e = err(nodes, "w");
    assert!(e.contains("@Frame"), "{e}");
}

#[test]
fn an_error_belongs_to_the_parameter_that_has_it() {
    // An unknown function fails at load on its own node, not on its readers.
    let nodes = r#"
        "link": {"type": "sphere", "params": {"radius": {"expr": "if($F > 10, 0.05, 0.02)"}}},
        "ring": {"type": "sphere", "params": {"radius": {"expr": "ch(\"../link/radius\") * 50"}}}"#;
    let net = geode_graph::Network::load_partial(
        &geode_graph::Document::from_json(&net(nodes, "ring")).unwrap(),
        &geode_nodes::registry(),
    )
    .unwrap();
    let p = &net.node_problems("/link")[0];
    assert!(p.message.contains("unknown function 'if'"), "{}", p.message);
    assert_eq!(p.position.map(|p| p.column), Some(1));
    assert!(net.node_problems("/ring").is_empty());
    // A reference whose parameter fails at cook time names that parameter's error.
    let nodes = r#"
        "a": {"type": "box", "params": {"size": [{"expr": "ch(\"../b/sizex\")"}, 1, 1]}},
        "b": {"type": "box", "params": {"size": [{"expr": "ch(\"../c/name\") * 2"}, 1, 1]}},
        "c": {"type": "wrangle", "inputs": ["a"], "spare": {"name": "string"}, "params": {"name": "x"}}"#;
    let e = cook_errors(nodes, "a");
    assert!(
        e[0].message.contains("ch(\"../b/sizex\") fails: /b `size`"),
        "{}",
        e[0].message
    );
}
