//! The frep_file node on fidget's own models (`corpus/fidget-models`):
//! 3D programs mesh to closed solids, 2D ones to prisms; errors name the
//! file and line.

mod common;
use common::*;

fn corpus() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../corpus/fidget-models")
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
        r#""f": {"type": "frep_file", "params": {"file": "model.stl"}}"#,
        "f",
    );
    assert!(
        e.contains("model.stl: expected a fidget .vm or a HyperFun .hf program"),
        "{e}"
    );
    let bad = dir.path().join("bad.hf");
    std::fs::write(
        &bad,
        "-- a sphere\nm(x[3], a[1])\n{\n  m = hfSphere(x, c, 1);\n}\n",
    )
    .unwrap();
    let e = err(
        &format!(
            r#""f": {{"type": "frep_file", "params": {{"file": {:?}}}}}"#,
            bad.to_str().unwrap()
        ),
        "f",
    );
    assert!(
        e.contains("bad.hf, line 4, column 19: 'c' is used before it is given a value"),
        "{e}"
    );
    let e = err(r#""f": {"type": "frep_file"}"#, "f");
    assert!(e.contains("names no file to read"), "{e}");
}

/// The die of Paul Murrell's HyperFun talk (NZSA 2022): a block with three
/// spherical dimples, its corners rounded by intersecting a ball. Read from
/// a `.hf` file, it meshes closed and fills the block it was cut from.
#[test]
fn a_published_hyperfun_program_meshes() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("die.hf");
    std::fs::write(
        &path,
        "-- die.hf: a block with three dimples, corners rounded\n\
         my_model(x[3], a[1])\n\
         {\n\
           array d[3];\n\
           array vertex[3];\n\
           d = [5, 5, 5];\n\
           vertex[1] = -d[1];\n\
           vertex[2] = -d[2];\n\
           vertex[3] = -d[3];\n\
           cube = hfBlock(x, vertex, 2*d[1], 2*d[2], 2*d[3]);\n\
           array centre[3];\n\
           r = .8;\n\
           centre = [2, 2, 5];\n\
           threeA = hfSphere(x, centre, r);\n\
           centre = [0, 0, 5];\n\
           threeB = hfSphere(x, centre, r);\n\
           centre = [-2, -2, 5];\n\
           threeC = hfSphere(x, centre, r);\n\
           three = threeA | threeB | threeC;\n\
           centre = [0, 0, 0];\n\
           trim = hfSphere(x, centre, .975*sqrt(2*d[1]*d[1]));\n\
           my_model = cube \\ three \\ ~trim;\n\
         }\n",
    )
    .unwrap();
    let nodes = format!(
        r#""f": {{"type": "frep_file", "params": {{"file": {:?}}}}},
           "m": {{"type": "polygonise", "inputs": ["f"], "params": {{"depth": 6, "min": [-6, -6, -6], "max": [6, 6, 6]}}}}"#,
        path.to_str().unwrap()
    );
    let g = geo(&nodes, "m");
    let report = g.topology().manifold_report(&g);
    assert!(report.is_closed_manifold(), "{report:?}");
    let b = geode_geo::ops::bounds(&g).unwrap();
    for k in 0..3 {
        assert!(
            (b.max[k] - 5.0).abs() < 0.05 && (b.min[k] + 5.0).abs() < 0.05,
            "{b:?}"
        );
    }
    // The rounding ball (radius 6.89) trims the block's corners (at 8.66):
    // the volume lies between the ball's and the block's.
    let v = geode_geo::ops::signed_volume(&g) as f64;
    assert!(v > 800.0 && v < 1000.0, "volume {v}");
}
