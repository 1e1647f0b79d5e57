//! Meshing time of fidget 0.5.1 (JIT, manifold dual contouring) against
//! geode's polygoniser on fidget's own models, same depth, same bounds
//! ([-1, 1]^3, 2^depth cells a side), same machine, all threads.
//! Run: cargo run --release --manifest-path bench/fidget-compare/Cargo.toml

use std::time::{Duration, Instant};

use fidget::context::Context;
use fidget::jit::JitShape;
use fidget::mesh::{Octree, Settings};
use fidget::shape::BoundShape;

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

fn main() {
    println!("| model | depth | fidget ms | fidget triangles | geode ms | geode triangles | geode / fidget |");
    println!("|---|---|---|---|---|---|---|");
    for name in ["colonnade.vm", "bear.vm"] {
        let text = corpus(name);
        let (ctx, node) = Context::from_text(text.as_bytes()).expect("fidget parses its model");
        let shape = JitShape::new(&ctx, node).expect("a 3D shape");
        let bound: BoundShape<_, f32> = shape.try_into().expect("only x, y, z");
        let field = geode_frep::parse_vm(&text).expect("geode parses the model");
        for depth in [6u8, 7, 8] {
            let (tf, fm) = median(5, || {
                let settings = Settings {
                    depth,
                    ..Default::default()
                };
                Octree::build(&bound, &settings)
                    .expect("not cancelled")
                    .walk_dual()
            });
            let opts = geode_frep::MeshOptions::new([-1.0; 3], [1.0; 3], depth as u32);
            let (tg, gm) = median(5, || {
                geode_frep::polygonise(&field, &opts, &|| false, &|_| {}).expect("meshes")
            });
            println!(
                "| {name} | {depth} | {:.1} | {} | {:.1} | {} | {:.2} |",
                tf.as_secs_f64() * 1e3,
                fm.triangles.len(),
                tg.as_secs_f64() * 1e3,
                gm.0.num_prims(),
                tg.as_secs_f64() / tf.as_secs_f64()
            );
        }
    }
}
