//! Times geode's polyreduce and pymeshlab's quadric edge collapse
//! (`meshing_decimation_quadric_edge_collapse`, single-threaded; PyPI,
//! through tools/.venv or GEODE_PYTHON) reducing the same 2M-triangle
//! ridged sphere to 10%, best of two each: `cargo run --release -p
//! geode-model --example reduce_vs_pymeshlab [triangles]`. geode's time is
//! from its geometry (as a cook is), with triangulation and the attribute
//! carry; pymeshlab's is the filter alone on a mesh it already holds.

use std::time::Instant;

use geode_model::reduce::{reduce, Reduce, Target};

mod common;
#[path = "../tests/common/meshes.rs"]
mod meshes;
use meshes::ridged_sphere;

const SCRIPT: &str = r#"
import pymeshlab
v, f = load(sys.argv[1])
v, f = v.astype(np.float64), f.astype(np.int32)
target = int(sys.argv[2])
best = None
for _ in range(2):
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=v, face_matrix=f))
    t = time.perf_counter()
    ms.meshing_decimation_quadric_edge_collapse(targetfacenum=target)
    dt = time.perf_counter() - t
    best = dt if best is None else min(best, dt)
print(f"pymeshlab: {best * 1000:.0f} ms ({ms.current_mesh().face_number()} triangles)")
"#;

fn main() {
    let triangles: u32 = std::env::args()
        .nth(1)
        .map(|a| a.parse().expect("a triangle count"))
        .unwrap_or(2_000_000);
    let g = ridged_sphere(triangles);
    println!("ridged sphere of {} triangles, to 10%", g.num_prims());
    let how = Reduce {
        target: Target::Percent(10.0),
        ..Reduce::default()
    };
    let mut best = f64::MAX;
    let mut out = 0;
    for _ in 0..2 {
        let t = Instant::now();
        let r = reduce(&g, &how, &|| false).unwrap();
        best = best.min(t.elapsed().as_secs_f64());
        out = r.triangles_out;
    }
    println!("geode: {:.0} ms ({out} triangles)", best * 1000.0);
    common::run_reference("pymeshlab", SCRIPT, &[&g], &[out.to_string()]);
}
