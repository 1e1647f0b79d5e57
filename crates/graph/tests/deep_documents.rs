//! Hostile nesting in network documents: 100,000 levels of JSON arrays,
//! objects or subnets are refused by serde_json's recursion limit (128,
//! never disabled here) with the line and column, on a test thread's stack.
//! (The fuzzer's crash inputs for the loader are replayed by geode-nodes'
//! tests, with the registry the fuzz target loads them with.)

mod common;

use geode_graph::{load_str, Document};

const LEVELS: usize = 100_000;

fn syntax_error(text: &str) -> String {
    Document::from_json(text).unwrap_err().to_string()
}

#[test]
fn deep_json_is_refused_with_its_line_and_column() {
    let arrays = format!(
        r#"{{"geode": "network", "version": 1, "future": {}{}}}"#,
        "[".repeat(LEVELS),
        "]".repeat(LEVELS)
    );
    assert_eq!(
        syntax_error(&arrays),
        "line 1, column 172: recursion limit exceeded"
    );
    let params = format!(
        r#"{{"geode": "network", "version": 1, "nodes": {{"a": {{"type": "points", "params": {{"count": {}1}}}}}}}}"#,
        "[".repeat(LEVELS)
    );
    // The error names the node and parameter it is in.
    assert_eq!(
        syntax_error(&params),
        "line 1, column 213: node /a, parameter `count`: recursion limit exceeded"
    );
    // The loader reports it as one error on that node and parameter.
    let Err(e) = load_str(&params, &common::registry()) else {
        panic!("loaded");
    };
    assert_eq!(e.len(), 1);
    assert_eq!(
        (e[0].path.as_str(), e[0].param.as_deref()),
        ("/a", Some("count"))
    );
    assert_eq!(e[0].message, "line 1, column 213: recursion limit exceeded");
}

/// Just inside serde_json's limit, a parameter nested 120 deep reaches the
/// loader, which refuses it without overflowing the stack.
#[test]
fn parameters_nested_just_inside_the_limit_are_refused() {
    let params = format!(
        r#"{{"geode": "network", "version": 1, "nodes": {{"a": {{"type": "points", "params": {{"count": {}1{}, "junk": {{"keys": {}{{"frame": 1}}{}}}}}}}}}}}"#,
        "[".repeat(120),
        "]".repeat(120),
        "[".repeat(110),
        "]".repeat(110)
    );
    Document::from_json(&params).unwrap();
    let Err(e) = load_str(&params, &common::registry()) else {
        panic!("loaded");
    };
    assert!(!e.is_empty());
}

#[test]
fn deep_subnets_are_refused_with_their_line_and_column() {
    let open = r#"{"type": "subnet", "network": {"nodes": {"s": "#;
    let subnets = format!(
        r#"{{"geode": "network", "version": 1, "nodes": {{"s": {}{{"type": "points"}}{}}}}}"#,
        open.repeat(LEVELS),
        "}}}".repeat(LEVELS)
    );
    let e = syntax_error(&subnets);
    assert!(
        e.starts_with("line 1, column 1977: node /s/s/s/")
            && e.ends_with("/s: recursion limit exceeded"),
        "{e}"
    );
    // As deep as the limit allows loads (the loader recurses per subnet).
    let fits = format!(
        r#"{{"geode": "network", "version": 1, "nodes": {{"s": {}{{"type": "points"}}{}}}}}"#,
        open.repeat(40),
        "}}}".repeat(40)
    );
    if let Err(e) = load_str(&fits, &common::registry()) {
        panic!("{e:?}");
    }
}

/// A chain of 100,000 nodes, each the input of the next, is long, not
/// nested: it loads and cooks without the loader or the engine recursing
/// along it.
#[test]
fn a_chain_of_100000_nodes_loads_and_cooks() {
    use geode_graph::{Cache, CookOptions, Engine};
    let mut nodes = vec![r#""n0": {"type": "points", "params": {"count": 2}}"#.to_string()];
    for i in 1..LEVELS {
        nodes.push(format!(
            r#""n{i}": {{"type": "offset", "inputs": ["n{}"]}}"#,
            i - 1
        ));
    }
    let text = format!(
        r#"{{"geode": "network", "version": 1, "output": "n{}", "nodes": {{{}}}}}"#,
        LEVELS - 1,
        nodes.join(", ")
    );
    let Ok(net) = load_str(&text, &common::registry()) else {
        panic!("the chain did not load");
    };
    let cache = Cache::new(1 << 30);
    let cooked = Engine::new(net, &cache).cook_output(&CookOptions::at_frame(1.0));
    assert!(cooked.is_ok());
}
