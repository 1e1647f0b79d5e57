//! Meshing time, size and accuracy of fidget 0.5.1 (JIT, manifold dual
//! contouring with its octree collapse) against geode's polygoniser on
//! fidget's own models, same depth, same bounds ([-1, 1]^3, 2^depth cells a
//! side), same machine, all threads. Accuracy is the largest distance from
//! each mesh to the exact surface (`deviation`); geode's adaptive output is
//! run with that distance of fidget's mesh as its tolerance, so the two
//! compare at the same maximum deviation.
//! Run: cargo run --release --manifest-path bench/fidget-compare/Cargo.toml [-- 6,7,8]
//! (`MODELS=colonnade.vm` runs one model: handy under a profiler).

mod deviation;

use std::time::{Duration, Instant};

use fidget::context::Context;
use fidget::jit::JitShape;
use fidget::mesh::{Octree, Settings};
use fidget::shape::BoundShape;

use deviation::deviation;

fn corpus(name: &str) -> String {
    let path = format!(
        "{}/../../../shared/corpus/fidget-models/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// Median of `runs` timings after one warm-up (JIT compilation and page
/// faults are not what is compared).
fn median<T>(runs: usize, mut f: impl FnMut() -> T) -> (Duration, T) {
    let mut out = f();
    let mut times = Vec::with_capacity(runs);
    for _ in 0..runs {
        let t = Instant::now();
        out = f();
        times.push(t.elapsed());
    }
    times.sort();
    (times[runs / 2], out)
}

fn geode_mesh(g: &geode_frep::MeshOptions, field: &geode_frep::Field) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let (m, _) = geode_frep::polygonise(field, g, &|| false, &|_| {}).expect("meshes");
    let positions = m.positions().iter().map(|p| p.to_array()).collect();
    let tris = (0..m.num_prims())
        .map(|p| {
            let pts = m.prim_points(p);
            [pts[0], pts[1], pts[2]]
        })
        .collect();
    (positions, tris)
}

fn main() {
    let depths: Vec<u8> = std::env::args()
        .nth(1)
        .map(|a| a.split(',').map(|d| d.parse().expect("depths like 6,7,8")).collect())
        .unwrap_or(vec![6, 7, 8]);
    println!("| model | depth | fidget ms | fidget triangles | fidget max dev | geode uniform ms | triangles | max dev | geode adaptive ms | triangles | max dev | adaptive time / fidget |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let models = std::env::var("MODELS").unwrap_or_else(|_| "colonnade.vm,bear.vm".into());
    for name in models.split(',') {
        let text = corpus(name);
        let (ctx, node) = Context::from_text(text.as_bytes()).expect("fidget parses its model");
        let shape = JitShape::new(&ctx, node).expect("a 3D shape");
        let bound: BoundShape<_, f32> = shape.try_into().expect("only x, y, z");
        let field = geode_frep::parse_vm(&text).expect("geode parses the model");
        for &depth in &depths {
            let runs = if depth >= 8 { 3 } else { 5 };
            let (tf, fm) = median(runs, || {
                let settings = Settings {
                    depth,
                    ..Default::default()
                };
                Octree::build(&bound, &settings)
                    .expect("not cancelled")
                    .walk_dual()
            });
            let fp: Vec<[f32; 3]> = fm.vertices.iter().map(|v| [v.x, v.y, v.z]).collect();
            let ft: Vec<[u32; 3]> = fm
                .triangles
                .iter()
                .map(|t| [t.x as u32, t.y as u32, t.z as u32])
                .collect();
            let (fdev, _) = deviation(&field, &fp, &ft);
            let mut opts = geode_frep::MeshOptions::new([-1.0; 3], [1.0; 3], depth as u32);
            let (tu, (up, ut)) = median(runs, || geode_mesh(&opts, &field));
            let (udev, _) = deviation(&field, &up, &ut);
            opts.tolerance = fdev;
            let (ta, (ap, at)) = median(runs, || geode_mesh(&opts, &field));
            let (adev, _) = deviation(&field, &ap, &at);
            println!(
                "| {name} | {depth} | {:.1} | {} | {:.5} | {:.1} | {} | {:.5} | {:.1} | {} | {:.5} | {:.2} |",
                tf.as_secs_f64() * 1e3,
                ft.len(),
                fdev,
                tu.as_secs_f64() * 1e3,
                ut.len(),
                udev,
                ta.as_secs_f64() * 1e3,
                at.len(),
                adev,
                ta.as_secs_f64() / tf.as_secs_f64()
            );
        }
    }
}
