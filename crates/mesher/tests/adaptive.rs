//! Adaptive output (`MeshOptions::tolerance`) against analytic surfaces:
//! every sample of a sphere's mesh within the tolerance of the exact sphere,
//! rotated boxes collapsed to a few triangles with every corner kept, closed
//! manifolds throughout, thread independence, fidget's models far below
//! fidget's triangle counts at fidget's deviation, and cancellation.

mod common;

use common::{apply, box_surface_distance, transpose, Rng};
use geode_frep::shapes::{block, sphere};
use geode_frep::{Field, Tape};
use geode_geo::glam::Vec3;
use geode_geo::Geometry;
use geode_mesher::{polygonise, surface_distances, MeshOptions, MeshStats};

fn adaptive(f: &Field, half: f64, depth: u32, tolerance: f64) -> (Geometry, MeshStats) {
    let mut opts = MeshOptions::new([-half; 3], [half; 3], depth);
    opts.tolerance = tolerance;
    polygonise(f, &opts, &|| false, &|_| {}).unwrap()
}

fn triangles(g: &Geometry) -> Vec<[Vec3; 3]> {
    (0..g.num_prims())
        .map(|p| {
            let pts = g.prim_points(p);
            assert_eq!(pts.len(), 3);
            [0, 1, 2].map(|i| g.positions()[pts[i] as usize])
        })
        .collect()
}

/// Vertices, centroids, edge midpoints and three more points inside each
/// triangle.
fn samples(g: &Geometry) -> Vec<Vec3> {
    let mut out = g.positions().to_vec();
    for [a, b, c] in triangles(g) {
        for (u, v) in [
            (1.0 / 3.0, 1.0 / 3.0),
            (0.5, 0.0),
            (0.5, 0.5),
            (0.0, 0.5),
            (0.6, 0.2),
            (0.2, 0.6),
            (0.2, 0.2),
        ] {
            out.push(a + (b - a) * u + (c - a) * v);
        }
    }
    out
}

fn assert_closed(g: &Geometry, what: &str) {
    let report = g.topology().manifold_report(g);
    assert!(report.is_closed_manifold(), "{what}: {report:?}");
}

#[test]
fn a_sphere_stays_within_the_tolerance_everywhere() {
    let f = sphere([0.05, -0.03, 0.02], 0.8);
    let (uniform, _) = adaptive(&f, 1.0, 7, 0.0);
    for tolerance in [0.001, 0.004] {
        let (g, stats) = adaptive(&f, 1.0, 7, tolerance);
        assert_closed(&g, "sphere");
        let worst = samples(&g)
            .iter()
            .map(|p| {
                ((p.as_dvec3() - geode_geo::glam::DVec3::new(0.05, -0.03, 0.02)).length() - 0.8)
                    .abs()
            })
            .fold(0.0, f64::max);
        eprintln!(
            "tolerance {tolerance}: {} of {} triangles, worst sample {worst:.5}, {} collapses",
            g.num_prims(),
            uniform.num_prims(),
            stats.collapses
        );
        // Measured points stay within the tolerance; other points of a
        // triangle on a convex surface lie no deeper than a little more.
        assert!(worst <= tolerance * 1.25, "{tolerance}: {worst}");
        assert!(g.num_prims() * 8 < uniform.num_prims(), "{}", g.num_prims());
    }
}

#[test]
fn rotated_boxes_collapse_to_a_few_triangles_keeping_every_corner() {
    let mut rng = Rng(0xada9);
    let depth = 6;
    let cell = 2.0 / (1u64 << depth) as f64;
    for case in 0..6 {
        let r = rng.rotation();
        let h = [
            0.3 + 0.2 * rng.next(),
            0.3 + 0.2 * rng.next(),
            0.3 + 0.2 * rng.next(),
        ];
        let rt = transpose(&r);
        let f = block([0.0; 3], h).affine_inverse(rt, [0.0; 3]);
        let (g, _) = adaptive(&f, 1.0, depth, 1e-3);
        assert_closed(&g, "box");
        for s in 0..8 {
            let local = [0, 1, 2].map(|k| if s >> k & 1 == 0 { -h[k] } else { h[k] });
            let corner = apply(&r, local);
            let nearest = common::nearest_vertex(&g, corner);
            assert!(
                nearest / cell <= 0.02,
                "case {case}: corner missed by {} cells",
                nearest / cell
            );
        }
        // A box is twelve triangles (most cases come out so); a vertex that
        // splitting put near a crease may stay where collapsing it would
        // stray past the tolerance.
        assert!(
            g.num_prims() <= 32,
            "case {case}: {} triangles",
            g.num_prims()
        );
        // The first-order measure `|f| / |∇f|` of a box reads the largest
        // of the distances to the faces: near a corner the true distance
        // is up to √3 times that.
        for p in samples(&g) {
            let d = box_surface_distance(apply(&rt, p.as_dvec3().to_array()), h);
            assert!(d <= 1.75e-3, "case {case}: {p} is {d} off");
        }
    }
}

#[test]
fn a_zero_tolerance_is_the_uniform_mesh() {
    let f = sphere([0.0; 3], 0.7).max(block([0.3; 3], [0.3; 3]));
    let uniform = common::mesh(&f, 1.0, 6);
    let (zero, stats) = adaptive(&f, 1.0, 6, 0.0);
    assert_eq!(uniform.positions(), zero.positions());
    assert_eq!(uniform.num_prims(), zero.num_prims());
    assert_eq!((stats.splits, stats.collapses), (0, 0));
}

#[test]
fn the_output_does_not_depend_on_threads() {
    let f = sphere([0.0; 3], 0.7)
        .max(block([0.3; 3], [0.3; 3]))
        .min(-sphere([0.5, 0.0, 0.0], 0.4));
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let (g, _) = pool.install(|| adaptive(&f, 1.0, 7, 0.002));
        let prims: Vec<Vec<u32>> = (0..g.num_prims())
            .map(|p| g.prim_points(p).to_vec())
            .collect();
        (g.positions().to_vec(), prims)
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(4));
}

fn corpus_model(name: &str) -> Field {
    let path = format!(
        "{}/../../corpus/fidget-models/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    geode_frep::parse_vm(&std::fs::read_to_string(&path).unwrap()).unwrap()
}

/// At the largest deviation fidget 0.5.1's own mesh of the model shows
/// (`bench/fidget-compare`, depth 7: colonnade 0.0208 with 36,262
/// triangles, bear 0.00644 with 72,836; depth 8: bear 0.00589 with
/// 117,118), geode's adaptive output is closed, within that deviation
/// wherever it is measured, and a small fraction of fidget's triangles.
#[test]
fn fidgets_models_take_far_fewer_triangles_than_fidget_at_its_deviation() {
    for (name, depth, deviation, fidget_triangles) in [
        ("colonnade.vm", 7, 0.0208, 36_262),
        ("bear.vm", 7, 0.00644, 72_836),
        ("bear.vm", 8, 0.00589, 117_118),
    ] {
        let f = corpus_model(name);
        let (g, stats) = adaptive(&f, 1.0, depth, deviation);
        assert_closed(&g, name);
        let tape = Tape::compile(&f);
        let mut points = g.positions().to_vec();
        for [a, b, c] in triangles(&g) {
            points.extend([
                (a + b + c) / 3.0,
                0.5 * (a + b),
                0.5 * (b + c),
                0.5 * (c + a),
            ]);
        }
        let worst = surface_distances(&tape, &points)
            .into_iter()
            .fold(0.0f32, f32::max);
        eprintln!(
            "{name}: {} triangles, worst {worst:.5}, {stats:?}",
            g.num_prims()
        );
        assert!(worst as f64 <= deviation * 1.001, "{name}: {worst}");
        assert!(
            g.num_prims() * 10 < fidget_triangles,
            "{name}: {}",
            g.num_prims()
        );
    }
}

#[test]
fn cancelling_stops_adaptive_output() {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let f = sphere([0.0; 3], 0.7);
    let mut opts = MeshOptions::new([-1.0; 3], [1.0; 3], 7);
    let calls = AtomicUsize::new(0);
    let count = || calls.fetch_add(1, Ordering::Relaxed) == usize::MAX;
    polygonise(&f, &opts, &count, &|_| {}).unwrap();
    let uniform = calls.load(Ordering::Relaxed);
    // Cancel once the uniform mesh is done: within adaptive output.
    opts.tolerance = 0.001;
    calls.store(0, Ordering::Relaxed);
    let cancel = || calls.fetch_add(1, Ordering::Relaxed) > uniform + 1;
    let r = polygonise(&f, &opts, &cancel, &|_| {});
    assert!(
        matches!(r, Err(geode_mesher::MeshError::Cancelled)),
        "{:?}",
        r.map(|x| x.1)
    );
}

/// Every sample the tolerance is kept at: vertices, centroids, edge midpoints.
fn worst_deviation(f: &Field, g: &Geometry) -> f32 {
    let tape = Tape::compile(f);
    let mut points = g.positions().to_vec();
    for [a, b, c] in triangles(g) {
        points.extend([
            (a + b + c) / 3.0,
            0.5 * (a + b),
            0.5 * (b + c),
            0.5 * (c + a),
        ]);
    }
    surface_distances(&tape, &points)
        .into_iter()
        .fold(0.0f32, f32::max)
}

/// Coarse leaves (octree nodes meshed as one vertex, top-down) on models
/// with thin plates, creases, blends and many parts, at tolerances from a
/// quarter of a cell to two cells: closed manifolds within the tolerance,
/// or where the uniform mesh itself strays as far (a feature thinner than
/// a cell, which no refinement of the mesh finds: colonnade at depth 6 is
/// half a cell off; the gyroid shell's walls a cell), about as far. Leaves placed without the
/// topology checks (one disc, one arc per face) left non-manifold edges
/// on colonnade.
#[test]
fn coarse_leaves_keep_every_model_closed_and_within_the_tolerance() {
    let (x, y, z) = (Field::x(), Field::y(), Field::z());
    let wave = |a: &Field, b: &Field| (a * 9.0).sin() * (b * 9.0).cos();
    let gyroid = (wave(&x, &y) + wave(&y, &z) + wave(&z, &x)).abs() * -1.0 + 0.3;
    // (Not hi.vm: its field is far from a distance, so the first-order
    // measure reads two cells off on the uniform mesh itself.)
    let mut models: Vec<(String, Field)> = ["colonnade.vm", "bear.vm", "tanglecube.vm"]
        .iter()
        .map(|n| (n.to_string(), corpus_model(n)))
        .collect();
    models.push(("gyroid shell".into(), gyroid.min(sphere([0.0; 3], 0.9))));
    for (name, f) in &models {
        for depth in [6, 7] {
            let cell = 2.0 / (1u64 << depth) as f64;
            let (uniform, _) = adaptive(f, 1.0, depth, 0.0);
            let floor = worst_deviation(f, &uniform) as f64;
            for k in [0.25, 1.0, 2.0] {
                let (g, stats) = adaptive(f, 1.0, depth, k * cell);
                assert_closed(&g, &format!("{name} at depth {depth}, tolerance {k} cell"));
                let worst = worst_deviation(f, &g) as f64;
                // Strict where the uniform mesh is well within the
                // tolerance; where it is not (refinement gives up there,
                // and may stop a little past it), within a tenth of it.
                let bound = if floor < 0.9 * k * cell {
                    k * cell * 1.001
                } else {
                    (k * cell).max(floor) * 1.1
                };
                assert!(
                    worst <= bound,
                    "{name} {depth} {k}: {worst} (uniform {floor})"
                );
                if name == "colonnade.vm" {
                    assert!(stats.leaves > 100, "{name} {depth} {k}: {stats:?}");
                }
            }
        }
    }
}

/// A tilted half-space is one flat sheet everywhere: the octree stops at
/// nodes of many cells (proved one sheet by interval bounds on the
/// gradient), so almost no cell is meshed on its own, yet the box's
/// creases and corners stay.
#[test]
fn a_tilted_plane_is_meshed_from_coarse_leaves() {
    let n = [0.3f64, 0.5, 0.81];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let plane = (Field::x() * (n[0] / len) + Field::y() * (n[1] / len) + Field::z() * (n[2] / len))
        * -1.0
        + 0.1;
    let f = plane.min(block([0.0; 3], [0.8; 3]));
    let depth = 7;
    let (_, uniform) = adaptive(&f, 1.0, depth, 0.0);
    let (g, stats) = adaptive(&f, 1.0, depth, 0.002);
    assert_closed(&g, "tilted plane");
    assert!(worst_deviation(&f, &g) <= 0.002 * 1.001);
    assert!(stats.leaves > 0, "{stats:?}");
    assert!(
        stats.cells_with_surface * 4 < uniform.cells_with_surface,
        "{} of {} cells meshed one by one",
        stats.cells_with_surface,
        uniform.cells_with_surface
    );
}

/// A tilted plate two cells thick crosses many nodes of 2 and 4 cells as
/// two sheets (two loops on their boundary): such a node is one vertex per
/// sheet, so the plate is meshed from leaves on both sides, each side
/// whole, closed and within the tolerance. (With one vertex per node, 2,984
/// of its 8,440 cells were meshed one by one; now 673.)
#[test]
fn a_thin_plate_is_meshed_from_leaves_of_two_sheets() {
    let n = [0.3f64, 0.5, 0.81];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let unit = n.map(|x| x / len);
    let depth = 6;
    let cell = 2.0 / (1u64 << depth) as f64;
    let half_thickness = cell;
    let across = Field::x() * unit[0] + Field::y() * unit[1] + Field::z() * unit[2];
    let plate = (across.abs() * -1.0 + half_thickness).min(block([0.0; 3], [0.7; 3]));
    let g = meshed_mostly_from_leaves(&plate, depth, 0.5 * cell, 8, "thin plate");
    // Each side's area: the triangles facing along the plate's normal, and
    // those facing against it.
    let normal = Vec3::new(unit[0] as f32, unit[1] as f32, unit[2] as f32);
    let (mut up, mut down) = (0.0f64, 0.0f64);
    for [a, b, c] in triangles(&g) {
        let cross = (b - a).cross(c - a);
        let area = 0.5 * cross.length() as f64;
        let facing = cross.normalize_or_zero().dot(normal);
        if facing > 0.9 {
            up += area;
        } else if facing < -0.9 {
            down += area;
        }
    }
    assert!(
        up > 0.0 && (up - down).abs() < 0.05 * up,
        "sides of {up} and {down}"
    );
}

/// A node whose one vertex strays beyond the tolerance hands its cells to
/// its octants, each a leaf where its own vertex fits: a sphere at a
/// quarter of a cell's tolerance is meshed almost wholly from leaves of 2
/// and 4 cells. (When such a node gave its cells to the brick instead,
/// 6,827 of the sphere's cells were meshed one by one; now 36.)
#[test]
fn a_node_that_does_not_fit_hands_its_cells_to_its_octants() {
    let f = sphere([0.0; 3], 0.6);
    let depth = 6;
    let cell = 2.0 / (1u64 << depth) as f64;
    meshed_mostly_from_leaves(&f, depth, 0.25 * cell, 50, "sphere");
}

/// `f` meshed adaptively at `depth` within `tolerance` over [-1, 1]^3:
/// closed, every vertex, centroid and edge midpoint within the tolerance,
/// and fewer than one in `fewer` of the uniform mesh's cells meshed one by
/// one (the rest in leaves).
fn meshed_mostly_from_leaves(
    f: &Field,
    depth: u32,
    tolerance: f64,
    fewer: usize,
    what: &str,
) -> Geometry {
    let (_, uniform) = adaptive(f, 1.0, depth, 0.0);
    let (g, stats) = adaptive(f, 1.0, depth, tolerance);
    assert_closed(&g, what);
    assert!(worst_deviation(f, &g) as f64 <= tolerance * 1.001, "{what}");
    assert!(
        stats.cells_with_surface * fewer < uniform.cells_with_surface,
        "{what}: {} of {} cells meshed one by one ({} leaves)",
        stats.cells_with_surface,
        uniform.cells_with_surface,
        stats.leaves
    );
    g
}

/// A cone and a cylinder capped by a sphere at five turns and three
/// tolerances: every adaptive mesh closed. A node meshed whole shares its
/// boundary with bricks that mesh an edge there crossed twice (the rim's
/// wedge poking past a grid edge) through quads the node left open: 22 of
/// 100 such meshes had holes on the rim before such a node was refused.
#[test]
fn rims_stay_closed_where_a_node_meets_edges_crossed_twice() {
    use geode_frep::shapes::{cone, cylinder};
    use geode_geo::glam::DMat4;
    let shapes = [
        ("cone", cone([0.0, 0.6, 0.0], 0.5, 1.2)),
        (
            "capped cylinder",
            cylinder([0.0; 3], 0.5, 0.6).max(sphere([0.0, 0.6, 0.0], 0.7)),
        ),
    ];
    let turns = [
        [0.0f64, 0.0, 0.0],
        [90.0, 0.0, 0.0],
        [10.0, 0.0, 0.0],
        [30.0, 20.0, 10.0],
        [13.0, 47.0, 71.0],
    ];
    let mut open = Vec::new();
    for (name, shape) in &shapes {
        for t in turns {
            let turn = DMat4::from_rotation_z(t[2].to_radians())
                * DMat4::from_rotation_y(t[1].to_radians())
                * DMat4::from_rotation_x(t[0].to_radians());
            let f = shape.transformed(&turn).unwrap();
            for tolerance in [0.002, 0.01, 0.05] {
                let (g, _) = adaptive(&f, 1.0, 7, tolerance);
                let report = g.topology().manifold_report(&g);
                if !report.is_closed_manifold() {
                    open.push(format!("{name} turned {t:?} at {tolerance}: {report:?}"));
                }
            }
        }
    }
    assert!(open.is_empty(), "{open:#?}");
}
