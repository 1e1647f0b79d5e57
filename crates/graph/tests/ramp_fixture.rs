//! The studio draws ramps with its own evaluator (studio/src/ramp.ts): this
//! test writes the engine's values (`geode_geo::Ramp`) for a set of ramps,
//! every basis and their mixes, at many positions to
//! studio/tests/ramp.fixture.json and fails when the committed file
//! differs, and the studio's unit test checks its evaluator against the
//! file, so the curve drawn is the curve cooked. Set GEODE_BLESS=1 to
//! rewrite the file after a change.

use std::path::PathBuf;

use geode_geo::{Ramp, RampBasis, RampKey, RampKind};
use serde_json::{json, Value};

fn ramps() -> Vec<Value> {
    let all = |interp: &str| {
        json!([
            {"pos": 0.0, "value": 0.1, "interp": interp},
            {"pos": 0.15, "value": 0.9, "interp": interp},
            {"pos": 0.4, "value": 0.3, "interp": interp},
            {"pos": 0.55, "value": 0.8, "interp": interp},
            {"pos": 0.8, "value": 0.2, "interp": interp},
            {"pos": 1.0, "value": 1.0, "interp": interp}
        ])
    };
    let mut out: Vec<Value> = RampBasis::NAMES.iter().map(|b| all(b)).collect();
    out.extend([
        // Keys out of order, a shared position (a step), keys inside 0..1.
        json!([
            {"pos": 0.7, "value": 2.0, "interp": "catmull-rom"},
            {"pos": 0.2, "value": -1.0, "interp": "monotonecubic"},
            {"pos": 0.45, "value": 0.5, "interp": "monotonecubic"},
            {"pos": 0.45, "value": 1.5, "interp": "catmull-rom"},
            {"pos": 0.9, "value": 0.0, "interp": "linear"}
        ]),
        // A B-spline run between other bases, and a constant step.
        json!([
            {"pos": 0.0, "value": 0.0, "interp": "linear"},
            {"pos": 0.3, "value": 1.0, "interp": "bspline"},
            {"pos": 0.4, "value": 0.0, "interp": "bspline"},
            {"pos": 0.5, "value": 1.0, "interp": "bspline"},
            {"pos": 0.7, "value": 1.0, "interp": "constant"},
            {"pos": 0.85, "value": 0.25, "interp": "catmull-rom"},
            {"pos": 1.0, "value": 0.5, "interp": "catmull-rom"}
        ]),
        // Two keys of each smooth basis, and one key.
        json!([{"pos": 0.0, "value": 0.0, "interp": "monotonecubic"}, {"pos": 1.0, "value": 1.0, "interp": "monotonecubic"}]),
        json!([{"pos": 0.1, "value": 1.0, "interp": "bspline"}, {"pos": 0.9, "value": 0.0, "interp": "bspline"}]),
        json!([{"pos": 0.5, "value": 0.25, "interp": "catmull-rom"}]),
        // A colour ramp.
        json!([
            {"pos": 0.0, "value": [0.0, 0.0, 0.5], "interp": "catmull-rom"},
            {"pos": 0.3, "value": [1.0, 0.2, 0.0], "interp": "bspline"},
            {"pos": 0.6, "value": [0.0, 1.0, 0.3], "interp": "bspline"},
            {"pos": 1.0, "value": [1.0, 1.0, 1.0], "interp": "monotonecubic"}
        ]),
    ]);
    out
}

fn ramp(keys: &Value) -> Ramp {
    let keys = keys.as_array().unwrap();
    let kind = if keys[0]["value"].is_array() {
        RampKind::Color
    } else {
        RampKind::Float
    };
    Ramp::new(
        kind,
        keys.iter()
            .map(|k| {
                let value = match &k["value"] {
                    Value::Array(v) => [0, 1, 2].map(|c| v[c].as_f64().unwrap()),
                    v => [v.as_f64().unwrap(), 0.0, 0.0],
                };
                RampKey {
                    pos: k["pos"].as_f64().unwrap(),
                    value,
                    basis: RampBasis::from_name(k["interp"].as_str().unwrap()).unwrap(),
                }
            })
            .collect(),
    )
    .unwrap()
}

#[test]
fn the_studios_ramps_are_the_engines() {
    let mut cases = Vec::new();
    for keys in ramps() {
        let r = ramp(&keys);
        let n = r.kind().components();
        let samples: Vec<Value> = (-10..=210)
            .map(|k| {
                let x = f64::from(k) / 200.0;
                json!([x, &r.eval(x)[..n]])
            })
            .collect();
        cases.push(json!({"keys": keys, "samples": samples}));
    }
    let text = serde_json::to_string_pretty(&cases).unwrap() + "\n";
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../studio/tests/ramp.fixture.json");
    if std::env::var_os("GEODE_BLESS").is_some() {
        std::fs::write(&path, &text).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == text,
        "studio/tests/ramp.fixture.json is not what the engine computes: rerun with GEODE_BLESS=1, then `cd studio && npm test`"
    );
}
