//! Encoding results for the viewport: a 1M-triangle grid, and the million packed instances.
//! Run: cargo bench -p geode-server --bench viewport

use std::sync::Arc;

use geode_geo::glam::{Mat4, Vec2, Vec3};
use geode_geo::{primitives, Geometry};
use geode_op::Value;
use geode_server::viewport::encode;

fn main() {
    divan::main();
}

#[divan::bench(sample_count = 10)]
fn grid_1m_triangles(bencher: divan::Bencher) {
    // 708 x 708 points: 707^2 quads, 999,698 triangles.
    let g = Value::Geometry(Arc::new(primitives::grid(Vec2::splat(10.0), 708, 708)));
    bencher.bench(|| encode(&g, serde_json::json!({})).unwrap().bytes.len());
}

#[divan::bench(sample_count = 10)]
fn packed_1m_instances(bencher: divan::Bencher) {
    let proto = Arc::new(primitives::uv_sphere(0.03, 24, 12));
    let mut g = Geometry::new();
    for i in 0..1_000_000u32 {
        let pt = g.add_point(Vec3::new(
            (i % 1000) as f32 * 0.1,
            0.0,
            (i / 1000) as f32 * 0.1,
        ));
        g.add_packed(pt, proto.clone(), Mat4::IDENTITY).unwrap();
    }
    let v = Value::Geometry(Arc::new(g));
    bencher.bench(|| encode(&v, serde_json::json!({})).unwrap().bytes.len());
}
