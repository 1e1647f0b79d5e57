//! A broken node fails only what reads it: the rest of the network cooks,
//! nodes on a cycle fail without hanging, and `Network::load` stays strict.

mod common;

use common::registry;
use geode_graph::{load_str, Cache, CookOptions, Document, Engine, Network};
use geode_op::ErrorKind;

fn partial(text: &str) -> Network {
    let doc = Document::from_json(text).unwrap();
    Network::load_partial(&doc, &registry()).unwrap()
}

fn messages(errors: &[geode_op::CookError]) -> Vec<String> {
    errors.iter().map(|e| e.to_string()).collect()
}

/// The display cooks; an unwired node, a typo'd type and a bad parameter
/// elsewhere are listed as problems of their own nodes.
const UNRELATED: &str = r#"{"geode": "network", "version": 1, "output": "b", "nodes": {
    "a": {"type": "points", "params": {"count": 4}},
    "b": {"type": "offset", "inputs": ["a"], "params": {"by": [0, 1, 0]}},
    "loose": {"type": "offset"},
    "typo": {"type": "pionts"},
    "bad": {"type": "points", "params": {"count": "many"}},
    "after": {"type": "offset", "inputs": ["bad"]}
}}"#;

#[test]
fn problems_elsewhere_do_not_stop_the_display_cooking() {
    let net = partial(UNRELATED);
    let listed: Vec<String> = net.problems().iter().map(|e| e.to_string()).collect();
    assert_eq!(
        listed,
        vec![
            "/bad: parameter `count`: expected int (a number, a channel or {\"expr\": ...}), found string \"many\"",
            "/loose: input 1 (geometry) is required but not connected",
            "/typo: unknown node type `pionts` (did you mean points?)",
        ]
    );
    assert_eq!(net.node_problems("/b"), &[]);
    assert_eq!(net.node_problems("/loose").len(), 1);
    let cache = Cache::disabled();
    let engine = Engine::new(net, &cache);
    let out = engine.cook_output(&CookOptions::at_frame(1.0)).unwrap();
    assert_eq!(out.value.as_geometry().unwrap().positions().len(), 4);
}

#[test]
fn downstream_of_a_broken_node_fails_with_its_error() {
    let cache = Cache::disabled();
    let engine = Engine::new(partial(UNRELATED), &cache);
    let opts = CookOptions::at_frame(1.0);
    let err = engine.cook("/after", &opts).err().unwrap();
    assert_eq!(
        messages(&err),
        vec![
            "/bad (parameter `count`): expected int (a number, a channel or {\"expr\": ...}), found string \"many\""
        ]
    );
    assert_eq!(err[0].param.as_deref(), Some("count"));
    let err = engine.cook("/typo", &opts).err().unwrap();
    assert_eq!(err[0].kind, ErrorKind::Network);
    assert_eq!(err[0].path, "/typo");
}

#[test]
fn nodes_on_a_cycle_fail_without_hanging_and_the_rest_cooks() {
    let text = r#"{"geode": "network", "version": 1, "output": "x", "nodes": {
        "x": {"type": "points"},
        "a": {"type": "offset", "inputs": ["c"]},
        "b": {"type": "offset", "inputs": ["a"]},
        "c": {"type": "offset", "inputs": ["b"]},
        "d": {"type": "offset", "inputs": ["c"]}}}"#;
    let cache = Cache::disabled();
    let engine = Engine::new(partial(text), &cache);
    let opts = CookOptions::at_frame(1.0);
    assert!(engine.cook_output(&opts).is_ok());
    for node in ["/a", "/b", "/c", "/d"] {
        let err = engine.cook(node, &opts).err().unwrap();
        assert_eq!(
            messages(&err),
            vec!["/a: cycle: /a -> /b -> /c -> /a"],
            "{node}"
        );
    }
}

#[test]
fn a_broken_node_inside_a_subnet_fails_the_subnet_only() {
    let text = r#"{"geode": "network", "version": 1, "output": "j", "nodes": {
        "p": {"type": "points", "params": {"count": 3}},
        "s": {"type": "subnet", "inputs": ["p"],
            "network": {"output": "x", "nodes": {"x": {"type": "offset", "inputs": ["@0"], "params": {"by": "up"}}}}},
        "j": {"type": "join", "inputs": ["p", "s"]},
        "k": {"type": "offset", "inputs": ["p"]}}}"#;
    let cache = Cache::disabled();
    let engine = Engine::new(partial(text), &cache);
    let opts = CookOptions::at_frame(1.0);
    let err = engine.cook_output(&opts).err().unwrap();
    assert_eq!(err[0].path, "/s/x");
    assert!(engine.cook("/k", &opts).is_ok());
}

#[test]
fn strict_loading_still_refuses_any_problem() {
    let errors = load_str(UNRELATED, &registry()).err().unwrap();
    assert_eq!(errors.len(), 3);
}

#[test]
fn only_an_unreadable_document_fails_partial_loading() {
    for (text, message) in [
        (
            r#"{"geode": "network", "version": 9, "nodes": {}}"#,
            "/: network version 9 is newer than this geode understands (1)",
        ),
        (
            r#"{"geode": "palette", "version": 1, "nodes": {}}"#,
            "/: not a geode network (\"geode\" is \"palette\", expected \"network\")",
        ),
    ] {
        let doc = Document::from_json(text).unwrap();
        let errors = Network::load_partial(&doc, &registry()).err().unwrap();
        let listed: Vec<String> = errors.iter().map(|e| e.to_string()).collect();
        assert_eq!(listed, vec![message]);
    }
}

#[test]
fn check_finds_what_operators_refuse_without_cooking() {
    // `max` is keyed from -1 at frame 1 to 9 at frame 10: negative at 1.
    let keyed = r#"{"keys": [{"frame": 1, "value": -1}, {"frame": 10, "value": 9}]}"#;
    let text = format!(
        r#"{{"geode": "network", "version": 1, "output": "c", "nodes": {{
        "a": {{"type": "points", "params": {{"count": 4}}}},
        "c": {{"type": "clamp", "inputs": ["a"], "params": {{"max": {keyed}}}}},
        "off": {{"type": "clamp", "inputs": ["a"], "bypass": true, "params": {{"max": -5}}}},
        "fine": {{"type": "clamp", "inputs": ["a"], "params": {{"max": 2}}}},
        "sub": {{"type": "subnet", "inputs": ["a"], "network": {{"output": "in", "nodes": {{
            "in": {{"type": "clamp", "inputs": ["@0"], "params": {{"max": -2}}}}}}}}}}
    }}}}"#
    );
    let net = load_str(&text, &registry()).unwrap();
    let env = geode_op::CookEnv::default();
    let found: Vec<String> = net.check(1.0, &env).iter().map(|e| e.to_string()).collect();
    assert_eq!(
        found,
        vec![
            "/c: parameter `max`: -1 at frame 1 is negative (input wired: true)",
            "/sub/in: parameter `max`: -2 at frame 1 is negative (input wired: true)",
        ]
    );
    let found: Vec<String> = net
        .check(10.0, &env)
        .iter()
        .map(|e| e.to_string())
        .collect();
    assert_eq!(
        found,
        vec!["/sub/in: parameter `max`: -2 at frame 10 is negative (input wired: true)"]
    );
    // A cook is not a check: the hook refuses nothing the engine cooks.
    let cache = Cache::new(1 << 20);
    assert!(Engine::new(net, &cache)
        .cook_output(&CookOptions::at_frame(1.0))
        .is_ok());
}
