//! `.vdb` files against OpenVDB itself (Debian's pyopenvdb, through
//! tools/vdb_check.py): OpenVDB reads every voxel of geode's files as geode
//! holds them, and geode reads OpenVDB's Blosc-compressed files, in floats
//! and in halves, voxel for voxel. Round trips, every tile level,
//! OpenVDB's files kept as fuzz seeds and malformed files are checked
//! without it.

mod common;

use std::process::Command;

use common::*;
use geode_geo::volume::{
    Leaf, SparseVolume, Tile, VolumeClass, VoxelTransform, LEAF_SIDE, LEAF_VOXELS,
};
use geode_io::vdb::{read_vdb, write_vdb, VdbCompression, VdbError};

const BUDGET: u64 = 1 << 32;

fn read(bytes: &[u8]) -> Result<Vec<SparseVolume>, VdbError> {
    read_vdb(bytes, BUDGET, &|| false)
}

/// A narrow-band level set of a sphere (distance negative inside, clamped
/// to the background), leaf-sized tiles of -background filling its inside,
/// and an active tile far away (so every tile level and both signs occur).
fn sphere(centre: [f64; 3], radius: f64, voxel: f64) -> SparseVolume {
    let bg = (3.0 * voxel) as f32;
    let t = VoxelTransform::uniform(voxel, [0.3, -0.2, 0.1]);
    let lo = t.to_index(centre.map(|c| c - radius - 4.0 * voxel));
    let hi = t.to_index(centre.map(|c| c + radius + 4.0 * voxel));
    let block = |v: f64| (v.floor() as i32).div_euclid(LEAF_SIDE);
    let (mut leaves, mut tiles) = (Vec::new(), Vec::new());
    for bx in block(lo[0])..=block(hi[0]) {
        for by in block(lo[1])..=block(hi[1]) {
            for bz in block(lo[2])..=block(hi[2]) {
                let origin = [bx, by, bz].map(|b| b * LEAF_SIDE);
                let mut values = Box::new([0.0f32; LEAF_VOXELS]);
                let mut active = [0u64; 8];
                let mut inside = true;
                for n in 0..LEAF_VOXELS {
                    let i = [
                        origin[0] + (n >> 6) as i32,
                        origin[1] + ((n >> 3) & 7) as i32,
                        origin[2] + (n & 7) as i32,
                    ];
                    let p = t.to_world(i);
                    let d =
                        ((0..3).map(|k| (p[k] - centre[k]).powi(2)).sum::<f64>()).sqrt() - radius;
                    values[n] = (d as f32).clamp(-bg, bg);
                    if d.abs() < bg as f64 {
                        active[n >> 6] |= 1 << (n & 63);
                    }
                    inside &= d < 0.0;
                }
                if active.iter().any(|&w| w != 0) {
                    leaves.push(Leaf {
                        origin,
                        active,
                        values,
                    });
                } else if inside {
                    tiles.push(Tile {
                        origin,
                        log2: 3,
                        value: -bg,
                        active: false,
                    });
                }
            }
        }
    }
    tiles.push(Tile {
        origin: [128 * 40, 0, -128 * 3],
        log2: 7,
        value: 0.5,
        active: true,
    });
    tiles.push(Tile {
        origin: [-4096 * 2, 4096, 0],
        log2: 12,
        value: -bg,
        active: false,
    });
    SparseVolume::new("surface", VolumeClass::LevelSet, t, bg, leaves, tiles).unwrap()
}

#[test]
fn volumes_round_trip_through_vdb_files() {
    let v = sphere([0.0, 0.1, -0.2], 0.5, 0.02);
    assert!(
        v.leaves().iter().any(|l| l.origin[0] < 0) && v.leaves().iter().any(|l| l.origin[0] >= 0)
    );
    let bytes = write_vdb(&[&v], VdbCompression::None);
    let back = read(&bytes).unwrap();
    assert_eq!(back, vec![v.clone()]);
    // Equal volumes, equal bytes; two grids come back in order.
    assert_eq!(write_vdb(&[&back[0]], VdbCompression::None), bytes);
    let mut other = sphere([1.0, 0.0, 0.0], 0.2, 0.05);
    other.name = "second".into();
    other.class = VolumeClass::FogVolume;
    assert_eq!(
        read(&write_vdb(&[&v, &other], VdbCompression::Zip)).unwrap(),
        vec![v, other]
    );
}

#[test]
fn an_empty_volume_round_trips() {
    let v = SparseVolume::new(
        "empty",
        VolumeClass::Unknown,
        VoxelTransform {
            scale: [0.5, 1.0, 2.0],
            translation: [1.0, 2.0, 3.0],
        },
        0.25,
        vec![],
        vec![],
    )
    .unwrap();
    assert_eq!(
        read(&write_vdb(&[&v], VdbCompression::None)).unwrap(),
        vec![v]
    );
}

#[test]
fn malformed_files_are_errors_naming_their_byte() {
    let v = sphere([0.0; 3], 0.3, 0.05);
    let bytes = write_vdb(&[&v], VdbCompression::None);
    for cut in (0..bytes.len()).step_by(97) {
        let e = read(&bytes[..cut]).unwrap_err();
        assert!(matches!(e, VdbError::Malformed { .. }), "{e}");
    }
    let mut rng = 0x2545_f491_4f6c_dd1du64;
    for _ in 0..2000 {
        let mut b = bytes.clone();
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        let at = (rng % b.len() as u64) as usize;
        b[at] ^= 1 << (rng >> 60 & 7);
        let _ = read(&b);
    }
    let e = read(b"not a vdb file at all, not even close").unwrap_err();
    assert!(e.to_string().contains("not an OpenVDB file"), "{e}");
    // The budget is checked before the leaves are held.
    let e = read_vdb(&bytes, 1000, &|| false).unwrap_err();
    assert!(matches!(e, VdbError::TooLarge { .. }), "{e}");
}

/// Inputs that once crashed the reader under the fuzzer stay errors, and
/// the fuzzer's seeds (OpenVDB's files and geode's) read.
#[test]
fn fuzz_regressions_and_seeds() {
    let root = repo_root();
    if let Ok(entries) = std::fs::read_dir(root.join("crates/io/tests/fuzz_regressions/vdb")) {
        for e in entries {
            let _ = read(&std::fs::read(e.unwrap().path()).unwrap());
        }
    }
    let dir = root.join("fuzz/seeds/read_vdb");
    if std::env::var_os("GEODE_WRITE_SEEDS").is_some() {
        let v = sphere([0.0, 0.05, 0.0], 0.3, 0.1);
        for (name, c) in [("raw", VdbCompression::None), ("zip", VdbCompression::Zip)] {
            std::fs::write(
                dir.join(format!("geode_sphere_{name}.vdb")),
                write_vdb(&[&v], c),
            )
            .unwrap();
        }
    }
    let mut seeds = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let path = e.unwrap().path();
        if path.extension().is_some_and(|x| x == "vdb") {
            let v = read(&std::fs::read(&path).unwrap()).unwrap();
            assert!(v[0].active_voxel_count() > 0, "{}", path.display());
            seeds += 1;
        }
    }
    assert!(seeds >= 5);
}

/// OpenVDB's fog volume beside a vector grid: the vector grid is skipped by
/// its recorded end, the fog volume's voxels and its filled box (tiles and
/// leaves where the box is not aligned to them) read.
#[test]
fn other_grids_are_skipped_and_tiles_read() {
    let bytes =
        std::fs::read(repo_root().join("fuzz/seeds/read_vdb/openvdb_fog_and_vectors.vdb")).unwrap();
    let v = read(&bytes).unwrap();
    assert_eq!(v.len(), 1);
    let fog = &v[0];
    assert_eq!(
        (fog.name.as_str(), fog.class, fog.background),
        ("density", VolumeClass::FogVolume, 0.0)
    );
    assert_eq!(fog.active_voxel_count(), 7 + 128 * 128 * 128);
    assert_eq!(fog.value([1, 2, -1]), 1.25);
    assert_eq!(fog.value([-3, -6, 3]), 0.25);
    assert_eq!(fog.value([250, 50, 50]), 1.0);
    assert_eq!(fog.value([327, 127, 127]), 1.0);
    assert_eq!(fog.value([328, 127, 127]), 0.0);
    assert!(fog
        .tiles()
        .iter()
        .any(|t| t.active && t.log2 == 7 || t.log2 == 3));
}

fn system_python() -> Command {
    let mut cmd = Command::new(
        std::env::var("GEODE_SYSTEM_PYTHON").unwrap_or_else(|_| "/usr/bin/python3".into()),
    );
    cmd.arg(repo_root().join("tools/vdb_check.py"));
    cmd
}

/// What pyopenvdb reported of a grid, and its dense values.
struct Dump {
    info: serde_json::Value,
    values: Vec<f32>,
    lo: [i32; 3],
    hi: [i32; 3],
}

impl Dump {
    /// Reads `base.json` and `base.bin`.
    fn load(base: &std::path::Path) -> Dump {
        let with = |ext: &str| format!("{}.{ext}", base.display());
        let info: serde_json::Value =
            serde_json::from_slice(&std::fs::read(with("json")).unwrap()).unwrap();
        let values: Vec<f32> = std::fs::read(with("bin"))
            .unwrap()
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        let corner =
            |k: &str| -> [i32; 3] { std::array::from_fn(|a| info[k][a].as_i64().unwrap() as i32) };
        let (lo, hi) = (corner("lo"), corner("hi"));
        Dump {
            info,
            values,
            lo,
            hi,
        }
    }

    /// Every voxel of the box: OpenVDB's value beside geode's.
    fn compare(&self, v: &SparseVolume) -> usize {
        let mut n = 0;
        let mut checked = 0;
        for x in self.lo[0]..=self.hi[0] {
            for y in self.lo[1]..=self.hi[1] {
                for z in self.lo[2]..=self.hi[2] {
                    let theirs = self.values[n];
                    let ours = v.value([x, y, z]);
                    assert_eq!(
                        ours.to_bits(),
                        theirs.to_bits(),
                        "voxel ({x}, {y}, {z}): geode {ours}, OpenVDB {theirs}"
                    );
                    n += 1;
                    checked += 1;
                }
            }
        }
        assert_eq!(n, self.values.len());
        checked
    }

    fn check_grid(&self, v: &SparseVolume) {
        assert_eq!(self.info["name"], v.name.as_str());
        assert_eq!(
            self.info["background"].as_f64().unwrap() as f32,
            v.background
        );
        assert_eq!(
            self.info["active_voxels"].as_u64().unwrap(),
            v.active_voxel_count()
        );
        for (k, i) in [[0, 0, 0], [1, 2, 3], [-7, 5, 11]].into_iter().enumerate() {
            let w = v.transform.to_world(i);
            for a in 0..3 {
                let theirs = self.info["world"][k][a].as_f64().unwrap();
                assert!(
                    (w[a] - theirs).abs() < 1e-12,
                    "index {i:?}: {w:?} against {theirs}"
                );
            }
        }
        let (lo, hi) = v.active_bounds().unwrap();
        for a in 0..3 {
            assert_eq!(
                self.info["active_bounds"][0][a].as_i64().unwrap() as i32,
                lo[a]
            );
            assert_eq!(
                self.info["active_bounds"][1][a].as_i64().unwrap() as i32,
                hi[a]
            );
        }
    }
}

#[test]
fn openvdb_reads_geode_s_level_set_voxel_for_voxel() {
    let dir = tempfile::tempdir().unwrap();
    let v = sphere([0.0, 0.1, -0.2], 0.5, 0.02);
    // The leaves' box and two voxels around it: the band, the inside
    // tiles and the background (not the far tiles: the box would be huge).
    let lo: [i32; 3] =
        std::array::from_fn(|k| v.leaves().iter().map(|l| l.origin[k]).min().unwrap() - 2);
    let hi: [i32; 3] =
        std::array::from_fn(|k| v.leaves().iter().map(|l| l.origin[k] + 7).max().unwrap() + 2);
    let text = |c: [i32; 3]| {
        c.iter()
            .map(|v| v.to_string())
            .collect::<Vec<_>>()
            .join(",")
    };
    for compression in [VdbCompression::None, VdbCompression::Zip] {
        let path = dir.path().join(format!("sphere{compression:?}.vdb"));
        std::fs::write(&path, write_vdb(&[&v], compression)).unwrap();
        let base = dir.path().join(format!("dump{compression:?}"));
        let mut cmd = system_python();
        cmd.args([
            "dump".as_ref(),
            path.as_os_str(),
            "surface".as_ref(),
            text(lo).as_ref(),
            text(hi).as_ref(),
            base.as_os_str(),
        ]);
        if run_validator(cmd, "pyopenvdb (Debian's python3-openvdb)").is_none() {
            return;
        }
        let dump = Dump::load(&base);
        assert_eq!(dump.info["class"], "level set");
        assert_eq!(dump.info["metadata"]["class"], "level set");
        dump.check_grid(&v);
        let checked = dump.compare(&v);
        eprintln!(
            "OpenVDB read {checked} voxels of geode's sphere ({compression:?}) as geode holds them"
        );
    }
}

#[test]
fn geode_reads_openvdb_s_spheres_in_floats_and_halves() {
    let dir = tempfile::tempdir().unwrap();
    for half in ["0", "1"] {
        let path = dir.path().join(format!("sphere{half}.vdb"));
        let mut cmd = system_python();
        cmd.args([
            "sphere".as_ref(),
            path.as_os_str(),
            "0.5".as_ref(),
            "0.1,-0.25,0.3".as_ref(),
            "0.05".as_ref(),
            "3".as_ref(),
            half.as_ref(),
        ]);
        if run_validator(cmd, "pyopenvdb (Debian's python3-openvdb)").is_none() {
            return;
        }
        let bytes = std::fs::read(&path).unwrap();
        // Debian's OpenVDB is built with Blosc: flags 6 on the grid.
        let v = read(&bytes).unwrap().remove(0);
        assert_eq!(v.class, VolumeClass::LevelSet);
        let dump = Dump::load(&path);
        dump.check_grid(&v);
        let checked = dump.compare(&v);
        eprintln!("geode read {checked} voxels of OpenVDB's sphere (half floats: {half}) as OpenVDB holds them");
        // And the values are the sphere's distances to within a voxel's
        // rounding (halves: their precision).
        for l in v.leaves() {
            for n in (0..LEAF_VOXELS).filter(|&n| l.is_active(n)) {
                let i = [
                    l.origin[0] + (n >> 6) as i32,
                    l.origin[1] + ((n >> 3) & 7) as i32,
                    l.origin[2] + (n & 7) as i32,
                ];
                let p = v.transform.to_world(i);
                let c = [0.1, -0.25, 0.3];
                let d = (0..3).map(|k| (p[k] - c[k]).powi(2)).sum::<f64>().sqrt() - 0.5;
                assert!(
                    (l.values[n] as f64 - d).abs() < 1e-3,
                    "{i:?}: {} against {d}",
                    l.values[n]
                );
            }
        }
    }
}
