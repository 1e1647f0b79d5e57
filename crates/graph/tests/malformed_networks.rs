//! Random and malformed networks never panic the loader or the engine.

mod common;

use geode_graph::{load_str, Cache, CookOptions, Document, Engine, Network};
use proptest::prelude::*;
use serde_json::{json, Value as Json};

fn any_json() -> impl Strategy<Value = Json> {
    let leaf = prop_oneof![
        Just(Json::Null),
        any::<bool>().prop_map(Json::Bool),
        (-1e3f64..1e3).prop_map(|x| json!(x)),
        (0i64..2000).prop_map(|x| json!(x)),
        "[a-z@/]{0,6}".prop_map(Json::String),
        Just(
            json!({"keys": [{"frame": 1, "value": 0}, {"frame": 5, "value": 3, "interp": "bezier"}]})
        ),
        Just(json!({"keys": "no"})),
    ];
    leaf.prop_recursive(2, 8, 4, |inner| {
        prop::collection::vec(inner, 0..4).prop_map(Json::Array)
    })
}

fn network() -> impl Strategy<Value = String> {
    let names = prop::sample::select(vec!["a", "b", "c", "d", "e"]);
    let types = prop::sample::select(vec![
        "points", "offset", "clamp", "join", "pack", "subnet", "nope",
    ]);
    let params = prop::collection::btree_map(
        prop::sample::select(vec!["count", "step", "by", "max", "junk"]),
        any_json(),
        0..3,
    );
    let inputs = prop::collection::vec(
        prop::option::of(prop::sample::select(vec![
            "a", "b", "c", "d", "e", "@0", "@9", "zz",
        ])),
        0..3,
    );
    let node = (types, params, inputs, any::<bool>());
    prop::collection::btree_map(names, node, 0..6).prop_flat_map(|nodes| {
        let doc = json!({
            "geode": "network",
            "version": 1,
            "output": "a",
            "nodes": nodes.into_iter().map(|(n, (t, p, i, bypass))| {
                let mut node = json!({"type": t, "params": p, "inputs": i, "bypass": bypass});
                if t == "subnet" {
                    node["network"] = json!({"output": "x", "nodes": {"x": {"type": "offset", "inputs": ["@0"]}}});
                    node["promote"] = json!({"count": "x/by"});
                }
                (n.to_string(), node)
            }).collect::<serde_json::Map<_, _>>(),
        });
        Just(doc.to_string())
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn random_networks_load_or_fail_cleanly(text in network()) {
        let reg = common::registry();
        if let Ok(net) = load_str(&text, &reg) {
            let cache = Cache::disabled();
            let engine = Engine::new(net, &cache);
            // Errors are fine; panics are not.
            let _ = engine.cook_output(&CookOptions::at_frame(2.5));
        }
    }

    /// Loaded as the studio loads (problems kept on their nodes), every
    /// node cooks or fails, cycles included, and never panics or hangs.
    #[test]
    fn random_networks_cook_every_node_when_loaded_partially(text in network()) {
        let reg = common::registry();
        let doc = Document::from_json(&text).unwrap();
        let net = Network::load_partial(&doc, &reg).unwrap();
        let paths: Vec<String> = net.paths().map(str::to_string).collect();
        let cache = Cache::disabled();
        let engine = Engine::new(net, &cache);
        for path in paths {
            let _ = engine.cook(&path, &CookOptions::at_frame(2.5));
        }
    }

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,200}") {
        let _ = load_str(&text, &common::registry());
    }
}
