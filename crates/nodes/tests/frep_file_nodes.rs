//! The frep_file node on fidget's own models (`../shared/corpus/fidget-models`):
//! 3D programs mesh to closed solids, 2D ones to prisms; errors name the
//! file and line.

mod common;
use common::*;

fn corpus() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus/fidget-models")
}

#[test]
fn every_fidget_model_is_read_and_meshes() {
    let dir = corpus();
    let Ok(entries) = std::fs::read_dir(&dir) else {
        panic!("the fidget models are not at {}", dir.display());
    };
    let mut seen = 0;
    for e in entries {
        let path = e.unwrap().path();
        if path.extension().is_none_or(|x| x != "vm") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let nodes = format!(
            r#""f": {{"type": "frep_file", "params": {{"file": {:?}}}}},
               "m": {{"type": "polygonise", "inputs": ["f"], "params": {{"depth": 5, "min": [-1, -1, -1], "max": [1, 1, 1]}}}}"#,
            path.to_str().unwrap()
        );
        let g = geo(&nodes, "m");
        assert!(
            g.num_prims() > 100,
            "{}: {} triangles",
            path.display(),
            g.num_prims()
        );
        let report = g.topology().manifold_report(&g);
        assert!(
            report.boundary_edges == 0 && report.inconsistent_edges == 0,
            "{} is not closed",
            path.display()
        );
        if !text.contains("var-z") {
            // A 2D program is a prism: the same outline at every height.
            let b = geode_geo::ops::bounds(&g).unwrap();
            assert!(
                b.max.z - b.min.z > 1.9,
                "{}: a prism spans the box",
                path.display()
            );
        }
        seen += 1;
    }
    assert!(seen >= 6, "read {seen} models");
}

#[test]
fn errors_name_the_file_and_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.vm");
    std::fs::write(&bad, "_0 var-x\n_1 frobnicate _0\n").unwrap();
    let e = err(
        &format!(
            r#""f": {{"type": "frep_file", "params": {{"file": {:?}}}}}"#,
            bad.to_str().unwrap()
        ),
        "f",
    );
    assert!(e.contains("bad.vm, line 2:"), "{e}");
    let e = err(
        r#""f": {"type": "frep_file", "params": {"file": "/nonexistent/x.vm"}}"#,
        "f",
    );
    assert!(e.contains("/nonexistent/x.vm"), "{e}");
    let e = err(
        r#""f": {"type": "frep_file", "params": {"file": "model.hf"}}"#,
        "f",
    );
    assert!(e.contains("model.hf: expected a fidget .vm program"), "{e}");
    let e = err(r#""f": {"type": "frep_file"}"#, "f");
    assert!(e.contains("names no file to read"), "{e}");
}
