//! Ramp parameters through networks: keys written as rows (sorted by
//! position at load, each field animatable), errors naming the node, the
//! key and the field, the ramp in the cook key, spare ramps on wrangles,
//! and the nodes that take ramps (attribute_remap, sweep) against analytic
//! answers.

mod common;
use common::*;

use geode_geo::glam::Vec3;
use geode_geo::AttribClass;
use geode_graph::{load_str, Cache, CookOptions, Engine, LoadError};
use geode_op::{CookEnv, ParamValue};

fn load(nodes: &str) -> Result<geode_graph::Network, Vec<LoadError>> {
    load_str(&net(nodes, "n"), &geode_nodes::registry())
}

fn errors(nodes: &str) -> Vec<String> {
    match load(nodes) {
        Ok(_) => panic!("loaded"),
        Err(e) => e.iter().map(|e| e.to_string()).collect(),
    }
}

/// Eleven points from x = 0 to x = 1 remapped on P with `params`: the new x
/// of each.
fn remapped_x(params: &str, frame: f64) -> Vec<f32> {
    let nodes = format!(
        r#""l": {{"type": "curve_line", "params": {{"points": 11, "end": [1, 0, 0]}}}},
            "n": {{"type": "attribute_remap", "inputs": ["l"], "params": {{"name": "P", {params}}}}}"#
    );
    let g = cook_at(&nodes, "n", frame).unwrap_or_else(|e| panic!("{e}"));
    g.as_geometry()
        .unwrap()
        .positions()
        .iter()
        .map(|p| p.x)
        .collect()
}

fn smoothstep(t: f32) -> f32 {
    t * t * (3.0 - 2.0 * t)
}

#[test]
fn attribute_remap_fits_through_the_ramp() {
    // The default ramp is the straight line: input 0..1 to output 0..2 doubles.
    let x = remapped_x(r#""output_max": 2"#, 1.0);
    for (k, v) in x.iter().enumerate() {
        assert!((v - 0.2 * k as f32).abs() < 1e-6, "{k}: {v}");
    }
    // Two monotone cubic keys ease in and out: smoothstep, scaled.
    let x = remapped_x(
        r#""output_max": 2, "ramp": [{"pos": 0, "value": 0, "interp": "monotonecubic"},
                                   {"pos": 1, "value": 1, "interp": "monotonecubic"}]"#,
        1.0,
    );
    for (k, v) in x.iter().enumerate() {
        let t = k as f32 / 10.0;
        assert!((v - 2.0 * smoothstep(t)).abs() < 1e-6, "{k}: {v}");
    }
    // An input range of 0..0.5: beyond it clamps (to the ramp's end, 1 -> 2).
    let x = remapped_x(r#""input_max": 0.5, "output_max": 2"#, 1.0);
    assert!(
        (x[2] - 0.8).abs() < 1e-6 && x[5] == 2.0 && x[10] == 2.0,
        "{x:?}"
    );
    let x = remapped_x(
        r#""input_max": 0.5, "output_max": 2, "out_of_range": "extrapolate""#,
        1.0,
    );
    assert!((x[10] - 4.0).abs() < 1e-6, "{x:?}");
    let x = remapped_x(
        r#""input_max": 0.5, "output_max": 2, "out_of_range": "cycle""#,
        1.0,
    );
    assert!((x[7] - 0.8).abs() < 1e-6, "{x:?}");
    // A new name leaves the original alone.
    let nodes = r#""l": {"type": "curve_line", "params": {"points": 3, "end": [1, 0, 0]}},
        "n": {"type": "attribute_remap", "inputs": ["l"], "params": {"name": "P", "new_name": "Pr", "output_max": 3}}"#;
    let g = geo(nodes, "n");
    let pr = g
        .attrib(AttribClass::Point, "Pr")
        .unwrap()
        .as_vec3()
        .unwrap();
    assert_eq!(pr[2], Vec3::new(3.0, 0.0, 0.0));
    assert_eq!(g.positions()[2], Vec3::new(1.0, 0.0, 0.0));
}

#[test]
fn attribute_remap_names_what_it_cannot_remap() {
    let e = err(
        r#""b": {"type": "box"}, "n": {"type": "attribute_remap", "inputs": ["b"], "params": {"name": "Cd"}}"#,
        "n",
    );
    assert!(
        e.contains("/n") && e.contains("name") && e.contains("no point attribute `Cd`"),
        "{e}"
    );
    let e = err(
        r#""b": {"type": "box"}, "n": {"type": "attribute_remap", "inputs": ["b"], "params": {"name": "P", "input_max": 0}}"#,
        "n",
    );
    assert!(
        e.contains("input_max") && e.contains("input range is empty"),
        "{e}"
    );
}

#[test]
fn keys_load_sorted_and_out_of_order_keys_cook_the_same() {
    let sorted = remapped_x(
        r#""ramp": [{"pos": 0, "value": 0}, {"pos": 0.5, "value": 1, "interp": "catmull-rom"}, {"pos": 1, "value": 0}]"#,
        1.0,
    );
    let shuffled = remapped_x(
        r#""ramp": [{"pos": 1, "value": 0}, {"pos": 0, "value": 0}, {"interp": "catmull-rom", "value": 1, "pos": 0.5}]"#,
        1.0,
    );
    assert_eq!(sorted, shuffled);
    assert_eq!(sorted[5], 1.0);
    let net = load(
        r#""l": {"type": "curve_line"}, "n": {"type": "attribute_remap", "inputs": ["l"], "params": {"name": "P",
            "ramp": [{"pos": 0.9, "value": 3}, {"pos": 0.1, "value": 2, "interp": "constant"}]}}"#,
    )
    .unwrap();
    let values = net.param_values("/n", 1.0, &CookEnv::default()).unwrap();
    let ramp = values.iter().find(|(n, _)| n == "ramp").unwrap();
    let Ok(ParamValue::Ramp(r)) = &ramp.1 else {
        panic!("{ramp:?}")
    };
    let pos: Vec<f64> = r.keys().iter().map(|k| k.pos).collect();
    assert_eq!(pos, [0.1, 0.9]);
    assert_eq!(r.eval_float(0.5), 2.0);
}

#[test]
fn bad_keys_are_named_by_node_key_and_field() {
    let e = errors(
        r#""l": {"type": "curve_line"}, "n": {"type": "attribute_remap", "inputs": ["l"], "params": {"ramp": [
            {"pos": 0, "value": 0, "interp": "cubic"},
            {"pos": 1.5, "value": 1},
            {"pos": 0.5, "value": [1, 2, 3]},
            {"pos": 0.2, "valeu": 1},
            {"pos": 0.3, "value": {"expr": "pow(10, 40)"}}
        ]}}"#,
    );
    assert_eq!(
        e,
        [
            "/n: parameter `ramp[0].interp`: `cubic` is not one of constant, linear, catmull-rom, monotonecubic, bspline",
            "/n: parameter `ramp[1].pos`: value 1.5 is above the maximum 1",
            "/n: parameter `ramp[2].value`: expected float (a number, a channel or {\"expr\": ...}), found an array of 3",
            "/n: parameter `ramp[3]`: unknown field `valeu` (did you mean `value`?) (fields: `pos`, `value`, `interp`)",
        ]
    );
    let e = errors(
        r#""l": {"type": "curve_line"}, "n": {"type": "attribute_remap", "inputs": ["l"], "params": {"ramp": 1}}"#,
    );
    assert_eq!(
        e,
        ["/n: parameter `ramp`: expected a ramp's keys (an array of objects with fields `pos`, `value`, `interp`), found number 1"]
    );
    // An expression that is not a finite number at a frame fails that
    // frame's cook, naming the key's field.
    let e = err(
        r#""l": {"type": "curve_line"}, "n": {"type": "attribute_remap", "inputs": ["l"], "params": {"name": "P",
            "ramp": [{"pos": 0, "value": 0}, {"pos": 1, "value": {"expr": "pow(10, 40)"}}]}}"#,
        "n",
    );
    assert!(
        e.contains("/n") && e.contains("ramp[1].value") && e.contains("gives inf"),
        "{e}"
    );
}

#[test]
fn animated_keys_recook_and_every_key_is_in_the_cook_key() {
    let ramp = r#""ramp": [{"pos": 0, "value": 0},
        {"pos": {"keys": [{"frame": 1, "value": 1}, {"frame": 11, "value": 0.5}]}, "value": {"expr": "$F * 0.1"}}]"#;
    // At frame 1 the second key is (1, 0.1); at frame 11 (0.5, 1.1).
    let x1 = remapped_x(ramp, 1.0);
    assert!(
        (x1[10] - 0.1).abs() < 1e-6 && (x1[5] - 0.05).abs() < 1e-6,
        "{x1:?}"
    );
    let x11 = remapped_x(ramp, 11.0);
    assert!(
        (x11[5] - 1.1).abs() < 1e-6 && (x11[10] - 1.1).abs() < 1e-6,
        "{x11:?}"
    );
    let net = load(&format!(
        r#""l": {{"type": "curve_line"}}, "n": {{"type": "attribute_remap", "inputs": ["l"], "params": {{"name": "P", {ramp}}}}}"#
    ))
    .unwrap();
    assert!(net.is_animated("/n"));
    // Each field of each key moves the key: position, value, interpolation.
    let key = |ramp: &str| {
        let net = load(&format!(
            r#""l": {{"type": "curve_line"}}, "n": {{"type": "attribute_remap", "inputs": ["l"], "params": {{"name": "P", "ramp": {ramp}}}}}"#
        ))
        .unwrap();
        let cache = Cache::disabled();
        let r = Engine::new(net, &cache)
            .cook("/n", &CookOptions::at_frame(1.0))
            .unwrap();
        r.events.iter().find(|e| e.path == "/n").unwrap().key
    };
    let base = key(r#"[{"pos": 0, "value": 0}, {"pos": 1, "value": 1}]"#);
    let variants = [
        r#"[{"pos": 0, "value": 0}, {"pos": 0.9, "value": 1}]"#,
        r#"[{"pos": 0, "value": 0}, {"pos": 1, "value": 0.9}]"#,
        r#"[{"pos": 0, "value": 0, "interp": "bspline"}, {"pos": 1, "value": 1}]"#,
        r#"[{"pos": 0, "value": 0}, {"pos": 1, "value": 1}, {"pos": 1, "value": 1}]"#,
    ];
    for v in variants {
        assert_ne!(key(v), base, "{v}");
    }
    // The same keys in another order are the same ramp, so the same key.
    assert_eq!(
        key(r#"[{"pos": 1, "value": 1}, {"pos": 0, "value": 0}]"#),
        base
    );
}

#[test]
fn spare_ramps_load_on_wrangles_with_their_defaults_and_errors() {
    let net = load(
        r#""l": {"type": "curve_line"}, "n": {"type": "wrangle", "inputs": ["l"], "spare": {"profile": "ramp", "tint": "colorramp"},
            "params": {"profile": [{"pos": 0, "value": 1, "interp": "catmull-rom"}, {"pos": 0.5, "value": 0}, {"pos": 1, "value": 1}]}}"#,
    )
    .unwrap();
    let values = net.param_values("/n", 1.0, &CookEnv::default()).unwrap();
    let get = |name: &str| match &values.iter().find(|(n, _)| n == name).unwrap().1 {
        Ok(ParamValue::Ramp(r)) => r.clone(),
        v => panic!("{v:?}"),
    };
    assert_eq!(get("profile").keys().len(), 3);
    assert_eq!(get("profile").eval_float(0.5), 0.0);
    // A colour ramp not given takes the default: black to white, linear.
    assert_eq!(get("tint").eval(0.25), [0.25; 3]);
    let e = errors(
        r#""l": {"type": "curve_line"}, "n": {"type": "wrangle", "inputs": ["l"], "spare": {"profile": "ramp", "bad": "rampe"},
            "params": {"profile": [{"pos": 0, "value": 1, "interp": "smooth"}]}}"#,
    );
    assert_eq!(
        e,
        [
            "/n: parameter `bad`: unknown spare parameter type `rampe`: expected one of float, int, toggle, vector2, vector, vector4, string, ramp, colorramp",
            "/n: parameter `profile[0].interp`: `smooth` is not one of constant, linear, catmull-rom, monotonecubic, bspline",
        ]
    );
}

/// chramp: "Returns the value of a ramp parameter at position x" (SideFX's
/// chramp page): a linear float ramp from 0 at 0 to 2 at 1 gives 2x along a
/// line of eleven points; a colour ramp from red to blue gives the mix; ch()
/// of a ramp is its key count, as a multiparm's.
#[test]
fn chramp_reads_spare_ramps_in_wrangles() {
    let nodes = r#""l": {"type": "curve_line", "params": {"points": 11, "end": [1, 0, 0]}},
        "n": {"type": "wrangle", "inputs": ["l"], "spare": {"profile": "ramp", "tint": "colorramp"},
            "params": {"snippet": "f@h = chramp(\"profile\", @P.x); v@c = chramp(\"tint\", @P.x); i@keys = chi(\"profile\");",
                "profile": [{"pos": 0, "value": 0, "interp": "linear"}, {"pos": 1, "value": 2}],
                "tint": [{"pos": 0, "value": [1, 0, 0], "interp": "linear"}, {"pos": 1, "value": [0, 0, 1]}]}}"#;
    let g = cook_at(nodes, "n", 1.0).unwrap_or_else(|e| panic!("{e}"));
    let g = g.as_geometry().unwrap();
    let h = g.attrib(AttribClass::Point, "h").unwrap().as_f32().unwrap();
    let c = g
        .attrib(AttribClass::Point, "c")
        .unwrap()
        .as_vec3()
        .unwrap();
    for (i, (h, c)) in h.iter().zip(c).enumerate() {
        let x = i as f32 / 10.0;
        assert!((h - 2.0 * x).abs() < 1e-5, "{i}: {h}");
        assert!(
            (*c - Vec3::new(1.0 - x, 0.0, x)).length() < 1e-5,
            "{i}: {c}"
        );
    }
    let keys = g
        .attrib(AttribClass::Point, "keys")
        .unwrap()
        .as_i32()
        .unwrap();
    assert_eq!(keys[0], 2);
    // A parameter that is not a ramp is named.
    let bad = r#""l": {"type": "curve_line"}, "n": {"type": "wrangle", "inputs": ["l"], "spare": {"amp": "float"},
            "params": {"snippet": "f@h = chramp(\"amp\", 0.5);"}}"#;
    let e = cook_at(bad, "n", 1.0).unwrap_err().to_string();
    assert!(
        e.contains("chramp(\"amp\"): the parameter is not a ramp"),
        "{e}"
    );
}

/// The distance of each ring of a sweep (16 sides) from the line it follows.
fn ring_radii(params: &str) -> Vec<f32> {
    let nodes = format!(
        r#""l": {{"type": "curve_line", "params": {{"points": 5, "end": [0, 4, 0]}}}},
            "n": {{"type": "sweep", "inputs": ["l"], "params": {{"sides": 16, "radius": 0.5, "caps": false{params}}}}}"#
    );
    let g = geo(&nodes, "n");
    let p = g.positions();
    (0..5).map(|i| p[i * 16].with_y(0.0).length()).collect()
}

#[test]
fn sweep_scales_along_the_curve_by_its_ramp() {
    // Flat at 1 by default.
    for r in ring_radii("") {
        assert!((r - 0.5).abs() < 1e-6);
    }
    // Linear from 1 to 0.2: the rings at u = 0, 0.25 ... 1.
    let r = ring_radii(r#", "ramp": [{"pos": 0, "value": 1}, {"pos": 1, "value": 0.2}]"#);
    for (k, v) in r.iter().enumerate() {
        let u = k as f32 / 4.0;
        assert!((v - 0.5 * (1.0 - 0.8 * u)).abs() < 1e-6, "{k}: {v}");
    }
    // Houdini's "Hill": a monotone cubic bump, widest in the middle.
    let r = ring_radii(
        r#", "ramp": [{"pos": 0, "value": 0, "interp": "monotonecubic"}, {"pos": 0.5, "value": 1, "interp": "monotonecubic"}, {"pos": 1, "value": 0}]"#,
    );
    assert!(
        (r[2] - 0.5).abs() < 1e-6 && r[0] < 1e-6 && r[4] < 1e-6,
        "{r:?}"
    );
    assert!((r[1] - 0.5 * smoothstep(0.5)).abs() < 1e-6, "{r:?}");
    // The old text form still loads, as linear keys, with a note.
    let old = ring_radii(r#", "ramp": "0 1, 1 0.2""#);
    let new = ring_radii(r#", "ramp": [{"pos": 0, "value": 1}, {"pos": 1, "value": 0.2}]"#);
    assert_eq!(old, new);
    let net = load(r#""l": {"type": "curve_line"}, "n": {"type": "sweep", "inputs": ["l"], "params": {"ramp": "0 1, 1 0.2"}}"#).unwrap();
    assert_eq!(
        net.notes().iter().map(|n| n.to_string()).collect::<Vec<_>>(),
        ["/n: parameter `ramp`: read from the old text form as 2 rows; write it as a list of objects with fields `pos`, `value`, `interp`"]
    );
    // An emptied ramp multiplies by 1, as the old empty text did.
    for r in ring_radii(r#", "ramp": []"#) {
        assert!((r - 0.5).abs() < 1e-6);
    }
}
