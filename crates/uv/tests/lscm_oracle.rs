//! geode's LSCM against libigl's (`igl.lscm`, PyPI libigl, through
//! tools/.venv or GEODE_PYTHON; the snippet is tests/lscm_oracle.py) on a
//! hemisphere, with the same two pins at the same uv: every vertex's uv
//! must agree within 1e-4 of the island's size. Without Python and igl
//! the test fails, unless the run skips oracles (GEODE_SKIP_ORACLES=1):
//! then it says it is skipping.

mod common;

use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};

use common::meshes::hemisphere_arrays;
use geode_geo::glam::Vec3;
use geode_uv::{choose_pins, lscm, Pin, SolverOptions};

/// True when a missing oracle must fail the test.
fn oracle_required() -> bool {
    std::env::var_os("GEODE_SKIP_ORACLES").is_none_or(|v| v != "1")
}

/// GEODE_PYTHON, else the workspace's tools/.venv.
fn python() -> String {
    std::env::var("GEODE_PYTHON").unwrap_or_else(|_| {
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../tools/.venv/bin/python").to_string()
    })
}

/// Says it is skipping and why, or fails when the oracle is required.
fn skip(why: &str) {
    assert!(
        !oracle_required(),
        "the libigl oracle is required here: {why}"
    );
    println!("skipping: lscm_matches_libigl: {why}");
    eprintln!("skipping: lscm_matches_libigl: {why}");
}

/// libigl's LSCM uv of the mesh with the pins, or why there is none.
fn igl_lscm(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    pins: &[Pin],
) -> Result<Vec<[f64; 2]>, String> {
    let python = python();
    if std::env::var_os("GEODE_PYTHON").is_none() && !Path::new(&python).exists() {
        return Err(format!(
            "{python} does not exist (run tools/test.sh, or pip install libigl)"
        ));
    }
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/lscm_oracle.py");
    let mut input = format!("{} {} {}\n", positions.len(), triangles.len(), pins.len());
    for p in positions {
        input += &format!("{:.9e} {:.9e} {:.9e}\n", p.x, p.y, p.z);
    }
    for t in triangles {
        input += &format!("{} {} {}\n", t[0], t[1], t[2]);
    }
    for pin in pins {
        input += &format!("{} {:.17e} {:.17e}\n", pin.vertex, pin.uv[0], pin.uv[1]);
    }
    let mut child = Command::new(&python)
        .arg(script)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("{python} could not run: {e}"))?;
    // A Python without numpy or igl exits before reading: its message
    // says more than the broken pipe.
    let written = child
        .stdin
        .take()
        .ok_or("no stdin")?
        .write_all(input.as_bytes());
    let out = child.wait_with_output().map_err(|e| e.to_string())?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    if out.status.code() == Some(3) {
        return Err(format!("{python}: {}", stderr.trim()));
    }
    written.map_err(|e| format!("writing to {python}: {e}"))?;
    assert!(out.status.success(), "the oracle failed:\n{stderr}");
    let uv: Vec<[f64; 2]> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|line| {
            let mut it = line
                .split_whitespace()
                .map(|x| x.parse::<f64>().expect("a number"));
            [it.next().expect("u"), it.next().expect("v")]
        })
        .collect();
    assert_eq!(
        uv.len(),
        positions.len(),
        "one uv per vertex from the oracle"
    );
    Ok(uv)
}

#[test]
fn lscm_matches_libigl() {
    let (positions, triangles) = hemisphere_arrays(24);
    let pins = choose_pins(&positions, &triangles).expect("a boundary");
    let ours = lscm(
        &positions,
        &triangles,
        &pins,
        &SolverOptions::default(),
        &|| false,
    )
    .expect("solved");
    assert!(ours.converged);
    let theirs = match igl_lscm(&positions, &triangles, &pins) {
        Ok(uv) => uv,
        Err(why) => return skip(&why),
    };
    let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
    for uv in &ours.uv {
        for k in 0..2 {
            lo[k] = lo[k].min(uv[k]);
            hi[k] = hi[k].max(uv[k]);
        }
    }
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let deviation = ours
        .uv
        .iter()
        .zip(&theirs)
        .map(|(a, b)| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt())
        .fold(0.0, f64::max);
    println!(
        "lscm vs libigl: {} vertices, {} triangles, island size {size:.4}, max deviation {deviation:.3e} ({:.3e} of the size)",
        positions.len(),
        triangles.len(),
        deviation / size
    );
    assert!(
        deviation <= 1e-4 * size,
        "max deviation {deviation} for size {size}"
    );
}
