//! What the timing examples share: meshes handed to a Python reference
//! (tools/.venv or GEODE_PYTHON) as raw arrays, and that reference's run.

use std::path::Path;

use geode_geo::Geometry;

/// Writes `g`'s positions and its polygons fanned into triangles as raw
/// little-endian arrays `stem.v` (f32 x 3) and `stem.f` (u32 x 3).
pub fn write_raw(g: &Geometry, stem: &Path) {
    let v: Vec<u8> = g
        .positions()
        .iter()
        .flat_map(|p| p.to_array())
        .flat_map(f32::to_le_bytes)
        .collect();
    let f: Vec<u8> = (0..g.num_prims())
        .flat_map(|k| {
            let pts = g.prim_points(k);
            (1..pts.len().saturating_sub(1)).flat_map(move |j| [pts[0], pts[j], pts[j + 1]])
        })
        .flat_map(u32::to_le_bytes)
        .collect();
    std::fs::write(stem.with_extension("v"), v).unwrap();
    std::fs::write(stem.with_extension("f"), f).unwrap();
}

/// What every reference script starts with: `load(stem)` gives a mesh
/// written by `write_raw` back as numpy arrays (positions as f32 x 3,
/// triangles as u32 x 3).
const PRELUDE: &str = r#"
import sys, time, numpy as np
def load(stem):
    v = np.fromfile(stem + ".v", dtype="<f4").reshape(-1, 3)
    f = np.fromfile(stem + ".f", dtype="<u4").reshape(-1, 3)
    return v, f
"#;

/// Runs `script` (after [`PRELUDE`]) with the stems of `meshes` (written
/// as by `write_raw`) and then `args` as its arguments; says how to
/// install the reference (`package`) when it cannot run.
pub fn run_reference(package: &str, script: &str, meshes: &[&Geometry], args: &[String]) {
    let dir = std::env::temp_dir().join(format!("geode-{package}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let stems: Vec<_> = (0..meshes.len())
        .map(|i| dir.join(format!("m{i}")))
        .collect();
    for (g, stem) in meshes.iter().zip(&stems) {
        write_raw(g, stem);
    }
    let python = std::env::var("GEODE_PYTHON").unwrap_or_else(|_| {
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../tools/.venv/bin/python").to_string()
    });
    let status = std::process::Command::new(python)
        .args(["-c", &format!("{PRELUDE}{script}")])
        .args(&stems)
        .args(args)
        .status();
    let _ = std::fs::remove_dir_all(&dir);
    match status {
        Ok(s) if s.success() => {}
        other => eprintln!("{package} did not run ({other:?}): install it with bash tools/test.sh"),
    }
}
