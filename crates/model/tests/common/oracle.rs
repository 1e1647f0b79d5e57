//! The Python oracles (trimesh, manifold3d, scipy, numpy, libigl from
//! PyPI, which tools/test.sh installs into tools/.venv and names in
//! GEODE_PYTHON), shared by the kernels' tests: the modelling kernel's
//! `common` includes it, other crates by `#[path]`.
#![allow(dead_code)]

use std::io::Write;
use std::process::{Command, Stdio};

use geode_geo::Geometry;

/// True unless the run was told to skip the outside oracles
/// (GEODE_SKIP_ORACLES=1): a missing oracle then fails the test.
pub fn oracles_required() -> bool {
    std::env::var_os("GEODE_SKIP_ORACLES").is_none_or(|v| v != "1")
}

/// Runs the Python `script` with `input` on its standard input and parses
/// the JSON it prints. None (the test says it skipped) when no Python with
/// the oracles is there and the run does not require them.
pub fn oracle(script: &str, input: &serde_json::Value) -> Option<serde_json::Value> {
    let python = std::env::var("GEODE_PYTHON").unwrap_or_else(|_| {
        let venv = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tools/.venv/bin/python");
        if std::path::Path::new(venv).exists() {
            venv.to_string()
        } else {
            "python3".to_string()
        }
    });
    let child = Command::new(&python)
        .args(["-c", script])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(e) => {
            assert!(!oracles_required(), "{python} could not run: {e}");
            eprintln!("skipping: {python} could not run: {e}");
            return None;
        }
    };
    child
        .stdin
        .take()
        .expect("piped")
        .write_all(input.to_string().as_bytes())
        .expect("oracle reads its input");
    let out = child.wait_with_output().expect("oracle ran");
    let err = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() && err.contains("ModuleNotFoundError") {
        assert!(!oracles_required(), "an oracle is not installed:\n{err}");
        eprintln!("skipping: an oracle is not installed:\n{err}");
        return None;
    }
    assert!(out.status.success(), "oracle failed:\n{err}");
    Some(serde_json::from_slice(&out.stdout).expect("oracle prints JSON"))
}

/// A triangle or polygon mesh as JSON for an oracle: `{"v": [[x,y,z]...],
/// "f": [[i,j,k]...]}` (polygons fanned into triangles).
pub fn mesh_json(g: &Geometry) -> serde_json::Value {
    let v: Vec<[f64; 3]> = g
        .positions()
        .iter()
        .map(|p| p.to_array().map(f64::from))
        .collect();
    let mut f = Vec::new();
    for k in 0..g.num_prims() {
        let p = g.prim_points(k);
        for j in 1..p.len().saturating_sub(1) {
            f.push([p[0], p[j], p[j + 1]]);
        }
    }
    serde_json::json!({ "v": v, "f": f })
}
