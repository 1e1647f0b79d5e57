//! Times geode's remesh and pymeshlab's isotropic explicit remeshing
//! (single-threaded; PyPI, through tools/.venv or GEODE_PYTHON) on the
//! same million-triangle mesh, ten iterations to the length that gives a
//! million back, best of two each: `cargo run --release -p geode-model
//! --example remesh_vs_pymeshlab -- box|sphere [geode-only]`. The box is a
//! million right triangles with twelve sharp edges; the sphere a
//! triangulated UV sphere whose pole bands are slivers a hundred times
//! shorter than the target. geode's time is from its geometry, as a cook
//! is, with the allocator the geode binary uses; pymeshlab's is the
//! filter alone on a mesh it already holds.

use std::time::Instant;

use geode_model::remesh::{remesh, RemeshOptions, Sizing};

mod common;
#[path = "../tests/common/meshes.rs"]
mod meshes;
use meshes::{equilateral_length, million_triangles};

#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

const SCRIPT: &str = r#"
import pymeshlab as ml
v, f = load(sys.argv[1])
v, f = v.astype(np.float64), f.astype(np.int32)
length = float(sys.argv[2])
best = None
for _ in range(2):
    ms = ml.MeshSet()
    ms.add_mesh(ml.Mesh(vertex_matrix=v, face_matrix=f))
    t = time.perf_counter()
    ms.meshing_isotropic_explicit_remeshing(iterations=10, targetlen=ml.PureValue(length), featuredeg=30.0)
    dt = time.perf_counter() - t
    best = dt if best is None else min(best, dt)
print(f"pymeshlab: {best * 1000:.0f} ms ({ms.current_mesh().face_number()} triangles)")
"#;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let shape = args.get(1).map_or("box", |s| s.as_str());
    let (g, area) = million_triangles(shape);
    let length = equilateral_length(area, 1e6);
    let opts = RemeshOptions {
        sizing: Sizing::Uniform { length },
        relative: false,
        ..RemeshOptions::default()
    };
    println!(
        "{shape} of {} triangles, target length {length:.5}",
        g.num_prims()
    );
    let mut best = f64::MAX;
    let mut out = 0;
    for _ in 0..2 {
        let t = Instant::now();
        out = remesh(&g, &opts, &|| false).unwrap().num_prims();
        best = best.min(t.elapsed().as_secs_f64());
    }
    println!("geode: {:.0} ms ({out} triangles)", best * 1000.0);
    if args.get(2).map(String::as_str) != Some("geode-only") {
        common::run_reference("pymeshlab", SCRIPT, &[&g], &[length.to_string()]);
    }
}
