//! The VDB nodes against OpenVDB (Debian's pyopenvdb, tools/vdb_check.py):
//! a sphere written by `frep_write` holds the sphere's distance on every
//! voxel OpenVDB reads; OpenVDB's own sphere read by `frep_file` meshes
//! back to the sphere and writes back voxel for voxel; Blender imports
//! the written file as a volume; `frep_volume` keeps
//! a field's surface; bad files and names are errors naming them.

mod common;

use std::process::Command;

use common::*;
use geode_geo::volume::VolumeClass;
use geode_io::vdb::read_vdb;

fn system_python(args: &[&str]) -> Option<String> {
    let out = Command::new(
        std::env::var("GEODE_SYSTEM_PYTHON").unwrap_or_else(|_| "/usr/bin/python3".into()),
    )
    .arg(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tools/vdb_check.py"
    ))
    .args(args)
    .output();
    let required = std::env::var_os("GEODE_SKIP_ORACLES").is_none_or(|v| v != "1");
    match out {
        Ok(o) if o.status.success() => Some(String::from_utf8_lossy(&o.stdout).into()),
        Ok(o) => {
            let text = String::from_utf8_lossy(&o.stderr).to_string();
            assert!(
                !required && text.contains("ModuleNotFoundError"),
                "pyopenvdb failed:\n{text}"
            );
            eprintln!("skipping: pyopenvdb (Debian's python3-openvdb) is not installed");
            None
        }
        Err(e) => {
            assert!(!required, "python3 could not run: {e}");
            eprintln!("skipping: python3 could not run: {e}");
            None
        }
    }
}

fn read_volume(path: &std::path::Path) -> geode_geo::volume::SparseVolume {
    read_vdb(&std::fs::read(path).unwrap(), 1 << 32, &|| false)
        .unwrap()
        .remove(0)
}

#[test]
fn openvdb_reads_the_sphere_frep_write_wrote_as_its_distance() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("sphere.vdb");
    let (c, r, voxel) = ([0.1, -0.05, 0.2], 0.6, 0.025);
    let nodes = format!(
        r#""s": {{"type": "frep_sphere", "params": {{"center": {c:?}, "radius": {r}}}}},
           "w": {{"type": "frep_write", "inputs": ["s"], "params": {{"file": {file:?}, "min": [-1, -1, -1], "max": [1, 1, 1], "voxel_size": {voxel}, "compress": true}}}}"#
    );
    cook_at(&nodes, "w", 1.0).unwrap();
    let v = read_volume(&file);
    let lo: [i32; 3] =
        std::array::from_fn(|k| v.leaves().iter().map(|l| l.origin[k]).min().unwrap());
    let hi: [i32; 3] =
        std::array::from_fn(|k| v.leaves().iter().map(|l| l.origin[k] + 7).max().unwrap());
    let text = |x: [i32; 3]| format!("{},{},{}", x[0], x[1], x[2]);
    let base = dir.path().join("dump");
    if system_python(&[
        "dump",
        file.to_str().unwrap(),
        "surface",
        &text(lo),
        &text(hi),
        base.to_str().unwrap(),
    ])
    .is_none()
    {
        return;
    }
    let info: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("dump.json")).unwrap()).unwrap();
    assert_eq!(info["name"], "surface");
    assert_eq!(info["class"], "level set");
    assert!((info["voxel_size"][0].as_f64().unwrap() - voxel).abs() < 1e-15);
    let bg = info["background"].as_f64().unwrap();
    assert!((bg - 3.0 * voxel).abs() < 1e-7);
    let values: Vec<f32> = std::fs::read(dir.path().join("dump.bin"))
        .unwrap()
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    // Every voxel OpenVDB holds in the leaves' box: the distance to the
    // sphere (negative inside) within the band, +-background beyond.
    let (mut n, mut band, mut worst) = (0, 0, 0.0f64);
    for x in lo[0]..=hi[0] {
        for y in lo[1]..=hi[1] {
            for z in lo[2]..=hi[2] {
                let p = [x, y, z].map(|i| i as f64 * voxel);
                let d = (0..3).map(|k| (p[k] - c[k]).powi(2)).sum::<f64>().sqrt() - r;
                let theirs = values[n] as f64;
                if d.abs() < bg - 1e-6 {
                    band += 1;
                    worst = worst.max((theirs - d).abs());
                } else if d.abs() > bg + 1e-6 {
                    assert_eq!(
                        theirs,
                        (bg as f32).copysign(d as f32) as f64,
                        "({x}, {y}, {z})"
                    );
                }
                n += 1;
            }
        }
    }
    assert!(worst < 1e-6, "worst {worst}");
    assert_eq!(
        info["active_voxels"].as_u64().unwrap(),
        v.active_voxel_count()
    );
    eprintln!(
        "OpenVDB holds the sphere's distance on {band} band voxels (worst {worst:.1e}) of {n}"
    );
}

#[test]
fn openvdb_s_sphere_reads_meshes_and_writes_back_voxel_for_voxel() {
    let dir = tempfile::tempdir().unwrap();
    let theirs = dir.path().join("theirs.vdb");
    let (c, r, voxel) = ([0.1, -0.25, 0.3], 0.5, 0.05);
    if system_python(&[
        "sphere",
        theirs.to_str().unwrap(),
        "0.5",
        "0.1,-0.25,0.3",
        "0.05",
        "3",
        "0",
    ])
    .is_none()
    {
        return;
    }
    let mesh = format!(
        r#""f": {{"type": "frep_file", "params": {{"file": {theirs:?}}}}},
           "m": {{"type": "polygonise", "inputs": ["f"], "params": {{"min": [-0.6, -0.9, -0.4], "max": [0.8, 0.5, 1.0], "depth": 6}}}}"#
    );
    let g = geo(&mesh, "m");
    let report = g.topology().manifold_report(&g);
    assert_eq!((report.boundary_edges, report.inconsistent_edges), (0, 0));
    let worst = g
        .positions()
        .iter()
        .map(|p| {
            (((p.x as f64 - c[0]).powi(2)
                + (p.y as f64 - c[1]).powi(2)
                + (p.z as f64 - c[2]).powi(2))
            .sqrt()
                - r)
                .abs()
        })
        .fold(0.0, f64::max);
    // Trilinear between voxels of a distance: well inside a tenth of a voxel.
    assert!(worst < 0.1 * voxel, "worst {worst}");
    // Written back at its own voxel size: the same voxels.
    let ours = dir.path().join("ours.vdb");
    let write = format!(
        r#""f": {{"type": "frep_file", "params": {{"file": {theirs:?}}}}},
           "w": {{"type": "frep_write", "inputs": ["f"], "params": {{"file": {ours:?}, "min": [-0.6, -0.9, -0.4], "max": [0.8, 0.5, 1.0], "voxel_size": {voxel}}}}}"#
    );
    cook_at(&write, "w", 1.0).unwrap();
    let (a, b) = (read_volume(&theirs), read_volume(&ours));
    assert_eq!(b.class, VolumeClass::LevelSet);
    let mut compared = 0;
    for l in a.leaves() {
        for n in (0..512).filter(|&n| l.is_active(n)) {
            let i = [
                l.origin[0] + (n >> 6) as i32,
                l.origin[1] + ((n >> 3) & 7) as i32,
                l.origin[2] + (n & 7) as i32,
            ];
            assert_eq!(b.value(i).to_bits(), l.values[n].to_bits(), "voxel {i:?}");
            compared += 1;
        }
    }
    assert_eq!(a.active_voxel_count(), b.active_voxel_count());
    eprintln!("mesh within {worst:.2e} of the sphere; {compared} voxels written back as read");
}

#[test]
fn frep_volume_keeps_a_field_s_surface() {
    let nodes = r#""t": {"type": "frep_torus", "params": {"major_radius": 0.5, "minor_radius": 0.2}},
        "v": {"type": "frep_volume", "inputs": ["t"], "params": {"voxel_size": 0.02}},
        "direct": {"type": "polygonise", "inputs": ["t"], "params": {"depth": 6}},
        "sampled": {"type": "polygonise", "inputs": ["v"], "params": {"depth": 6}}"#;
    let (a, b) = (geo(nodes, "direct"), geo(nodes, "sampled"));
    let volume = |g: &geode_geo::Geometry| geode_geo::ops::signed_volume(g).abs() as f64;
    let (va, vb) = (volume(&a), volume(&b));
    assert!((va - vb).abs() < 0.005 * va, "direct {va}, sampled {vb}");
    let exact = 2.0 * std::f64::consts::PI.powi(2) * 0.5 * 0.2f64.powi(2);
    assert!(
        (vb - exact).abs() < 0.01 * exact,
        "sampled {vb}, exact {exact}"
    );
}

#[test]
fn bad_files_and_names_are_errors_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.vdb");
    let nodes = format!(
        r#""s": {{"type": "frep_sphere"}},
           "w": {{"type": "frep_write", "inputs": ["s"], "params": {{"file": {good:?}, "voxel_size": 0.1}}}}"#
    );
    cook_at(&nodes, "w", 1.0).unwrap();
    let bytes = std::fs::read(&good).unwrap();
    let cut = dir.path().join("cut.vdb");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let read = |file: &std::path::Path, grid: &str| {
        err(
            &format!(
                r#""f": {{"type": "frep_file", "params": {{"file": {file:?}, "grid": {grid:?}}}}}"#
            ),
            "f",
        )
    };
    let e = read(&cut, "");
    assert!(e.contains("cut.vdb") && e.contains("byte "), "{e}");
    let e = read(&good, "density");
    assert!(
        e.contains("no float grid named \"density\"") && e.contains("\"surface\""),
        "{e}"
    );
    let e = err(
        r#""s": {"type": "frep_sphere"}, "w": {"type": "frep_write", "inputs": ["s"], "params": {"file": "out.stl"}}"#,
        "w",
    );
    assert!(e.contains("out.stl: expected a .vdb file"), "{e}");
    let e = err(
        r#""s": {"type": "frep_sphere"}, "w": {"type": "frep_volume", "inputs": ["s"], "params": {"voxel_size": 1e-6, "min": [-100, -100, -100], "max": [100, 100, 100]}}"#,
        "w",
    );
    assert!(e.contains("voxel_size") && e.contains("too many"), "{e}");
}

/// Blender (Debian's 3.4, through tools/blender_vdb.py) imports the file
/// frep_write wrote as a volume: the grid `surface` of floats, its voxels
/// loaded, the voxel transform as the index-to-object matrix and the
/// sphere's band as the object's bounds.
#[test]
fn blender_imports_frep_write_s_file_as_a_volume() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("sphere.vdb");
    let (c, r, voxel) = ([0.2, -0.1, 0.0], 0.5, 0.04);
    let nodes = format!(
        r#""s": {{"type": "frep_sphere", "params": {{"center": {c:?}, "radius": {r}}}}},
           "w": {{"type": "frep_write", "inputs": ["s"], "params": {{"file": {file:?}, "voxel_size": {voxel}}}}}"#
    );
    cook_at(&nodes, "w", 1.0).unwrap();
    let required = std::env::var_os("GEODE_SKIP_ORACLES").is_none_or(|v| v != "1");
    let out = Command::new("blender")
        .args(["-b", "--factory-startup", "--python"])
        .arg(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tools/blender_vdb.py"
        ))
        .arg("--")
        .arg(&file)
        .output();
    let out = match out {
        Ok(o) => o,
        Err(e) => {
            assert!(!required, "blender could not run: {e}");
            eprintln!("skipping: blender (Debian's) is not installed: {e}");
            return;
        }
    };
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text
        .lines()
        .find_map(|l| l.strip_prefix("VDB "))
        .unwrap_or_else(|| {
            panic!(
                "blender printed no report:\n{text}\n{}",
                String::from_utf8_lossy(&out.stderr)
            )
        });
    let report: serde_json::Value = serde_json::from_str(line).unwrap();
    assert_eq!(report["type"], "VOLUME");
    assert_eq!(report["error"], "");
    assert_eq!(report["grids"], serde_json::json!([["surface", "FLOAT"]]));
    assert_eq!(report["loaded"], true);
    for i in 0..3 {
        for j in 0..4 {
            let expected = if i == j { voxel } else { 0.0 };
            let m = report["matrix"][i][j].as_f64().unwrap();
            assert!((m - expected).abs() < 1e-6, "matrix {i} {j}: {m}");
        }
    }
    // The object's bounds: the band's leaves, so the sphere grown by at
    // most the half width and a leaf.
    for k in 0..3 {
        let (lo, hi) = (
            report["min"][k].as_f64().unwrap(),
            report["max"][k].as_f64().unwrap(),
        );
        assert!(
            lo <= c[k] - r - 2.0 * voxel && lo >= c[k] - r - 12.0 * voxel,
            "axis {k}: min {lo}"
        );
        assert!(
            hi >= c[k] + r + 2.0 * voxel && hi <= c[k] + r + 12.0 * voxel,
            "axis {k}: max {hi}"
        );
    }
}

/// OpenVDB's fog volume (a box of density 1 filled by `FloatGrid.fill`,
/// kept as a fuzz seed) reads with its surface at the isovalue: halfway
/// between the last voxel of density and the first without, a box of
/// 128 voxels a side; the warning says the values are not distances.
#[test]
fn a_fog_volume_s_surface_lies_at_the_isovalue() {
    let file = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fuzz/seeds/read_vdb/openvdb_fog_and_vectors.vdb"
    );
    let nodes = format!(
        r#""f": {{"type": "frep_file", "params": {{"file": {file:?}, "grid": "density", "iso": 0.5}}}},
           "m": {{"type": "polygonise", "inputs": ["f"], "params": {{"min": [190, -10, -10], "max": [340, 140, 140], "depth": 7}}}}"#
    );
    let g = geo(&nodes, "m");
    let volume = geode_geo::ops::signed_volume(&g).abs() as f64;
    let b = geode_geo::ops::bounds(&g).unwrap();
    assert!(
        (b.min.x - 199.5).abs() < 0.6 && (b.max.x - 327.5).abs() < 0.6,
        "{b:?}"
    );
    assert!(
        (volume / 128f64.powi(3) - 1.0).abs() < 0.02,
        "volume {volume}"
    );
    let w = warnings(&nodes, "/f");
    assert!(
        w.iter()
            .any(|w| w.contains("not a level set") && w.contains("isovalue 0.5")),
        "{w:?}"
    );
}

/// Voxels that are not numbers, a grid without active voxels, a box
/// narrower than two voxels and a band wider than its level set's: each
/// warned of.
#[test]
fn unusual_volumes_are_warned_of() {
    use geode_geo::volume::{Leaf, SparseVolume, VoxelTransform};
    let dir = tempfile::tempdir().unwrap();
    let mut values = Box::new([0.5f32; 512]);
    values[3] = f32::NAN;
    values[9] = f32::NEG_INFINITY;
    let leaf = Leaf {
        origin: [0; 3],
        active: [0; 8],
        values,
    };
    let v = SparseVolume::new(
        "odd",
        VolumeClass::LevelSet,
        VoxelTransform::uniform(0.1, [0.0; 3]),
        0.3,
        vec![leaf],
        vec![],
    )
    .unwrap();
    let odd = dir.path().join("odd.vdb");
    std::fs::write(
        &odd,
        geode_io::vdb::write_vdb(&[&v], geode_io::vdb::VdbCompression::None),
    )
    .unwrap();
    let w = warnings(
        &format!(r#""f": {{"type": "frep_file", "params": {{"file": {odd:?}}}}}"#),
        "/f",
    );
    assert!(
        w.iter()
            .any(|w| w.contains("2 voxels or tiles that are NaN or infinite")),
        "{w:?}"
    );
    assert!(w.iter().any(|w| w.contains("no active voxels")), "{w:?}");
    let w = warnings(
        r#""s": {"type": "frep_sphere"}, "v": {"type": "frep_volume", "inputs": ["s"], "params": {"voxel_size": 5}}"#,
        "/v",
    );
    assert!(
        w.iter().any(|w| w.contains("fewer than two voxels")),
        "{w:?}"
    );
    // A level set of half width 3 sampled again with 6.
    let narrow = dir.path().join("narrow.vdb");
    let nodes = format!(
        r#""s": {{"type": "frep_sphere"}},
           "w": {{"type": "frep_write", "inputs": ["s"], "params": {{"file": {narrow:?}, "voxel_size": 0.1}}}},
           "f": {{"type": "frep_file", "params": {{"file": {narrow:?}}}}},
           "v": {{"type": "frep_volume", "inputs": ["f"], "params": {{"voxel_size": 0.1, "half_width": 6}}}}"#
    );
    cook_at(&nodes, "w", 1.0).unwrap();
    let w = warnings(&nodes, "/v");
    assert!(
        w.iter().any(|w| w.contains("holds distances only within")),
        "{w:?}"
    );
    // An offset past the band (0.3), and one within it.
    let offset = |d: f64| {
        warnings(
            &format!(
                r#""f": {{"type": "frep_file", "params": {{"file": {narrow:?}}}}},
                   "o": {{"type": "frep_offset", "inputs": ["f"], "params": {{"distance": {d}}}}}"#
            ),
            "/o",
        )
    };
    assert!(offset(0.5)
        .iter()
        .any(|w| w.contains("reaches past the band")));
    assert!(offset(-0.2).is_empty());
}
