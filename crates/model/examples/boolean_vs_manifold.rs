//! Times geode's boolean and manifold3d's (PyPI, through tools/.venv or
//! GEODE_PYTHON) on the same two 500k-triangle spheres in one run, best of
//! three each: `cargo run --release -p geode-model --example
//! boolean_vs_manifold`. geode's time is from its meshes (as a cook is);
//! manifold3d's is given both on solids it built before and from the
//! meshes.

use std::time::Instant;

use geode_geo::glam::{Mat4, Vec3};
use geode_geo::{ops, primitives};
use geode_model::boolean::{boolean, BooleanOp};

mod common;

const SCRIPT: &str = r#"
import manifold3d as m3
def solid_mesh(stem):
    v, f = load(stem)
    return m3.Mesh(vert_properties=v, tri_verts=f)
ma, mb = solid_mesh(sys.argv[1]), solid_mesh(sys.argv[2])
a, b = m3.Manifold(ma), m3.Manifold(mb)
for name, op in [("union", lambda x, y: x + y), ("subtract", lambda x, y: x - y)]:
    best, whole = None, None
    for _ in range(3):
        t = time.perf_counter(); r = op(a, b); n = r.num_tri(); dt = time.perf_counter() - t
        best = dt if best is None else min(best, dt)
        t = time.perf_counter(); r = op(m3.Manifold(ma), m3.Manifold(mb)); r.num_tri(); dt = time.perf_counter() - t
        whole = dt if whole is None else min(whole, dt)
    print(f"manifold3d {name}: {best * 1000:.0f} ms on built solids, {whole * 1000:.0f} ms from the meshes ({n} triangles, volume {r.volume():.6f})")
"#;

fn main() {
    let rows = (500_000f32 / 4.0).sqrt() as u32;
    let a = primitives::uv_sphere(1.0, 2 * rows, rows);
    let mut b = a.clone();
    ops::transform(&mut b, Mat4::from_translation(Vec3::new(0.5, 0.3, 0.2)));
    println!(
        "two spheres of {} triangles; manifold built {}",
        4 * rows * rows,
        if geode_manifold::parallel() {
            "on TBB"
        } else {
            "serially (no libtbb-dev)"
        }
    );
    for (name, op) in [
        ("union", BooleanOp::Union),
        ("subtract", BooleanOp::Subtract),
    ] {
        let mut best = f64::MAX;
        let mut tris = 0;
        for _ in 0..3 {
            let t = Instant::now();
            let r = boolean(&a, &b, op, &|| false).unwrap();
            best = best.min(t.elapsed().as_secs_f64());
            tris = r.num_prims();
        }
        println!("geode {name}: {:.0} ms ({tris} triangles)", best * 1000.0);
    }
    common::run_reference("manifold3d", SCRIPT, &[&a, &b], &[]);
}
