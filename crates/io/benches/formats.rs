//! Read and write a 10-million-triangle mesh in every format.
//! Run: cargo bench -p geode-io --bench formats

use std::path::Path;
use std::sync::OnceLock;

use divan::counter::{BytesCount, ItemsCount};
use divan::Bencher;
use geode_geo::glam::Vec2;
use geode_geo::{ops, primitives, Geometry};
use geode_io::{Format, NoProgress};

fn main() {
    divan::main();
}

/// 2237 x 2236 quads triangulated: 10.0 million triangles, 5.0 million points.
fn mesh_10m() -> &'static Geometry {
    static G: OnceLock<Geometry> = OnceLock::new();
    G.get_or_init(|| {
        let mut g = primitives::grid(Vec2::splat(100.0), 2237, 2236);
        g.remove_attrib(geode_geo::AttribClass::Point, "uv")
            .unwrap();
        for p in g.positions_mut() {
            p.y = (p.x * 0.3).sin() * (p.z * 0.2).cos();
        }
        ops::triangulate(&g, None)
    })
}

fn encoded(f: Format) -> &'static [u8] {
    static E: OnceLock<Vec<(Format, Vec<u8>)>> = OnceLock::new();
    let all = E.get_or_init(|| {
        READ.into_iter()
            .map(|f| {
                (
                    f,
                    geode_io::write_bytes(mesh_10m(), f, Path::new("bench"), &NoProgress).unwrap(),
                )
            })
            .collect()
    });
    &all.iter().find(|(x, _)| *x == f).unwrap().1
}

const WRITE: [Format; 7] = [
    Format::Obj,
    Format::Stl,
    Format::Ply,
    Format::Glb,
    Format::Usda,
    Format::Geo,
    Format::Bgeo,
];
const READ: [Format; 6] = [
    Format::Obj,
    Format::Stl,
    Format::Ply,
    Format::Glb,
    Format::Geo,
    Format::Bgeo,
];

#[divan::bench(args = WRITE, sample_count = 3, sample_size = 1)]
fn write_10m_triangles(bencher: Bencher, f: Format) {
    let g = mesh_10m();
    bencher
        .counter(ItemsCount::new(g.num_prims()))
        .bench(|| geode_io::write_bytes(g, f, Path::new("bench"), &NoProgress).unwrap());
}

#[divan::bench(args = READ, sample_count = 3, sample_size = 1)]
fn read_10m_triangles(bencher: Bencher, f: Format) {
    let bytes = encoded(f);
    bencher
        .counter(BytesCount::new(bytes.len()))
        .bench(|| geode_io::read_bytes(bytes, f, Path::new("bench"), &NoProgress).unwrap());
}

/// Through the file system, atomically (temporary file, fsync, rename).
#[divan::bench(sample_count = 3, sample_size = 1)]
fn write_file_atomic_stl(bencher: Bencher) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.stl");
    bencher.bench(|| geode_io::write(mesh_10m(), &path, &NoProgress).unwrap());
}

/// A million packed copies of a 10k-quad sphere on a 1000 x 1000 grid,
/// turned and scaled: GLB writes them with `EXT_mesh_gpu_instancing`.
#[divan::bench(sample_count = 3, sample_size = 1)]
fn write_glb_million_instances(bencher: Bencher) {
    use geode_geo::glam::{Mat4, Quat, Vec3};
    let ball = std::sync::Arc::new(primitives::uv_sphere(0.03, 100, 100));
    let mut g = Geometry::new();
    g.add_packed_with(&ball, 1_000_000, |i| {
        let (x, z) = ((i % 1000) as f32 * 0.1, (i / 1000) as f32 * 0.1);
        Mat4::from_scale_rotation_translation(
            Vec3::splat(0.5 + (i % 7) as f32 * 0.25),
            Quat::from_rotation_y(i as f32 * 0.01),
            Vec3::new(x, 0.0, z),
        )
    })
    .unwrap();
    bencher
        .counter(ItemsCount::new(1_000_000usize))
        .bench(|| geode_io::write_bytes(&g, Format::Glb, Path::new("bench"), &NoProgress).unwrap());
}
