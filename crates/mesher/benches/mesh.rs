//! Meshing time against octree depth: cost should grow ~4x per level (with the
//! surface), not 8x (with the volume). Triangle counts are printed once.
//! Also the memory estimate made before meshing, at depths 9 and 12.
//! Run: cargo bench -p geode-mesher --bench mesh

use geode_frep::shapes::{block, cylinder, sphere, union};
use geode_frep::Field;
use geode_mesher::{polygonise, MeshOptions};

fn main() {
    for (name, f, half) in cases() {
        for depth in [6, 7, 8] {
            let (g, s) = polygonise(
                &f,
                &MeshOptions::new([-half; 3], [half; 3], depth),
                &|| false,
                &|_| {},
            )
            .unwrap();
            eprintln!(
                "{name} depth {depth}: {} triangles, {} surface cells, {} of {} bricks meshed",
                g.num_prims(),
                s.cells_with_surface,
                s.bricks_meshed,
                s.bricks_total
            );
        }
    }
    divan::main();
}

fn gyroid_lattice() -> Field {
    let (x, y, z) = (Field::x() * 8.0, Field::y() * 8.0, Field::z() * 8.0);
    let g = x.sin() * y.cos() + y.sin() * z.cos() + z.sin() * x.cos();
    // A shell of thickness 0.6 (in gyroid units) inside a rounded part.
    let shell = 0.3 - g.abs();
    shell.min(block([0.0; 3], [0.8, 0.6, 0.5]))
}

fn spheres200() -> Field {
    let mut f = sphere([0.6, 0.0, -0.5], 0.08);
    for i in 1..200 {
        let t = i as f64 * 0.1;
        f = union(
            &f,
            &sphere([t.cos() * 0.6, t.sin() * 0.6, i as f64 / 200.0 - 0.5], 0.08),
            1.0,
        );
    }
    f
}

/// The seed's screw (figure 5.1): a sharp thread cut by a helical sawtooth,
/// a slotted head.
fn screw() -> Field {
    let (x, y, z) = (Field::x(), Field::y(), Field::z());
    let turns = z.atan2(x.clone()) / std::f64::consts::TAU + y.clone() / 0.25;
    let radius = (x.square() + z.square()).sqrt();
    let thread = 0.42 - radius - 0.3 * (turns.modulo(1.0) - 0.5).abs();
    let shaft = thread.min(cylinder([0.0; 3], 1.0, 0.8));
    let head = cylinder([0.0, 0.95, 0.0], 0.6, 0.15);
    let slot = block([0.0, 1.05, 0.0], [0.7, 0.1, 0.06]);
    shaft.max(head.min(&-slot))
}

/// Three discs 0.01 thick, turned off the axes (0.3 of a cell at depth 6,
/// 1.3 at depth 8): walls meshed through edges crossed twice.
fn walls() -> Field {
    let (x, y, z) = (Field::x(), Field::y(), Field::z());
    let disc = |n: [f64; 3], shift: f64| {
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let along = (&x * n[0] + &y * n[1] + &z * n[2]) / len - shift;
        (0.005 - along.abs()).min(sphere([0.0; 3], 0.8))
    };
    disc([1.0, 0.3, 0.2], 0.0)
        .max(disc([0.2, 1.0, -0.4], 0.1))
        .max(disc([-0.3, 0.1, 1.0], -0.05))
}

fn vm(name: &str) -> Field {
    let text = std::fs::read_to_string(format!(
        "{}/../../corpus/fidget-models/{name}",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    geode_frep::parse_vm(&text).unwrap()
}

fn cases() -> Vec<(&'static str, Field, f64)> {
    vec![
        ("sphere", sphere([0.0; 3], 0.9), 1.0),
        ("gyroid", gyroid_lattice(), 1.0),
        ("spheres200", spheres200(), 1.0),
        ("screw", screw().translate([0.0, -0.15, 0.0]), 1.0),
        ("walls", walls(), 1.0),
        ("colonnade", vm("colonnade.vm"), 1.0),
        ("bear", vm("bear.vm"), 1.0),
    ]
}

const CASES: [&str; 7] = [
    "sphere",
    "gyroid",
    "spheres200",
    "screw",
    "walls",
    "colonnade",
    "bear",
];

#[divan::bench(args = CASES, consts = [6, 7, 8], sample_count = 3)]
fn mesh_at_depth<const DEPTH: u32>(bencher: divan::Bencher, case: &str) {
    let (_, f, half) = cases()
        .into_iter()
        .find(|(n, _, _)| *n == case)
        .expect("a known case");
    bencher.bench(|| {
        polygonise(
            &f,
            &MeshOptions::new([-half; 3], [half; 3], DEPTH),
            &|| false,
            &|_| {},
        )
        .unwrap()
    });
}

/// The memory estimate the polygonise node makes before meshing (it must
/// stay milliseconds at any depth, the guard's whole point).
#[divan::bench(args = CASES, consts = [9, 12], sample_count = 3)]
fn estimate_at_depth<const DEPTH: u32>(bencher: divan::Bencher, case: &str) {
    let (_, f, half) = cases()
        .into_iter()
        .find(|(n, _, _)| *n == case)
        .expect("a known case");
    bencher.bench(|| {
        geode_mesher::polygonise::estimate(
            &f,
            &MeshOptions::new([-half; 3], [half; 3], DEPTH),
            &|| false,
        )
        .unwrap()
    });
}

/// Adaptive output at depth 8 with the tolerance set to the largest
/// deviation fidget 0.5.1's own mesh shows at that depth
/// (`bench/fidget-compare`): colonnade 0.0028, bear 0.00589, and for the
/// analytic cases a thousandth of the box.
#[divan::bench(args = CASES, sample_count = 3)]
fn adaptive_at_depth_8(bencher: divan::Bencher, case: &str) {
    let (_, f, half) = cases()
        .into_iter()
        .find(|(n, _, _)| *n == case)
        .expect("a known case");
    let mut opts = MeshOptions::new([-half; 3], [half; 3], 8);
    opts.tolerance = match case {
        "colonnade" => 0.0028,
        "bear" => 0.00589,
        _ => 0.002 * half,
    };
    bencher.bench(|| polygonise(&f, &opts, &|| false, &|_| {}).unwrap());
}
