//! The live session: edits checked as the loader checks files, wires and names kept consistent, keys, undo and redo, slider drags as one step, saving in `geode fmt`'s form.

use std::path::PathBuf;
use std::sync::Arc;

use geode_graph::Document;
use geode_server::edits::{apply, Edit};
use geode_server::Session;
use serde_json::{json, Value};

fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

fn registry() -> Arc<geode_op::Registry> {
    Arc::new(geode_nodes::registry())
}

fn edit(j: Value) -> Edit {
    serde_json::from_value(j).unwrap()
}

fn doc(name: &str) -> Document {
    Document::from_json(&std::fs::read_to_string(example(name)).unwrap()).unwrap()
}

#[test]
fn adding_names_nodes_as_houdini_does_and_refuses_unknown_types() {
    let r = registry();
    let d = apply(
        &doc("coral.json"),
        &edit(json!({"kind": "add_node", "parent": "/", "type": "box"})),
        &r,
    )
    .unwrap();
    let d = apply(
        &d,
        &edit(json!({"kind": "add_node", "parent": "/", "type": "box", "pos": [10, 20]})),
        &r,
    )
    .unwrap();
    assert!(d.network.nodes.contains_key("box1") && d.network.nodes.contains_key("box2"));
    assert_eq!(
        d.network.nodes["box2"].extra["ui"]["pos"],
        json!([10.0, 20.0])
    );
    let e = apply(
        &d,
        &edit(json!({"kind": "add_node", "parent": "/", "type": "boxx"})),
        &r,
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "/: unknown node type `boxx` (did you mean `box`?)"
    );
    let e = apply(
        &d,
        &edit(json!({"kind": "add_node", "parent": "/nowhere", "type": "box"})),
        &r,
    )
    .unwrap_err();
    assert_eq!(e.to_string(), "/nowhere: no such subnetwork");
}

#[test]
fn renaming_rewires_inputs_output_and_promotions() {
    let r = registry();
    let d = apply(
        &doc("coral.json"),
        &edit(json!({"kind": "rename", "path": "/both", "name": "result"})),
        &r,
    )
    .unwrap();
    assert_eq!(d.network.output.as_deref(), Some("result"));
    let d = apply(
        &d,
        &edit(json!({"kind": "rename", "path": "/grow", "name": "branches"})),
        &r,
    )
    .unwrap();
    assert_eq!(
        d.network.nodes["tubes"].inputs,
        vec![Some("branches".to_owned())]
    );
    assert!(geode_graph::Network::load(&d, &r).is_ok());
    let d = apply(
        &doc("rig.json"),
        &edit(json!({"kind": "rename", "path": "/rig/raise", "name": "lifted"})),
        &r,
    )
    .unwrap();
    assert_eq!(d.network.nodes["rig"].promote["lift"], "lifted/translate");
    assert!(geode_graph::Network::load(&d, &r).is_ok());
    let e = apply(
        &d,
        &edit(json!({"kind": "rename", "path": "/rig", "name": "9lives"})),
        &r,
    )
    .unwrap_err();
    assert!(e.message.contains("is not a node name"), "{e}");
    let e = apply(
        &d,
        &edit(json!({"kind": "rename", "path": "/rig", "name": "plate"})),
        &r,
    )
    .unwrap_err();
    assert_eq!(e.message, "a node named `plate` exists");
}

#[test]
fn loops_and_solvers_take_wires_into_every_declared_input() {
    let r = registry();
    let mut d = doc("coral.json");
    for ty in ["loop", "solver", "subnet"] {
        d = apply(
            &d,
            &edit(json!({"kind": "add_node", "parent": "/", "type": ty, "name": ty})),
            &r,
        )
        .unwrap();
        for input in 0..4 {
            d = apply(
                &d,
                &edit(json!({"kind": "connect", "from": "/food", "to": format!("/{ty}"), "input": input})),
                &r,
            )
            .unwrap_or_else(|e| panic!("{ty} input {input}: {e}"));
        }
        assert_eq!(d.network.nodes[ty].inputs.len(), 4);
        assert!(
            d.network.nodes[ty].network.is_some(),
            "{ty} holds a network"
        );
        let e = apply(
            &d,
            &edit(json!({"kind": "connect", "from": "/food", "to": format!("/{ty}"), "input": 4})),
            &r,
        )
        .unwrap_err();
        assert_eq!(e.to_string(), format!("/{ty}: has no input 5"));
    }
    // A typo is refused with the engine's own types among the suggestions.
    let e = apply(
        &d,
        &edit(json!({"kind": "add_node", "parent": "/", "type": "lop"})),
        &r,
    )
    .unwrap_err();
    assert!(e.to_string().contains("did you mean `loop`?"), "{e}");
}

#[test]
fn wires_refuse_cycles_and_mismatched_ports() {
    let r = registry();
    let d = doc("coral.json");
    let e = apply(
        &d,
        &edit(json!({"kind": "connect", "from": "/both", "to": "/grow", "input": 0})),
        &r,
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "/grow: wiring `both` into it would make a cycle"
    );
    // A field into a geometry input.
    let e = apply(
        &d,
        &edit(json!({"kind": "connect", "from": "/skeleton", "to": "/beside", "input": 0})),
        &r,
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "/beside: input 1 takes geometry, but `skeleton` produces field"
    );
    let d = apply(
        &d,
        &edit(json!({"kind": "connect", "from": "/crown", "to": "/smooth", "input": 0})),
        &r,
    )
    .unwrap();
    assert_eq!(
        d.network.nodes["smooth"].inputs,
        vec![Some("crown".to_owned())]
    );
    let d = apply(
        &d,
        &edit(json!({"kind": "disconnect", "to": "/both", "input": 1})),
        &r,
    )
    .unwrap();
    assert_eq!(
        d.network.nodes["both"].inputs,
        vec![Some("tubes".to_owned())]
    );
}

#[test]
fn removing_a_node_drops_its_wires_and_the_output() {
    let r = registry();
    let d = apply(
        &doc("coral.json"),
        &edit(json!({"kind": "remove_nodes", "paths": ["/grow", "/both"]})),
        &r,
    )
    .unwrap();
    assert!(d.network.nodes["tubes"].inputs.is_empty());
    assert_eq!(d.network.output, None);
}

#[test]
fn an_unwired_node_is_a_problem_of_its_own_and_the_display_still_cooks() {
    let r = registry();
    let mut s = Session::open(Some(&example("primitives.json")), r).unwrap();
    s.edit(
        &edit(json!({"kind": "add_node", "parent": "/", "type": "transform", "name": "loose"})),
        false,
    )
    .unwrap();
    let problems = s.problems();
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert_eq!(problems[0]["path"], "/loose");
    assert_eq!(problems[0]["level"], "error");
    let net = s.network().as_ref().unwrap().clone();
    let cache = geode_graph::Cache::disabled();
    let engine = geode_graph::Engine::new(net, &cache);
    let opts = geode_graph::CookOptions::at_frame(1.0);
    assert!(engine.cook_output(&opts).is_ok());
    let err = engine.cook("/loose", &opts).err().unwrap();
    assert_eq!(
        err[0].to_string(),
        "/loose: input 1 (geometry) is required but not connected"
    );
}

#[test]
fn parameters_are_checked_by_the_loader_not_refused() {
    let r = registry();
    let mut s = Session::open(Some(&example("coral.json")), r).unwrap();
    s.edit(
        &edit(json!({"kind": "set_param", "path": "/grow", "param": "kill", "value": -1})),
        false,
    )
    .unwrap();
    let problems = s.problems();
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert_eq!(problems[0]["path"], "/grow");
    assert_eq!(problems[0]["param"], "kill");
    assert!(problems[0]["message"]
        .as_str()
        .unwrap()
        .contains("below the minimum"));
    // An unknown parameter names nothing: refused.
    let e = s
        .edit(
            &edit(json!({"kind": "set_param", "path": "/grow", "param": "kil", "value": 1})),
            false,
        )
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "/grow: has no parameter `kil` (did you mean `kill`?)"
    );
    s.edit(
        &edit(json!({"kind": "set_param", "path": "/grow", "param": "kill", "value": null})),
        false,
    )
    .unwrap();
    assert!(s.network().is_ok());
    assert!(!s.document().network.nodes["grow"]
        .params
        .contains_key("kill"));
}

#[test]
fn keys_turn_constants_into_channels_and_back() {
    let r = registry();
    let mut s = Session::open(Some(&example("coral.json")), r).unwrap();
    let key = |frame: f64, value: f64| {
        edit(
            json!({"kind": "set_key", "path": "/beside", "param": "translate", "component": 1, "frame": frame, "value": value}),
        )
    };
    s.edit(&key(1.0, 0.0), false).unwrap();
    s.edit(&key(24.0, 2.0), false).unwrap();
    s.edit(&key(24.0, 3.0), false).unwrap();
    let t = &s.document().network.nodes["beside"].params["translate"];
    assert_eq!(t[0], json!(3));
    assert_eq!(
        t[1],
        json!({"keys": [{"frame": 1.0, "value": 0.0}, {"frame": 24.0, "value": 3.0}]})
    );
    let net = s.network().as_ref().unwrap();
    assert!(net.is_animated("/beside"));
    let del = |frame: f64| {
        edit(
            json!({"kind": "delete_key", "path": "/beside", "param": "translate", "component": 1, "frame": frame}),
        )
    };
    s.edit(&del(1.0), false).unwrap();
    s.edit(&del(24.0), false).unwrap();
    assert_eq!(
        s.document().network.nodes["beside"].params["translate"],
        json!([3, 3.0, 0])
    );
    let e = s.edit(&del(5.0), false).unwrap_err();
    assert!(e.message.contains("not animated"), "{e}");
}

#[test]
fn undo_redo_and_a_drag_as_one_step() {
    let r = registry();
    let mut s = Session::open(Some(&example("coral.json")), r).unwrap();
    let original = s.document().clone();
    let set =
        |v: f64| edit(json!({"kind": "set_param", "path": "/grow", "param": "step", "value": v}));
    s.edit(&set(0.06), false).unwrap();
    s.edit(&set(0.07), true).unwrap();
    s.edit(&set(0.08), true).unwrap();
    assert!(s.is_dirty());
    assert!(s.undo());
    assert_eq!(s.document(), &original, "the drag undoes as one step");
    assert!(!s.is_dirty());
    assert!(!s.undo());
    assert!(s.redo());
    assert_eq!(
        s.document().network.nodes["grow"].params["step"],
        json!(0.08)
    );
    // A new edit clears the redo stack.
    s.edit(&set(0.05), false).unwrap();
    assert!(!s.redo());
}

#[test]
fn save_writes_what_geode_fmt_writes_and_keeps_unknown_fields() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("coral.json");
    let mut text = std::fs::read_to_string(example("coral.json")).unwrap();
    text = text.replacen(
        "\"version\": 1,",
        "\"version\": 1, \"studio_future\": {\"x\": 1},",
        1,
    );
    std::fs::write(&path, &text).unwrap();
    let mut s = Session::open(Some(&path), registry()).unwrap();
    s.edit(
        &edit(json!({"kind": "move", "positions": {"/grow": [12.34, 56.78]}})),
        false,
    )
    .unwrap();
    assert!(s.is_dirty());
    s.save(None).unwrap();
    assert!(!s.is_dirty());
    let saved = std::fs::read_to_string(&path).unwrap();
    // `geode fmt` is: parse, then write the document's canonical JSON.
    assert_eq!(Document::from_json(&saved).unwrap().to_json(), saved);
    assert!(saved.contains("\"studio_future\""));
    assert!(
        saved.contains("\"pos\": [\n          12.3,\n          56.8\n        ]"),
        "{saved}"
    );
    let e = s.save(Some(&dir.path().join("x.txt"))).unwrap_err();
    assert!(e.to_string().contains("ends in .json"));
    let other = dir.path().join("copy.json");
    s.save(Some(&other)).unwrap();
    assert_eq!(s.path(), Some(other.as_path()));
}

#[test]
fn paste_renames_collisions_and_keeps_inner_wires_only() {
    let r = registry();
    let d = doc("coral.json");
    let nodes = json!({
        "grow": d.network.nodes["grow"],
        "tubes": d.network.nodes["tubes"],
    });
    let d2 = apply(
        &d,
        &edit(json!({"kind": "paste", "parent": "/", "nodes": nodes, "offset": [30, 30]})),
        &r,
    )
    .unwrap();
    assert_eq!(
        d2.network.nodes["tubes1"].inputs,
        vec![Some("grow1".to_owned())]
    );
    assert!(
        d2.network.nodes["grow1"].inputs.is_empty(),
        "wires from outside the copy are dropped"
    );
}

#[test]
fn spare_parameters_are_declared_where_taken_and_keyed_like_any_other() {
    let r = registry();
    let d = apply(&doc("chain_vex.json"), &edit(json!({"kind": "set_spare", "path": "/compute_tangent", "name": "gain", "type": "float"})), &r).unwrap();
    assert_eq!(d.network.nodes["compute_tangent"].spare["gain"], "float");
    let d = apply(&d, &edit(json!({"kind": "set_key", "path": "/compute_tangent", "param": "gain", "component": 0, "frame": 5, "value": 2})), &r).unwrap();
    assert!(d.network.nodes["compute_tangent"].params["gain"]["keys"].is_array());
    let e = apply(
        &d,
        &edit(json!({"kind": "set_spare", "path": "/curve", "name": "gain", "type": "float"})),
        &r,
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "/curve: a curve_helix takes no spare parameters"
    );
    let e = apply(&d, &edit(json!({"kind": "set_spare", "path": "/compute_tangent", "name": "snippet", "type": "float"})), &r).unwrap_err();
    assert_eq!(
        e.to_string(),
        "/compute_tangent: `snippet` is one of the node's own parameters"
    );
    let d = apply(
        &d,
        &edit(
            json!({"kind": "set_spare", "path": "/compute_tangent", "name": "gain", "type": null}),
        ),
        &r,
    )
    .unwrap();
    assert!(d.network.nodes["compute_tangent"].spare.is_empty());
    assert!(!d.network.nodes["compute_tangent"]
        .params
        .contains_key("gain"));
    // Removing a spare parameter that is not there is refused, and never
    // drops the value of a parameter of the node's own.
    for name in ["gain", "snippet"] {
        let e = apply(
            &d,
            &edit(json!({"kind": "set_spare", "path": "/compute_tangent", "name": name, "type": null})),
            &r,
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            format!("/compute_tangent: has no spare parameter `{name}`")
        );
    }
    assert!(d.network.nodes["compute_tangent"]
        .params
        .contains_key("snippet"));
    // An unknown parameter's refusal names the nearest one.
    let e = apply(
        &d,
        &edit(json!({"kind": "set_param", "path": "/compute_tangent", "param": "snipet", "value": ""})),
        &r,
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "/compute_tangent: has no parameter `snipet` (did you mean `snippet`?)"
    );
}

#[test]
fn the_frame_range_and_rate_are_kept_in_the_document() {
    let r = registry();
    let d = apply(
        &doc("coral.json"),
        &edit(json!({"kind": "set_timeline", "frames": [1, 90], "fps": 30})),
        &r,
    )
    .unwrap();
    let text = serde_json::to_value(&d).unwrap();
    assert_eq!(text["frames"], json!([1.0, 90.0]));
    assert_eq!(text["fps"], json!(30.0));
    for bad in [
        json!({"frames": [9, 1], "fps": 24}),
        json!({"frames": [1, 9], "fps": 0}),
    ] {
        let mut e = bad.clone();
        e["kind"] = json!("set_timeline");
        assert!(apply(&d, &edit(e), &r).is_err(), "{bad}");
    }
}

#[test]
fn a_node_added_after_another_is_wired_to_it_in_one_step() {
    let r = registry();
    let d = apply(
        &doc("coral.json"),
        &edit(json!({"kind": "add_node", "parent": "/", "type": "transform", "name": "next", "after": "/beside"})),
        &r,
    )
    .unwrap();
    assert_eq!(
        d.network.nodes["next"].inputs,
        vec![Some("beside".to_owned())]
    );
    // A port that does not agree refuses the whole edit.
    let e = apply(
        &doc("coral.json"),
        &edit(
            json!({"kind": "add_node", "parent": "/", "type": "transform", "after": "/skeleton"}),
        ),
        &r,
    )
    .unwrap_err();
    assert!(e.to_string().contains("produces field"), "{e}");
}

#[test]
fn each_tab_undoes_its_own_edits_and_never_another_tabs() {
    let r = registry();
    let mut s = Session::open(Some(&example("coral.json")), r).unwrap();
    let set =
        |v: f64| edit(json!({"kind": "set_param", "path": "/grow", "param": "step", "value": v}));
    s.edit_by(&set(0.1), false, 1).unwrap();
    s.edit_by(&set(0.2), false, 2).unwrap();
    assert_eq!(s.state()["undoBy"], 2);
    // Tab 1's step is under tab 2's: undoing it would drop tab 2's edit.
    let e = s.undo_by(1).unwrap_err();
    assert_eq!(
        e.to_string(),
        "another tab made the latest change: undo it there (each tab undoes its own edits)"
    );
    s.undo_by(2).unwrap();
    assert_eq!(
        s.document().network.nodes["grow"].params["step"],
        json!(0.1)
    );
    assert_eq!(s.state()["redoBy"], 2);
    assert!(s.redo_by(1).is_err());
    s.undo_by(1).unwrap();
    assert!(
        !s.document().network.nodes["grow"]
            .params
            .contains_key("step")
            || s.document().network.nodes["grow"].params["step"] != json!(0.1)
    );
    // A slider drag merges only within one tab.
    s.edit_by(&set(0.3), false, 1).unwrap();
    s.edit_by(&set(0.4), true, 2).unwrap();
    s.undo_by(2).unwrap();
    assert_eq!(
        s.document().network.nodes["grow"].params["step"],
        json!(0.3)
    );
}

#[test]
fn notes_boxes_and_colours_are_kept_in_the_file_and_follow_renames() {
    let r = registry();
    let mut d = doc("coral.json");
    for e in [
        json!({"kind": "move", "positions": {"/base": [10, 20]}}),
        json!({"kind": "set_color", "paths": ["/base"], "color": "#ff8800"}),
        json!({"kind": "set_note", "parent": "/", "id": "n1", "note": {"text": "grows for 90 frames", "pos": [0, -80], "size": [200, 60]}}),
        json!({"kind": "set_box", "parent": "/", "id": "b1", "box": {"label": "growth", "nodes": ["base", "grow"], "color": "#335577"}}),
        json!({"kind": "rename", "path": "/base", "name": "start"}),
    ] {
        d = apply(&d, &edit(e.clone()), &r).unwrap_or_else(|err| panic!("{e}: {err}"));
    }
    let text = Document::from_json(&d.to_json()).unwrap();
    let saved = serde_json::to_value(&text).unwrap();
    assert_eq!(
        saved["nodes"]["start"]["ui"],
        json!({"pos": [10.0, 20.0], "color": "#ff8800"})
    );
    assert_eq!(saved["notes"]["n1"]["text"], "grows for 90 frames");
    assert_eq!(saved["boxes"]["b1"]["nodes"], json!(["start", "grow"]));
    // A moved node keeps its colour; a removed node leaves its box.
    let d = apply(
        &d,
        &edit(json!({"kind": "move", "positions": {"/start": [5, 5]}})),
        &r,
    )
    .unwrap();
    let d = apply(
        &d,
        &edit(json!({"kind": "remove_nodes", "paths": ["/grow"]})),
        &r,
    )
    .unwrap();
    let v = serde_json::to_value(&d).unwrap();
    assert_eq!(v["nodes"]["start"]["ui"]["color"], "#ff8800");
    assert_eq!(v["boxes"]["b1"]["nodes"], json!(["start"]));
    for (bad, why) in [
        (
            json!({"kind": "set_color", "paths": ["/start"], "color": "orange"}),
            "#rrggbb",
        ),
        (
            json!({"kind": "set_box", "parent": "/", "id": "b2", "box": {"label": "x", "nodes": ["nope"]}}),
            "`nope` is not one",
        ),
        (
            json!({"kind": "set_note", "parent": "/", "id": "n2", "note": {"text": "", "pos": [0, 0], "size": [0, 10]}}),
            "positive size",
        ),
        (
            json!({"kind": "set_note", "parent": "/", "id": "gone", "note": null}),
            "no note",
        ),
    ] {
        let e = apply(&d, &edit(bad.clone()), &r).unwrap_err();
        assert!(e.to_string().contains(why), "{bad}: {e}");
    }
}

#[test]
fn a_network_name_leading_to_a_device_is_refused_unread() {
    let dir = tempfile::tempdir().unwrap();
    let link = dir.path().join("net.json");
    std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
    let Err(e) = Session::open(Some(&link), registry()) else {
        panic!("opened /dev/zero")
    };
    assert_eq!(
        e.to_string(),
        format!(
            "{}: not a regular file (a character device); only regular files are read",
            link.display()
        )
    );
}
