//! `.vdb` files of a level-set sphere on a 1024^3 grid (about 30,000
//! leaves, 7 million active voxels): written raw and zlib-compressed, read
//! back.
//! Run: cargo bench -p geode-io --bench vdb

use std::sync::OnceLock;

use divan::counter::BytesCount;
use divan::Bencher;
use geode_geo::volume::{Leaf, SparseVolume, VolumeClass, VoxelTransform, LEAF_VOXELS};
use geode_io::vdb::{read_vdb, write_vdb, VdbCompression};

fn main() {
    divan::main();
}

/// A sphere of radius 450 voxels, distances within 3 voxels of it.
fn sphere() -> &'static SparseVolume {
    static V: OnceLock<SparseVolume> = OnceLock::new();
    V.get_or_init(|| {
        let (r, bg) = (450.0f64, 3.0f32);
        let mut leaves = Vec::new();
        for bx in -58..58 {
            for by in -58..58 {
                for bz in -58..58 {
                    let origin = [bx * 8, by * 8, bz * 8];
                    let centre = origin.map(|o| o as f64 + 3.5);
                    let d = centre.iter().map(|c| c * c).sum::<f64>().sqrt() - r;
                    if d.abs() > 10.0 {
                        continue;
                    }
                    let mut values = Box::new([0.0f32; LEAF_VOXELS]);
                    let mut active = [0u64; 8];
                    for (n, v) in values.iter_mut().enumerate() {
                        let p = [
                            origin[0] + (n >> 6) as i32,
                            origin[1] + ((n >> 3) & 7) as i32,
                            origin[2] + (n & 7) as i32,
                        ];
                        let d = p.iter().map(|&c| (c as f64).powi(2)).sum::<f64>().sqrt() - r;
                        *v = (d as f32).clamp(-bg, bg);
                        if d.abs() < bg as f64 {
                            active[n >> 6] |= 1 << (n & 63);
                        }
                    }
                    leaves.push(Leaf {
                        origin,
                        active,
                        values,
                    });
                }
            }
        }
        let t = VoxelTransform::uniform(1.0 / 1024.0, [0.0; 3]);
        SparseVolume::new("surface", VolumeClass::LevelSet, t, bg, leaves, vec![]).unwrap()
    })
}

#[divan::bench(args = ["raw", "zip"], sample_count = 3, sample_size = 1)]
fn write(bencher: Bencher, compression: &str) {
    let c = if compression == "zip" {
        VdbCompression::Zip
    } else {
        VdbCompression::None
    };
    let v = sphere();
    let size = write_vdb(&[v], c).len();
    bencher
        .counter(BytesCount::new(size))
        .bench(|| write_vdb(&[v], c));
}

#[divan::bench(args = ["raw", "zip"], sample_count = 3, sample_size = 1)]
fn read(bencher: Bencher, compression: &str) {
    let c = if compression == "zip" {
        VdbCompression::Zip
    } else {
        VdbCompression::None
    };
    let bytes = write_vdb(&[sphere()], c);
    bencher
        .counter(BytesCount::new(bytes.len()))
        .bench(|| read_vdb(&bytes, 1 << 34, &|| false).unwrap());
}
