//! The studio draws animation curves with its own evaluator
//! (studio/src/channel.ts): this test writes the engine's values for a set of
//! channels at many frames to studio/tests/channel.fixture.json and fails
//! when the committed file differs, and the studio's unit test checks its
//! evaluator against the file, so the curve drawn is the curve cooked. Set
//! GEODE_BLESS=1 to rewrite the file after a change.

use std::path::PathBuf;

use geode_graph::channel::{Channel, Key};
use serde_json::{json, Value};

fn channels() -> Vec<Value> {
    vec![
        json!([{"frame": 1, "value": 0}, {"frame": 11, "value": 10}]),
        json!([{"frame": 1, "value": 2, "interp": "constant"}, {"frame": 5, "value": -1}, {"frame": 9, "value": 4}]),
        json!([{"frame": 0, "value": 0, "interp": "ease"}, {"frame": 24, "value": 3}]),
        json!([{"frame": 1, "value": 0, "interp": "bezier"}, {"frame": 10, "value": 5, "interp": "bezier"}, {"frame": 20, "value": 1, "interp": "bezier"}, {"frame": 30, "value": 2}]),
        json!([{"frame": 1, "value": 0, "interp": "bezier", "slope_out": 2.5}, {"frame": 13, "value": 1, "slope_in": -0.5, "interp": "bezier", "slope_out": 0}, {"frame": 20, "value": 1}]),
    ]
}

#[test]
fn the_studios_curves_are_the_engines() {
    let mut cases = Vec::new();
    for keys in channels() {
        let parsed: Vec<Key> = serde_json::from_value(keys.clone()).unwrap();
        let ch = Channel::new(parsed).unwrap();
        let samples: Vec<Value> = (-8..=140)
            .map(|k| {
                let f = f64::from(k) * 0.25;
                json!([f, ch.eval(f)])
            })
            .collect();
        cases.push(json!({"keys": keys, "samples": samples}));
    }
    let text = serde_json::to_string_pretty(&cases).unwrap() + "\n";
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../studio/tests/channel.fixture.json");
    if std::env::var_os("GEODE_BLESS").is_some() {
        std::fs::write(&path, &text).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == text,
        "studio/tests/channel.fixture.json is not what the engine computes: rerun with GEODE_BLESS=1, then `cd studio && npm test`"
    );
}
