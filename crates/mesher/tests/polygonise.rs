//! The polygoniser against analytic answers: volumes, distance of vertices to
//! the surface, sharp box corners and edges, normals, manifoldness, cost
//! following the surface, determinism, cancellation.

mod common;

use geode_frep::shapes::{block, sphere, torus, union};
use geode_frep::{Field, GradEval, PointEval, Tape};
use geode_geo::{ops, AttribClass, Geometry};
use geode_mesher::{polygonise, MeshOptions};

use common::mesh;

fn closed_manifold(g: &Geometry) {
    let r = g.topology().manifold_report(g);
    assert!(r.is_closed_manifold(), "{r:?}");
}

#[test]
fn volumes_within_half_a_percent() {
    let cases = [
        (
            "sphere",
            sphere([0.1, 0.0, -0.05], 1.0),
            4.0 / 3.0 * std::f64::consts::PI,
        ),
        (
            "box",
            block([0.0; 3], [0.8, 0.5, 0.3]),
            8.0 * 0.8 * 0.5 * 0.3,
        ),
        (
            "torus",
            torus([0.0; 3], 1.0, 0.35),
            2.0 * std::f64::consts::PI.powi(2) * 1.0 * 0.35f64.powi(2),
        ),
    ];
    for (name, f, v) in cases {
        let g = mesh(&f, 1.5, 6);
        closed_manifold(&g);
        let got = ops::signed_volume(&g) as f64;
        assert!((got - v).abs() / v < 0.005, "{name}: {got} vs {v}");
    }
}

#[test]
fn vertices_lie_on_the_surface() {
    let f = union(&sphere([0.0; 3], 0.8), &torus([0.0; 3], 1.0, 0.25), 1.0);
    let g = mesh(&f, 1.5, 6);
    closed_manifold(&g);
    let cell = 3.0 / 64.0;
    let tape = Tape::compile(&f);
    let mut p = PointEval::new(&tape);
    let mut gr = GradEval::new(&tape);
    let mut worst = 0.0f64;
    for q in g.positions() {
        let q = [q.x as f64, q.y as f64, q.z as f64];
        let d = gr.eval(q).d;
        let dist = p.eval(q).abs() / (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt().max(1e-9);
        worst = worst.max(dist);
    }
    assert!(
        worst < 0.1 * cell,
        "worst |f|/|grad f| = {worst} (cell {cell})"
    );
}

#[test]
fn box_corners_and_edges_are_sharp_at_coarse_resolution() {
    // A box whose faces fall inside cells (not on grid planes) at depth 4.
    let half = [0.61, 0.43, 0.37];
    let f = block([0.013, -0.021, 0.007], half);
    let g = mesh(&f, 1.0, 4);
    closed_manifold(&g);
    let c = [0.013, -0.021, 0.007];
    for sx in [-1.0, 1.0] {
        for sy in [-1.0, 1.0] {
            for sz in [-1.0, 1.0] {
                let corner = [
                    c[0] + sx * half[0],
                    c[1] + sy * half[1],
                    c[2] + sz * half[2],
                ];
                let nearest = common::nearest_vertex(&g, corner);
                assert!(nearest < 1e-4, "corner {corner:?} missed by {nearest}");
            }
        }
    }
    // Points on the twelve edges: every vertex near an edge lies on it.
    let vol = ops::signed_volume(&g) as f64;
    let exact = 8.0 * half[0] * half[1] * half[2];
    assert!(
        (vol - exact).abs() / exact < 1e-3,
        "sharp edges keep the volume: {vol} vs {exact}"
    );
}

#[test]
fn normals_agree_with_the_gradient() {
    let f = sphere([0.0; 3], 1.0);
    let g = mesh(&f, 1.2, 5);
    let n = g
        .attrib(AttribClass::Point, "N")
        .unwrap()
        .as_vec3()
        .unwrap();
    for (p, n) in g.positions().iter().zip(n) {
        assert!((*n - p.normalize()).length() < 1e-3, "outward unit normal");
    }
    // Triangles wind outward: positive volume.
    assert!(ops::signed_volume(&g) > 0.0);
}

#[test]
fn cost_follows_the_surface() {
    let f = sphere([0.0; 3], 1.0);
    let stats = |d| {
        polygonise(
            &f,
            &MeshOptions::new([-1.2; 3], [1.2; 3], d),
            &|| false,
            &|_| {},
        )
        .unwrap()
        .1
    };
    let (a, b) = (stats(6), stats(7));
    let ratio = b.cells_with_surface as f64 / a.cells_with_surface as f64;
    assert!(
        (3.3..4.8).contains(&ratio),
        "surface cells grow ~4x per level: {ratio}"
    );
    let brick_ratio = b.bricks_meshed as f64 / a.bricks_meshed as f64;
    assert!(
        brick_ratio < 5.0,
        "meshed bricks grow with the surface, not 8x: {brick_ratio}"
    );
}

#[test]
fn deterministic_on_any_thread_count_and_cancellable() {
    let f = union(
        &sphere([0.3, 0.0, 0.0], 0.5),
        &block([-0.3, 0.0, 0.0], [0.3, 0.3, 0.3]),
        0.0,
    );
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| mesh(&f, 1.0, 6).content_hash())
    };
    assert_eq!(run(1), run(3));
    let r = polygonise(
        &f,
        &MeshOptions::new([-1.0; 3], [1.0; 3], 7),
        &|| true,
        &|_| {},
    );
    assert_eq!(r.unwrap_err(), geode_mesher::MeshError::Cancelled);
    let bad = polygonise(
        &f,
        &MeshOptions::new([0.0; 3], [0.0, 1.0, 1.0], 5),
        &|| false,
        &|_| {},
    );
    assert_eq!(bad.unwrap_err(), geode_mesher::MeshError::BadBounds);
}

#[test]
fn solids_touching_the_box_are_closed_by_it() {
    let g = mesh(&sphere([0.0; 3], 2.0), 1.0, 4);
    closed_manifold(&g);
    assert!(
        (ops::signed_volume(&g) - 8.0).abs() < 1e-3,
        "the clipped sphere fills the box"
    );
}

/// Tubes thinner than a cell (a thin gyroid shell cut by a superellipsoid,
/// a tree of branches one to two cells thick, at depth 7): some cell faces
/// are crossed twice by one sheet that also joins both crossings inside the
/// cells on either side. Dual contouring with one vertex per cell component
/// puts such a dual edge in four quads; the mesher must split those
/// vertices so the result stays a closed manifold.
#[test]
fn thin_tubes_through_cell_faces_stay_manifold() {
    let (x, y, z) = (Field::x() * 12.0, Field::y() * 12.0, Field::z() * 12.0);
    let g = x.sin() * y.cos() + y.sin() * z.cos() + z.sin() * x.cos();
    let shell = 0.35 - g.abs();
    let part = geode_frep::shapes::superellipsoid([0.0; 3], [0.9, 0.6, 0.6], 0.3, 0.3);
    let cases = [
        (shell.min(part), [-1.0, -0.7, -0.7], [1.0, 0.7, 0.7]),
        (branches().min(1.5), [-1.0; 3], [1.0; 3]),
    ];
    let mut split = 0;
    for (f, lo, hi) in cases {
        let (g, stats) = polygonise(&f, &MeshOptions::new(lo, hi, 7), &|| false, &|_| {}).unwrap();
        split += stats.vertices_split;
        closed_manifold(&g);
        // Split copies are moved apart: no two vertices share a position (a
        // welding checker such as trimesh would otherwise fuse them back).
        let mut seen = std::collections::HashSet::new();
        for p in g.positions() {
            assert!(
                seen.insert(p.to_array().map(f32::to_bits)),
                "duplicate vertex {p}"
            );
        }
    }
    assert!(split > 0, "the case this test is for");
}

/// A seeded tree of 400 tapered branches, one to two cells thick at depth 7.
fn branches() -> Field {
    use geode_frep::CapsuleSet;
    let mut rng = common::Rng(0xc0a1);
    let mut segments = Vec::new();
    let mut tips = vec![[0.0, -0.8, 0.0]];
    for _ in 0..400 {
        let from = tips[(rng.next() * tips.len() as f64) as usize];
        let to: [f64; 3] = std::array::from_fn(|k| {
            let step = if k == 1 {
                0.05 + 0.04 * rng.next()
            } else {
                0.12 * (rng.next() - 0.5)
            };
            (from[k] + step).clamp(-0.9, 0.9)
        });
        segments.push((
            from,
            to,
            0.02 + 0.01 * rng.next(),
            0.015 + 0.01 * rng.next(),
        ));
        tips.push(to);
    }
    Field::capsules(CapsuleSet::new(&segments).unwrap())
}

#[test]
fn the_meshing_estimate_is_close_to_the_cells_meshed() {
    // A sphere, a torus and a gyroid slab: curved, thin and busy surfaces.
    let sphere = sphere([0.0; 3], 0.9);
    let torus = torus([0.1, 0.0, 0.0], 0.6, 0.2);
    let (x, y, z) = (Field::x(), Field::y(), Field::z());
    let k = 6.0;
    let gyroid = ((x.clone() * k).sin() * (y.clone() * k).cos()
        + (y * k).sin() * (z.clone() * k).cos()
        + (z * k).sin() * (x * k).cos())
    .min(0.6)
    .max(-0.6);
    for (name, f) in [("sphere", sphere), ("torus", torus), ("gyroid", gyroid)] {
        for depth in [7, 8] {
            let opts = MeshOptions::new([-1.0; 3], [1.0; 3], depth);
            let est = geode_mesher::polygonise::estimate(&f, &opts, &|| false).unwrap();
            let (_, stats) = polygonise(&f, &opts, &|| false, &|_| {}).unwrap();
            let ratio = est.surface_cells / stats.cells_with_surface as f64;
            eprintln!(
                "{name} depth {depth}: estimate {:.0}, meshed {}, ratio {ratio:.2}",
                est.surface_cells, stats.cells_with_surface
            );
            assert!(
                (0.8..=1.5).contains(&ratio),
                "{name} at depth {depth}: ratio {ratio}"
            );
        }
    }
}

/// A branching sweep of many thin capsules (the coral's kind of field):
/// the mesher floors capsule sets it reaches through min and max at a few
/// cells below zero, so that far capsules drop out of every search; the
/// mesh must be the same as that of the same field the floor cannot reach
/// (the sweep behind `* 1`), and closed.
#[test]
fn floored_capsule_sets_mesh_as_the_unfloored_field() {
    let sweep = branches();
    let opts = MeshOptions::new([-1.0; 3], [1.0; 3], 7);
    let floored = polygonise(&sweep.min(1.5), &opts, &|| false, &|_| {})
        .unwrap()
        .0;
    let plain = polygonise(&(&sweep * 1.0).min(1.5), &opts, &|| false, &|_| {})
        .unwrap()
        .0;
    closed_manifold(&floored);
    assert_eq!(floored.num_points(), plain.num_points());
    assert_eq!(floored.positions(), plain.positions());
}
