//! Meshing time, size and accuracy of fidget 0.5.1 (JIT, manifold dual
//! contouring with its octree collapse) against geode's polygoniser on
//! fidget's own models, same depth, same bounds ([-1, 1]^3, 2^depth cells a
//! side), same machine, all threads. Accuracy is the largest distance from
//! each mesh to the exact surface (`deviation`); geode's adaptive output is
//! run with that distance of fidget's mesh as its tolerance, so the two
//! compare at the same maximum deviation. Timed runs of the three are
//! interleaved and the ratio is the median of each round's own, so the
//! machine's drift in speed (often 30% here) does not fall on one of them.
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
        "{}/../../corpus/fidget-models/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// Times one run of `f`.
fn timed<T>(f: impl FnOnce() -> T) -> (Duration, T) {
    let t = Instant::now();
    let out = f();
    (t.elapsed(), out)
}

fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs[xs.len() / 2]
}

fn geode_mesh(
    g: &geode_mesher::MeshOptions,
    field: &geode_frep::Field,
) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let (m, _) = geode_mesher::polygonise(field, g, &|| false, &|_| {}).expect("meshes");
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
        .map(|a| {
            a.split(',')
                .map(|d| d.parse().expect("depths like 6,7,8"))
                .collect()
        })
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
            // More rounds where a round is short: the ratio's median then
            // moves less with the machine's drift (colonnade at depth 7 read
            // 0.45-0.56 over runs of five rounds).
            let runs = match depth {
                0..=6 => 15,
                7 => 9,
                _ => 3,
            };
            let fidget_mesh = || {
                let settings = Settings {
                    depth,
                    ..Default::default()
                };
                Octree::build(&bound, &settings)
                    .expect("not cancelled")
                    .walk_dual()
            };
            // A warm-up of each (JIT compilation and page faults are not
            // what is compared), which also gives fidget's deviation, the
            // tolerance of geode's adaptive output.
            let fm = fidget_mesh();
            let fp: Vec<[f32; 3]> = fm.vertices.iter().map(|v| [v.x, v.y, v.z]).collect();
            let ft: Vec<[u32; 3]> = fm
                .triangles
                .iter()
                .map(|t| [t.x as u32, t.y as u32, t.z as u32])
                .collect();
            let (fdev, _) = deviation(&field, &fp, &ft);
            let uniform = geode_mesher::MeshOptions::new([-1.0; 3], [1.0; 3], depth as u32);
            let mut adaptive = uniform.clone();
            adaptive.tolerance = fdev;
            let (mut up, mut ut) = geode_mesh(&uniform, &field);
            let (mut ap, mut at) = geode_mesh(&adaptive, &field);
            // Rounds of one run each, interleaved, so a drift in the
            // machine's speed moves all three alike; the ratio is the
            // median of each round's own.
            let (mut tf, mut tu, mut ta, mut ratios) = (vec![], vec![], vec![], vec![]);
            for _ in 0..runs {
                let (f, _) = timed(fidget_mesh);
                let (u, mesh) = timed(|| geode_mesh(&uniform, &field));
                (up, ut) = mesh;
                let (a, mesh) = timed(|| geode_mesh(&adaptive, &field));
                (ap, at) = mesh;
                let [f, u, a] = [f, u, a].map(|t| t.as_secs_f64() * 1e3);
                tf.push(f);
                tu.push(u);
                ta.push(a);
                ratios.push(a / f);
            }
            let (udev, _) = deviation(&field, &up, &ut);
            let (adev, _) = deviation(&field, &ap, &at);
            let [tf, tu, ta, ratio] = [tf, tu, ta, ratios].map(median);
            println!(
                "| {name} | {depth} | {:.1} | {} | {:.5} | {:.1} | {} | {:.5} | {:.1} | {} | {:.5} | {:.2} |",
                tf,
                ft.len(),
                fdev,
                tu,
                ut.len(),
                udev,
                ta,
                at.len(),
                adev,
                ratio
            );
        }
    }
}
