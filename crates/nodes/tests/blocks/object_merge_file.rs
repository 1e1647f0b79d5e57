//! object_merge from another network file: the other file's node cooked at
//! this frame with its own `$HIP`, edits to it (or to a file it reads)
//! recooking the merge, and files that reach themselves refused.

use std::path::Path;

use geode_graph::{Cache, CookOptions, Engine};
use geode_op::CookEnv;

fn write(dir: &Path, name: &str, nodes: &str, output: &str) {
    std::fs::write(dir.join(name), super::net(nodes, output)).unwrap();
}

fn cook_file(dir: &Path, name: &str, cache: &Cache) -> Result<geode_op::Value, String> {
    let path = dir.join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    let net =
        geode_graph::load_str(&text, &geode_nodes::registry()).map_err(|e| format!("{e:?}"))?;
    let mut opts = CookOptions::at_frame(3.0);
    opts.env = CookEnv::for_network(&path);
    Engine::new(net, cache)
        .cook_output(&opts)
        .map(|r| r.value)
        .map_err(|e| {
            e.iter()
                .map(|e| format!("{e} [{:?}]", e.param))
                .collect::<Vec<_>>()
                .join("\n")
        })
}

#[test]
fn merges_a_node_of_another_network_file_and_recooks_when_it_changes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The other network reads a file of its own folder through `$HIP` and
    // moves it by the frame.
    std::fs::write(d.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    write(
        d,
        "parts.json",
        r#""tri": {"type": "file", "params": {"file": "$HIP/tri.obj"}},
           "up": {"type": "transform", "inputs": ["tri"], "params": {"translate": [0, {"expr": "$F"}, 0]}},
           "b": {"type": "box"}"#,
        "up",
    );
    write(
        d,
        "main.json",
        r#""om": {"type": "object_merge", "params": {"file": "$HIP/parts.json", "objects": "up /b", "translate": [10, 0, 0]}}"#,
        "om",
    );
    let cache = Cache::new(64 << 20);
    let g = cook_file(d, "main.json", &cache).unwrap();
    let g = g.as_geometry().unwrap();
    assert_eq!(g.num_prims(), 1 + 6);
    // Frame 3 in the other network, then this node's transform.
    assert_eq!(g.positions()[0].to_array(), [10.0, 3.0, 0.0]);
    // A file the other network reads changes: the merge recooks, though
    // nothing of this network changed.
    std::fs::write(d.join("tri.obj"), "v 0 0 5\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let g = cook_file(d, "main.json", &cache).unwrap();
    assert_eq!(
        g.as_geometry().unwrap().positions()[0].to_array(),
        [10.0, 3.0, 5.0]
    );
    // And so does an edit of the other network itself.
    write(
        d,
        "parts.json",
        r#""up": {"type": "box", "params": {"size": [2, 2, 2]}}, "b": {"type": "box"}"#,
        "up",
    );
    let g = cook_file(d, "main.json", &cache).unwrap();
    assert_eq!(g.as_geometry().unwrap().num_prims(), 12);
}

#[test]
fn refuses_files_that_reach_themselves_and_names_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cache = Cache::disabled();
    // Directly, and through a second file.
    write(
        d,
        "self.json",
        r#""om": {"type": "object_merge", "params": {"file": "$HIP/self.json", "objects": "om"}}"#,
        "om",
    );
    let e = cook_file(d, "self.json", &cache).unwrap_err();
    assert!(
        e.contains("may not merge from itself") && e.contains("\"file\""),
        "{e}"
    );
    write(
        d,
        "a.json",
        r#""om": {"type": "object_merge", "params": {"file": "$HIP/b.json", "objects": "om"}}"#,
        "om",
    );
    write(
        d,
        "b.json",
        r#""om": {"type": "object_merge", "params": {"file": "$HIP/a.json", "objects": "om"}}"#,
        "om",
    );
    let e = cook_file(d, "a.json", &cache).unwrap_err();
    assert!(
        e.contains("may not merge from itself") && e.contains("b.json"),
        "{e}"
    );
    // A node the other file lacks, a file that is not there, one that does
    // not load, and no node named.
    write(d, "one.json", r#""b": {"type": "box"}"#, "b");
    write(
        d,
        "m.json",
        r#""om": {"type": "object_merge", "params": {"file": "$HIP/one.json", "objects": "nope"}}"#,
        "om",
    );
    let e = cook_file(d, "m.json", &cache).unwrap_err();
    assert!(
        e.contains("one.json") && e.contains("/nope") && e.contains("no such node"),
        "{e}"
    );
    write(
        d,
        "m.json",
        r#""om": {"type": "object_merge", "params": {"file": "$HIP/missing.json", "objects": "b"}}"#,
        "om",
    );
    let e = cook_file(d, "m.json", &cache).unwrap_err();
    assert!(e.contains("missing.json"), "{e}");
    // A broken node of the other file fails only the merges that read it.
    let bad = super::net(r#""b": {"type": "boxx"}, "ok": {"type": "box"}"#, "b");
    std::fs::write(d.join("bad.json"), bad).unwrap();
    let merge = |file: &str, objects: &str| {
        let text = format!(
            r#""om": {{"type": "object_merge", "params": {{"file": "$HIP/{file}", "objects": "{objects}"}}}}"#
        );
        write(d, "m.json", &text, "om");
        cook_file(d, "m.json", &Cache::disabled())
    };
    let ok = merge("bad.json", "ok").unwrap();
    assert_eq!(ok.as_geometry().unwrap().num_points(), 8);
    let e = merge("bad.json", "b").unwrap_err();
    assert!(
        e.contains("bad.json") && e.contains("/b") && e.contains("boxx"),
        "{e}"
    );
    std::fs::write(d.join("notjson.json"), "{").unwrap();
    let e = merge("notjson.json", "b").unwrap_err();
    assert!(
        e.contains("notjson.json") && e.contains("does not load"),
        "{e}"
    );
    // Paths above the other network's top, and patterns, are refused as such.
    for (objects, says) in [
        ("../ok", "goes above the network's top level"),
        ("b*", "exact paths"),
    ] {
        let e = merge("bad.json", objects).unwrap_err();
        assert!(e.contains(says), "{objects}: {e}");
    }
    write(
        d,
        "m.json",
        r#""om": {"type": "object_merge", "params": {"file": "$HIP/one.json"}}"#,
        "om",
    );
    let e = cook_file(d, "m.json", &cache).unwrap_err();
    assert!(e.contains("names no node"), "{e}");
}

/// `geode check` sees, without cooking, what no cook of the merge could
/// get past: a missing file, a node the other file lacks or has broken.
#[test]
fn check_reads_the_other_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(
        d,
        "parts.json",
        r#""b": {"type": "box"}, "typo": {"type": "boxx"}"#,
        "b",
    );
    let problems = |objects: &str, file: &str| {
        let text = super::net(
            &format!(
                r#""om": {{"type": "object_merge", "params": {{"file": "$HIP/{file}", "objects": "{objects}"}}}}"#
            ),
            "om",
        );
        let path = d.join("m.json");
        std::fs::write(&path, &text).unwrap();
        let net = geode_graph::load_str(&text, &geode_nodes::registry()).unwrap();
        net.check(1.0, &CookEnv::for_network(&path))
            .iter()
            .map(|e| e.to_string())
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(problems("b", "parts.json"), "");
    let e = problems("nosuch", "parts.json");
    assert!(e.contains("/nosuch: no such node"), "{e}");
    assert!(problems("typo", "parts.json").contains("boxx"));
    assert!(problems("b", "missing.json").contains("missing.json"));
}
