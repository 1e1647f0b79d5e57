//! File-writing nodes are outputs, not cached side effects: they write on
//! every cook, per frame with `$F`, and `$HIP` travels in the cook's
//! environment and so in the key.

use geode_graph::{load_str, Cache, CookOptions, Engine};
use geode_op::{CookEnv, ErrorKind};

fn engine_for<'c>(text: &str, cache: &'c Cache) -> Engine<'c> {
    Engine::new(load_str(text, &geode_nodes::registry()).unwrap(), cache)
}

fn at(frame: f64, hip: &str) -> CookOptions<'static> {
    let mut o = CookOptions::at_frame(frame);
    o.env = CookEnv::default().with_hip(hip);
    o
}

#[test]
fn a_write_node_writes_one_file_per_frame_and_every_time_it_cooks() {
    let dir = tempfile::tempdir().unwrap();
    let hip = dir.path().to_str().unwrap();
    let text = r#"{"geode": "network", "version": 1, "output": "w", "nodes": {
        "b": {"type": "box", "params": {"size": [1, 1, 1]}},
        "w": {"type": "write", "params": {"file": "$HIP/w.$F4.obj"}, "inputs": ["b"]}}}"#;
    let cache = Cache::new(1 << 26);
    let engine = engine_for(text, &cache);
    for f in 1..=3 {
        let r = engine.cook("/w", &at(f as f64, hip)).unwrap();
        // The box is the same every frame: a cache hit after frame 1; the write is not.
        let w = r.events.iter().find(|e| e.path == "/w").unwrap();
        assert!(!w.hit);
        let b = r.events.iter().find(|e| e.path == "/b").unwrap();
        assert_eq!(b.hit, f > 1);
    }
    let mut files: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    assert_eq!(files, ["w.0001.obj", "w.0002.obj", "w.0003.obj"]);
    // Cooking frame 2 again writes it again (the user deleted it meanwhile).
    std::fs::remove_file(dir.path().join("w.0002.obj")).unwrap();
    engine.cook("/w", &at(2.0, hip)).unwrap();
    assert!(dir.path().join("w.0002.obj").exists());
}

/// What a format cannot carry reaches the user as the write node's warning.
#[test]
fn a_write_names_the_attributes_its_format_drops() {
    let dir = tempfile::tempdir().unwrap();
    let hip = dir.path().to_str().unwrap();
    let text = r#"{"geode": "network", "version": 1, "output": "w", "nodes": {
        "l": {"type": "curve_line", "params": {"points": 5}},
        "f": {"type": "polyframe", "inputs": ["l"]},
        "w": {"type": "write", "params": {"file": "$HIP/f.stl"}, "inputs": ["f"]}}}"#;
    let cache = Cache::new(1 << 26);
    let r = engine_for(text, &cache).cook("/w", &at(1.0, hip)).unwrap();
    let w = r.events.iter().find(|e| e.path == "/w").unwrap();
    assert_eq!(
        w.warnings.to_vec(),
        vec![format!(
            "{hip}/f.stl: STL cannot hold point `B` (vector3), point `N` (vector3), point `T` (vector3), point `orient` (quaternion), 1 polylines (STL holds triangles only); not written"
        )]
    );
}

#[test]
fn an_hspline_save_is_written_per_frame_and_its_surface_still_caches_without_one() {
    let dir = tempfile::tempdir().unwrap();
    let hip = dir.path().to_str().unwrap();
    let text = r#"{"geode": "network", "version": 1, "output": "h", "nodes": {
        "h": {"type": "hspline", "params": {"levels": 1, "save": "$HIP/h.$F.hs"}}}}"#;
    let cache = Cache::new(1 << 26);
    let engine = engine_for(text, &cache);
    for f in [1.0, 2.0, 2.0] {
        let r = engine.cook("/h", &at(f, hip)).unwrap();
        assert!(!r.events[0].hit);
    }
    assert!(dir.path().join("h.1.hs").exists());
    assert!(dir.path().join("h.2.hs").exists());
    let text = text.replace("$HIP/h.$F.hs", "");
    let engine = engine_for(&text, &cache);
    engine.cook("/h", &at(1.0, hip)).unwrap();
    assert!(engine.cook("/h", &at(1.0, hip)).unwrap().events[0].hit);
}

#[test]
fn hip_is_a_hidden_input_in_the_key() {
    let a = tempfile::tempdir().unwrap();
    let b = tempfile::tempdir().unwrap();
    std::fs::write(
        a.path().join("m.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(
        b.path().join("m.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\n",
    )
    .unwrap();
    let text = r#"{"geode": "network", "version": 1, "output": "f", "nodes": {
        "f": {"type": "file", "params": {"file": "$HIP/m.obj"}}}}"#;
    let cache = Cache::new(1 << 26);
    let engine = engine_for(text, &cache);
    let ra = engine
        .cook("/f", &at(1.0, a.path().to_str().unwrap()))
        .unwrap();
    let rb = engine
        .cook("/f", &at(1.0, b.path().to_str().unwrap()))
        .unwrap();
    assert!(!rb.events[0].hit, "another $HIP is another key");
    assert_ne!(ra.events[0].key, rb.events[0].key);
    let (ga, gb) = (
        ra.value.as_geometry().unwrap(),
        rb.value.as_geometry().unwrap(),
    );
    assert_eq!((ga.num_points(), gb.num_points()), (3, 4));
}

#[test]
fn a_write_without_a_file_or_to_a_bad_place_is_a_typed_error() {
    let text = r#"{"geode": "network", "version": 1, "output": "w", "nodes": {
        "b": {"type": "box"},
        "w": {"type": "write", "params": {"file": "/proc/version/x/out.obj"}, "inputs": ["b"]}}}"#;
    let cache = Cache::disabled();
    let Err(e) = engine_for(text, &cache).cook("/w", &at(1.0, ".")) else {
        panic!("the write succeeded")
    };
    assert_eq!(e[0].kind, ErrorKind::Io);
    assert_eq!(e[0].param.as_deref(), Some("file"));
    assert!(
        std::error::Error::source(&e[0]).is_some(),
        "keeps the I/O error"
    );
    assert!(
        e[0].to_string()
            .starts_with("/w (parameter `file`): /proc/version/x/out.obj"),
        "{}",
        e[0]
    );
}

#[test]
fn cook_errors_keep_their_kind_and_source() {
    let kind = |nodes: &str| {
        let text =
            format!(r#"{{"geode": "network", "version": 1, "output": "n", "nodes": {{{nodes}}}}}"#);
        let cache = Cache::disabled();
        let Err(e) = engine_for(&text, &cache).cook("/n", &at(1.0, ".")) else {
            panic!("no error")
        };
        (
            e[0].kind,
            e[0].param.clone(),
            std::error::Error::source(&e[0]).is_some(),
            e[0].to_string(),
        )
    };
    // A parameter the node cannot use.
    let (k, param, _, msg) = kind(
        r#""b": {"type": "box"}, "n": {"type": "skin", "inputs": ["b"], "params": {"skeleton": [{"name": "root"}], "bend_joint": "elbow"}}"#,
    );
    assert_eq!(
        (k, param.as_deref()),
        (ErrorKind::Parameter, Some("bend_joint"))
    );
    assert_eq!(msg, "/n (parameter `bend_joint`): no joint named `elbow`");
    // A row of a list parameter is named in full.
    let (k, param, source, msg) = kind(
        r#""n": {"type": "hspline", "params": {"edits": [{"level": 0, "vertex": [1, 1]}, {"level": 4, "vertex": [1, 1], "move": [0, 0.1, 0]}]}}"#,
    );
    assert_eq!(
        (k, param.as_deref(), source),
        (ErrorKind::Kernel, Some("edits[1].move"), true),
        "{msg}"
    );
    // An input whose content cannot be used.
    let (k, _, _, msg) =
        kind(r#""c": {"type": "curve_line"}, "n": {"type": "subdivide", "inputs": ["c"]}"#);
    assert_eq!(k, ErrorKind::Input);
    assert_eq!(
        msg,
        "/n: input 1: primitive 0 is not a polygon; subdivide needs a polygon mesh"
    );
    // A kernel's refusal keeps the kernel's error as its source.
    let (k, _, source, msg) = kind(
        r#""n": {"type": "hspline", "params": {"topology": "cylinder", "symmetric": true, "columns": 7, "edit_move": [0.1, 0, 0], "edit_vertex": [1, 1]}}"#,
    );
    assert_eq!(k, ErrorKind::Parameter, "{msg}");
    assert!(!source);
    let (k, param, source, _) =
        kind(r#""n": {"type": "hspline", "params": {"edit_level": 3, "edit_move": [0.1, 0, 0]}}"#);
    assert_eq!(
        (k, param.as_deref(), source),
        (ErrorKind::Kernel, Some("edit_move"), true)
    );
}

/// The issue that started it: polyframe's `orient`, `T`, `B` (and `N`) and
/// its polyline survive PLY, GLB and Houdini's files, and reach USD as
/// primvars.
#[test]
fn polyframe_attributes_survive_every_writer_that_can_carry_them() {
    let dir = tempfile::tempdir().unwrap();
    let hip = dir.path().to_str().unwrap();
    let cache = Cache::new(1 << 26);
    for ext in ["ply", "glb", "bgeo", "usda"] {
        let text = format!(
            r#"{{"geode": "network", "version": 1, "output": "w", "nodes": {{
            "l": {{"type": "curve_line", "params": {{"points": 9}}}},
            "f": {{"type": "polyframe", "inputs": ["l"]}},
            "w": {{"type": "write", "params": {{"file": "$HIP/f.{ext}"}}, "inputs": ["f"]}}}}}}"#
        );
        let r = engine_for(&text, &cache).cook("/w", &at(1.0, hip)).unwrap();
        let written = r.value.as_geometry().unwrap().clone();
        let path = dir.path().join(format!("f.{ext}"));
        if ext == "usda" {
            let usda = std::fs::read_to_string(&path).unwrap();
            for decl in [
                "quatf[] primvars:orient",
                "vector3f[] primvars:T",
                "vector3f[] primvars:B",
                "normal3f[] normals",
            ] {
                assert!(usda.contains(decl), "{decl} missing from the USD");
            }
            continue;
        }
        let back = geode_io::read(&path, &geode_io::NoProgress).unwrap();
        // glTF draws lines as segments: the curve comes back as its 8 spans.
        let spans = if ext == "glb" { 8 } else { 1 };
        assert_eq!(
            back.prim_kinds(),
            vec![geode_geo::PrimKind::Polyline; spans],
            "{ext}: the polyline"
        );
        for name in ["orient", "T", "B", "N"] {
            let (a, b) = (
                written.attrib(geode_geo::AttribClass::Point, name).unwrap(),
                back.attrib(geode_geo::AttribClass::Point, name)
                    .unwrap_or_else(|| panic!("{ext}: `{name}` lost")),
            );
            assert_eq!(b.data(), a.data(), "{ext}: `{name}`");
        }
    }
}
