//! List parameters (Houdini's multiparms): rows of typed, ranged,
//! animatable fields, validated at load with every problem named by its row
//! and field; old networks' text forms still load, converted, with a note.

use geode_graph::{load_str, Cache, CookOptions, Engine, LoadError};

fn load(nodes: &str) -> Result<geode_graph::Network, Vec<LoadError>> {
    let text =
        format!(r#"{{"geode": "network", "version": 1, "output": "n", "nodes": {{{nodes}}}}}"#);
    load_str(&text, &geode_nodes::registry())
}

fn errors(nodes: &str) -> Vec<String> {
    match load(nodes) {
        Ok(_) => panic!("loaded"),
        Err(e) => e.iter().map(|e| e.to_string()).collect(),
    }
}

#[test]
fn every_problem_in_every_row_is_reported_at_load() {
    let e = errors(
        r#""n": {"type": "hspline", "params": {"edits": [
            {"level": 1, "vertex": [2, 2], "mvoe": [0, 1, 0]},
            {"level": 40, "vertex": [1, 1]},
            {"level": 1, "vertex": [1, 1], "move": [0, 1]},
            [1, 2, 3]
        ]}}"#,
    );
    assert_eq!(
        e,
        [
            "/n: parameter `edits[0]`: unknown field `mvoe` (did you mean `move`?) (fields: `level`, `vertex`, `move`)",
            "/n: parameter `edits[1].level`: value 40 is above the maximum 16",
            "/n: parameter `edits[2].move`: expected vector3 (an array of 3 numbers, channels or expressions), found an array of 2",
            "/n: parameter `edits[3]`: expected an object with fields `level`, `vertex`, `move`, found an array of 3",
        ]
    );
    let e = errors(r#""n": {"type": "hspline", "params": {"edits": 3}}"#);
    assert_eq!(
        e,
        ["/n: parameter `edits`: expected a list of rows (an array of objects with fields `level`, `vertex`, `move`), found number 3"]
    );
    let e = errors(r#""n": {"type": "hspline", "params": {"edits": "1 2"}}"#);
    assert_eq!(
        e,
        ["/n: parameter `edits`: edit 1 `1 2`: expected `level i j dx dy dz`"]
    );
}

#[test]
fn old_text_forms_load_converted_with_a_note_and_cook_the_same() {
    let old = load(
        r#""n": {"type": "hspline", "params": {"levels": 1, "edits": "1 3 3 0 0.2 0; 0 2 2 0.1 0 0"}}"#,
    )
    .unwrap();
    assert_eq!(
        old.notes().iter().map(|n| n.to_string()).collect::<Vec<_>>(),
        ["/n: parameter `edits`: read from the old text form as 2 rows; write it as a list of objects with fields `level`, `vertex`, `move`"]
    );
    let new = load(
        r#""n": {"type": "hspline", "params": {"levels": 1, "edits": [
            {"level": 1, "vertex": [3, 3], "move": [0, 0.2, 0]},
            {"level": 0, "vertex": [2, 2], "move": [0.1, 0, 0]}]}}"#,
    )
    .unwrap();
    assert!(new.notes().is_empty());
    let cache = Cache::disabled();
    let cook = |net| {
        Engine::new(net, &cache)
            .cook_output(&CookOptions::at_frame(1.0))
            .unwrap()
            .value
            .identity()
    };
    assert_eq!(cook(old), cook(new));
    // The other three old forms.
    for (node, inputs, params) in [
        (
            "attach",
            r#"["b", "b"]"#,
            r#""regions": "2 4 2 4; 4 5 4 5""#,
        ),
        (
            "skin",
            r#"["b"]"#,
            r#""skeleton": "root - 0 0 0; tip root 0 1 0", "pose": "tip 0 0 30""#,
        ),
    ] {
        let net = load(&format!(
            r#""b": {{"type": "box"}}, "n": {{"type": "{node}", "inputs": {inputs}, "params": {{{params}}}}}"#
        ))
        .unwrap_or_else(|e| panic!("{e:?}"));
        assert!(!net.notes().is_empty(), "{node}");
    }
}

#[test]
fn list_fields_animate_and_key_the_cook() {
    let net = load(
        r#""b": {"type": "box", "params": {"size": [0.2, 2, 0.2], "divisions": [1, 8, 1]}},
           "n": {"type": "skin", "inputs": ["b"], "params": {
             "skeleton": [{"name": "root", "rest": [0, -1, 0]}, {"name": "mid", "parent": "root"}],
             "pose": [{"joint": "mid", "rotate": [0, 0, {"keys": [{"frame": 1, "value": 0}, {"frame": 10, "value": 90}]}]}]}}"#,
    )
    .unwrap();
    assert!(net.is_animated("/n"));
    let cache = Cache::new(1 << 24);
    let engine = Engine::new(net, &cache);
    let at = |f: f64| engine.cook_output(&CookOptions::at_frame(f)).unwrap();
    let (a, b) = (at(1.0), at(10.0));
    assert_ne!(
        a.value.identity(),
        b.value.identity(),
        "the keyed rotation bends the box"
    );
    let top = |r: &geode_graph::CookResult| {
        let g = r.value.as_geometry().unwrap();
        g.positions()
            .iter()
            .map(|p| p.x.abs())
            .fold(0.0f32, f32::max)
    };
    assert!(top(&a) < 0.2 && top(&b) > 0.5, "{} {}", top(&a), top(&b));
    assert!(
        at(10.0).events.iter().all(|e| e.hit),
        "the same frame is a cache hit"
    );
}
