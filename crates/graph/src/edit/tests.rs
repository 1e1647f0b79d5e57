//! Tests of the edits themselves: the output named per network, and a refused edit that leaves the document as it was.

use super::*;
use serde_json::json;
fn add(d: &mut Document, parent: &str, name: &str, r: &Registry) {
    let edit = Edit::AddNode {
        parent: parent.into(),
        ty: "subnet".into(),
        name: Some(name.into()),
        pos: None,
        after: None,
    };
    apply_in_place(d, &edit, r).unwrap();
}

#[test]
fn the_output_is_named_per_network_and_a_refused_edit_changes_nothing() {
    // The engine's own types need no library.
    let r = Registry::new();
    let mut d = Document::new();
    add(&mut d, "/", "a", &r);
    add(&mut d, "/a", "inner", &r);
    let set = |parent: &str, node: Option<&str>| Edit::SetOutput {
        parent: parent.into(),
        node: node.map(str::to_owned),
    };
    apply_in_place(&mut d, &set("/", Some("a")), &r).unwrap();
    apply_in_place(&mut d, &set("/a", Some("inner")), &r).unwrap();
    assert_eq!(d.network.output.as_deref(), Some("a"));
    let inner = d.network.nodes["a"].network.as_deref().unwrap();
    assert_eq!(inner.output.as_deref(), Some("inner"));
    let before = d.clone();
    for refused in [
        set("/", Some("nope")),
        set("/nope", None),
        Edit::Connect {
            from: "/a".into(),
            to: "/a".into(),
            input: 0,
        },
        Edit::SetParam {
            path: "/a".into(),
            param: "nope".into(),
            value: json!(1),
        },
    ] {
        assert!(apply_in_place(&mut d, &refused, &r).is_err(), "{refused:?}");
        assert_eq!(d, before, "{refused:?} changed the document");
    }
    apply_in_place(&mut d, &set("/", None), &r).unwrap();
    assert_eq!(d.network.output, None);
}
