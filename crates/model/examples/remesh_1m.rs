//! Times one remesh of a million-triangle box or UV sphere (for perf):
//! `cargo run --release -p geode-model --example remesh_1m -- box|sphere [iterations]`.

use geode_geo::{ops, primitives};
use geode_model::remesh::{remesh, RemeshOptions, Sizing};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let shape = args.get(1).map_or("box", |s| s.as_str());
    let iterations = args.get(2).map_or(10, |s| s.parse().unwrap());
    let (g, area) = match shape {
        "box" => (
            ops::triangulate(
                &primitives::box_mesh(geode_geo::glam::Vec3::ONE, [290, 290, 290]),
                None,
            ),
            6.0f32,
        ),
        _ => (
            ops::triangulate(&primitives::uv_sphere(1.0, 1000, 501), None),
            12.566,
        ),
    };
    let l = (area / (3f32.sqrt() / 4.0 * 1e6)).sqrt();
    let opts = RemeshOptions {
        sizing: Sizing::Uniform { length: l },
        relative: false,
        iterations,
        ..RemeshOptions::default()
    };
    let t = std::time::Instant::now();
    let out = remesh(&g, &opts, &|| false).unwrap();
    eprintln!(
        "{shape}: {} -> {} triangles in {:.2} s",
        g.num_prims(),
        out.num_prims(),
        t.elapsed().as_secs_f64()
    );
}
