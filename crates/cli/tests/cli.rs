//! The `geode` command end to end: info, convert, errors and exit codes.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn geode(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_geode"))
        .args(args)
        .current_dir(repo_root())
        .output()
        .unwrap()
}

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn text(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr)
}

#[test]
fn info_reports_counts_attributes_and_hash() {
    let o = geode(&["info", "examples/assets/creased_box.obj"]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    for needle in [
        "points:      8",
        "6 polygons",
        "vertex     creaseweight",
        "topology:    closed manifold",
        "content hash: ",
    ] {
        assert!(t.contains(needle), "missing `{needle}` in\n{t}");
    }
    let o = geode(&["info", "--json", "examples/assets/creased_box.obj"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["points"], 8);
    assert_eq!(v["content_hash"].as_str().unwrap().len(), 32);
}

/// A `.vdb` file's grids: OpenVDB's fog volume beside a vector grid (a fuzz
/// seed), its voxel count as OpenVDB's `activeVoxelCount` gives it.
#[test]
fn info_reports_a_vdb_file_s_grids() {
    let file = "fuzz/seeds/read_vdb/openvdb_fog_and_vectors.vdb";
    let o = geode(&["info", file]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    for needle in [
        "grids:       1 float",
        "grid \"density\":",
        "class:       fog volume",
        "active:      2097159 voxels",
    ] {
        assert!(t.contains(needle), "missing `{needle}` in\n{t}");
    }
    let o = geode(&["info", "--json", file]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["grids"][0]["active_voxels"], 2_097_159);
    assert_eq!(
        v["grids"][0]["bounds"]["index_max"],
        serde_json::json!([327, 127, 127])
    );
    let bad = tempfile::tempdir().unwrap();
    let cut = bad.path().join("cut.vdb");
    std::fs::write(&cut, &std::fs::read(repo_root().join(file)).unwrap()[..500]).unwrap();
    let o = geode(&["info", cut.to_str().unwrap()]);
    assert!(
        !o.status.success() && text(&o).contains("cut.vdb: byte "),
        "{}",
        text(&o)
    );
}

#[test]
fn convert_round_trips_every_writable_format() {
    let dir = tempfile::tempdir().unwrap();
    let reference = geode(&["info", "--json", "examples/assets/creased_box.obj"]);
    let reference: serde_json::Value = serde_json::from_slice(&reference.stdout).unwrap();
    for ext in ["obj", "ply", "glb", "stl"] {
        let out = dir.path().join(format!("box.{ext}"));
        let o = geode(&[
            "convert",
            "examples/assets/creased_box.obj",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", text(&o));
        let back = geode(&["info", "--json", out.to_str().unwrap()]);
        let back: serde_json::Value = serde_json::from_slice(&back.stdout).unwrap();
        assert_eq!(back["bounds"], reference["bounds"], "{ext}");
        assert_eq!(back["boundary_edges"], 0, "{ext} stays closed");
    }
    let out = dir.path().join("box.usda");
    assert!(geode(&[
        "convert",
        "examples/assets/creased_box.obj",
        out.to_str().unwrap()
    ])
    .status
    .success());
    assert!(std::fs::read_to_string(out)
        .unwrap()
        .starts_with("#usda 1.0"));
}

#[test]
fn errors_name_the_file_and_exit_codes_distinguish() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.obj");
    std::fs::write(&bad, "v 0 0 0\nf 1 2 3\n").unwrap();
    let o = geode(&["info", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(4));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr).trim(),
        format!(
            "error: {}: line 2: vertex index 2 out of range (1 vertexs defined so far)",
            bad.display()
        )
    );
    let o = geode(&["info", "missing.obj"]);
    assert_eq!(o.status.code(), Some(5));
    assert!(
        text(&o).contains("missing.obj: No such file or directory"),
        "{}",
        text(&o)
    );
    // A failed conversion leaves no output behind.
    let out = dir.path().join("out.glb");
    let o = geode(&["convert", bad.to_str().unwrap(), out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(4));
    assert!(!out.exists());
    assert_eq!(geode(&["frobnicate"]).status.code(), Some(2));
    let v = geode(&["--version"]);
    assert!(text(&v).starts_with("geode "), "{}", text(&v));
}

/// A device behind a geometry or network name is refused unread (it would
/// never end), as is a file larger than the memory budget.
#[test]
fn only_regular_files_within_the_budget_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let zero_obj = dir.path().join("zero.obj");
    let zero_json = dir.path().join("zero.json");
    std::os::unix::fs::symlink("/dev/zero", &zero_obj).unwrap();
    std::os::unix::fs::symlink("/dev/zero", &zero_json).unwrap();
    let t = std::time::Instant::now();
    let o = geode(&["info", zero_obj.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr).trim(),
        format!(
            "error: {}: not a regular file (a character device); only regular files are read",
            zero_obj.display()
        )
    );
    let out = dir.path().join("out.obj");
    let o = geode(&[
        "cook",
        zero_json.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o).contains(&format!(
            "cannot read the network: {}: not a regular file (a character device)",
            zero_json.display()
        )),
        "{}",
        text(&o)
    );
    // A glTF whose buffer is a FIFO: opening it would wait for a writer.
    let fifo = dir.path().join("fifo.bin");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let gltf = dir.path().join("fifo.gltf");
    std::fs::write(
        &gltf,
        r#"{"asset": {"version": "2.0"}, "buffers": [{"uri": "fifo.bin", "byteLength": 36}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                           "min": [0, 0, 0], "max": [1, 1, 0]}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
            "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}"#,
    )
    .unwrap();
    let o = geode(&["info", gltf.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(4));
    assert!(
        text(&o).contains("buffer 0: cannot read") && text(&o).contains("not a regular file"),
        "{}",
        text(&o)
    );
    assert!(t.elapsed() < std::time::Duration::from_secs(10));

    let big = dir.path().join("big.obj");
    std::fs::write(&big, "v 0 0 0\n".repeat(300_000)).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_geode"))
        .args(["info", big.to_str().unwrap()])
        .env("GEODE_MEMORY_MB", "1")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(6));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr).trim(),
        format!(
            "error: {}: the file's 2.4 MB would exceed the memory budget of 1.0 MB (GEODE_MEMORY_MB)",
            big.display()
        )
    );
}

/// `geode nodes | head -0`: standard output is closed before the first
/// line; the command ends quietly instead of panicking on the broken pipe.
#[test]
fn a_closed_pipe_ends_output_quietly() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_geode"))
        .arg("nodes")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{:?} {stderr}", out.status);
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// A closed part as an OpenVDB level set and back (Houdini's VDB from
/// Polygons, then Convert VDB): closed, its box kept within a voxel; a
/// level set OpenVDB itself wrote meshes closed; wrong requests are named.
#[test]
fn convert_takes_meshes_to_level_sets_and_back() {
    let dir = tempfile::tempdir().unwrap();
    let vdb = dir.path().join("plate.vdb");
    let obj = dir.path().join("plate.obj");
    let part = "examples/parts/plate_holes.stl";
    let o = geode(&[
        "convert",
        part,
        vdb.to_str().unwrap(),
        "--voxel-size",
        "1.5",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let info = geode(&["info", "--json", vdb.to_str().unwrap()]);
    let info: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    assert_eq!(info["grids"][0]["name"], "surface");
    assert_eq!(info["grids"][0]["class"], "level set");
    let o = geode(&["convert", vdb.to_str().unwrap(), obj.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    let bounds = |file: &str| {
        let o = geode(&["info", "--json", file]);
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(j["boundary_edges"], 0, "{file} is closed");
        assert_eq!(j["non_manifold_edges"], 0, "{file} is manifold");
        let v = |k: &str| -> Vec<f64> {
            j["bounds"][k]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        };
        (v("min"), v("max"))
    };
    let (a, b) = (bounds(part), bounds(obj.to_str().unwrap()));
    for k in 0..3 {
        assert!(
            (a.0[k] - b.0[k]).abs() < 1.5 && (a.1[k] - b.1[k]).abs() < 1.5,
            "{a:?} {b:?}"
        );
    }
    let sphere = dir.path().join("sphere.obj");
    let o = geode(&[
        "convert",
        "fuzz/seeds/read_vdb/openvdb_sphere.vdb",
        sphere.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    bounds(sphere.to_str().unwrap());
    for (args, says) in [
        (vec![part, "x.vdb", "--voxel-size", "-1"], "--voxel-size -1"),
        (
            vec![
                "fuzz/seeds/read_vdb/openvdb_sphere.vdb",
                "x.obj",
                "--grid",
                "density",
            ],
            "no float grid named \"density\" (it has \"surface\")",
        ),
        (
            vec!["fuzz/seeds/read_vdb/openvdb_sphere.vdb", "x.vdb"],
            "both .vdb files",
        ),
    ] {
        let o = geode(&[&["convert"][..], &args].concat());
        assert!(!o.status.success());
        assert!(text(&o).contains(says), "{}", text(&o));
    }
}

/// Each kind of failure exits with its own status (README: Exit status),
/// and a bad number in a network names its node and parameter.
#[test]
fn each_kind_of_failure_has_its_exit_status() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let write = |name: &str, text: &str| std::fs::write(d.join(name), text).unwrap();
    let status = |args: &[&str]| {
        let o = common::geode_in(d, args, &[]);
        (o.status.code(), common::stderr(&o))
    };
    write(
        "ok.json",
        r#"{"geode": "network", "version": 1, "output": "t", "nodes": {
            "f": {"type": "file", "params": {"file": "$HIP/in.obj"}},
            "t": {"type": "transform", "inputs": ["f"]}}}"#,
    );
    write(
        "range.json",
        r#"{"geode": "network", "version": 1, "nodes": {"box1": {"type": "box", "params": {"size": [1, 1e999, 1]}}}}"#,
    );
    write(
        "unknown.json",
        r#"{"geode": "network", "version": 1, "nodes": {"a": {"type": "no_such_node"}}}"#,
    );

    // 2: the command line.
    assert_eq!(status(&["cook", "ok.json", "--frames", "5-3"]).0, Some(2));
    assert_eq!(
        status(&["cook", "ok.json", "--set", "no-equals"]).0,
        Some(2)
    );
    assert_eq!(
        status(&["cook", "ok.json", "--node", "/nowhere"]).0,
        Some(2)
    );
    assert_eq!(status(&["cook", "--no-such-flag"]).0, Some(2));
    // 3: the network.
    let (code, err) = status(&["cook", "range.json"]);
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains("node /box1, parameter `size`: number out of range"),
        "{err}"
    );
    assert_eq!(status(&["check", "unknown.json"]).0, Some(3));
    // 5: the system refused a file (the network itself, or a node's input).
    let (code, err) = status(&["cook", "missing.json"]);
    assert_eq!(code, Some(5), "{err}");
    // The cause is kept as the error's source and said once.
    assert_eq!(err.matches("No such file or directory").count(), 1, "{err}");
    let (code, err) = status(&["cook", "ok.json", "-o", "out.ply"]);
    assert_eq!(code, Some(5), "{err}");
    // 4: the cook (a file whose content cannot be read as OBJ).
    write("in.obj", "v 1 2 x\nf 1 2 3\n");
    let (code, err) = status(&["cook", "ok.json", "-o", "out.ply"]);
    assert_eq!(code, Some(4), "{err}");
    // 0, and 5 again where the output's folder cannot be made.
    std::fs::copy(
        common::root().join("examples/assets/creased_box.obj"),
        d.join("in.obj"),
    )
    .unwrap();
    assert_eq!(status(&["cook", "ok.json", "-o", "out.ply"]).0, Some(0));
    write("blocker", "a file where a folder would go");
    let (code, err) = status(&["cook", "ok.json", "-o", "blocker/out.ply"]);
    assert_eq!(code, Some(5), "{err}");
}
