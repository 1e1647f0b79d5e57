//! Thin features: a plate or a slot thinner than a cell, at seeded random
//! orientations, is meshed on both of its sides (edges the surface crosses
//! twice, see `double.rs`): its volume within 10% of the exact one, each
//! face of the plate covered by the mesh, closed and manifold, and nothing
//! reported missing. A feature no grid edge crosses (a speck inside a cell)
//! is still reported; solids whose features are larger than a cell report
//! nothing.

mod common;

use common::Rng;
use geode_frep::shapes::{block, sphere};
use geode_frep::Field;
use geode_geo::glam::{DVec3, Vec3};
use geode_geo::{ops, Geometry};
use geode_mesher::{polygonise, MeshOptions, MeshStats};

const DEPTH: u32 = 6;
const HALF: f64 = 1.0;

fn cell() -> f64 {
    2.0 * HALF / (1u64 << DEPTH) as f64
}

fn mesh(f: &Field) -> (Geometry, MeshStats) {
    polygonise(
        f,
        &MeshOptions::new([-HALF; 3], [HALF; 3], DEPTH),
        &|| false,
        &|_| {},
    )
    .unwrap()
}

/// A disc-shaped plate `thickness` thick, radius `RADIUS`, normal `n`,
/// offset from the origin by `shift` along it.
fn plate(n: [f64; 3], thickness: f64, shift: f64) -> Field {
    let (x, y, z) = (Field::x(), Field::y(), Field::z());
    let along = &x * n[0] + &y * n[1] + &z * n[2] - shift;
    let slab = thickness * 0.5 - along.abs();
    slab.min(sphere([0.0; 3], RADIUS))
}

const RADIUS: f64 = 0.6;

fn normal(rng: &mut Rng) -> [f64; 3] {
    rng.rotation()[2]
}

/// Points of the plane `n . p = offset` within `within` of the origin, on
/// a spiral (a fixed, even spread over the disc).
fn disc_points(n: [f64; 3], offset: f64, within: f64) -> Vec<Vec3> {
    let n = DVec3::from_array(n);
    let u = n.any_orthonormal_vector();
    let w = n.cross(u);
    let count = 2000;
    (0..count)
        .map(|i| {
            let r = within * ((i as f64 + 0.5) / count as f64).sqrt();
            let a = i as f64 * 2.399_963_229_728_653;
            (n * offset + u * (r * a.cos()) + w * (r * a.sin())).as_vec3()
        })
        .collect()
}

/// The fraction of `points` within `within` of the mesh's triangles.
fn covered(g: &Geometry, points: &[Vec3], within: f64) -> f64 {
    let tris: Vec<[u32; 3]> = (0..g.num_prims())
        .map(|p| {
            let v = g.prim_points(p);
            [v[0], v[1], v[2]]
        })
        .collect();
    let bvh = ops::TriangleBvh::new(g.positions(), &tris);
    let near = points
        .iter()
        .filter(|&&p| {
            let hit = bvh.closest(p, f32::INFINITY).unwrap();
            (hit.dist2.sqrt() as f64) <= within
        })
        .count();
    near as f64 / points.len() as f64
}

#[test]
fn a_plate_thinner_than_a_cell_is_meshed_on_both_sides_at_any_orientation() {
    let mut rng = Rng(0x7417);
    let thickness = 0.3 * cell();
    for case in 0..20 {
        let n = normal(&mut rng);
        let shift = (rng.next() - 0.5) * cell();
        let (g, stats) = mesh(&plate(n, thickness, shift));
        let report = g.topology().manifold_report(&g);
        assert!(report.is_closed_manifold(), "case {case}: {report:?}");
        // A slab through a ball: the cross-sections' areas over the thickness.
        let exact = std::f64::consts::PI
            * (RADIUS * RADIUS - shift * shift - thickness * thickness / 12.0)
            * thickness;
        let volume = ops::signed_volume(&g) as f64;
        // Each face of the plate, away from its rim, lies on the mesh.
        let sides = [-0.5, 0.5].map(|s| {
            let points = disc_points(n, shift + s * thickness, RADIUS - 2.0 * cell());
            covered(&g, &points, 0.05 * cell())
        });
        eprintln!(
            "case {case} n {n:.3?}: volume {:.3} of exact, faces covered {sides:.3?}, {} thin cells",
            volume / exact,
            stats.thin_cells
        );
        assert!(
            (volume - exact).abs() <= 0.1 * exact,
            "case {case}: volume {volume} vs {exact}"
        );
        assert!(sides.iter().all(|&s| s >= 0.99), "case {case}: {sides:?}");
        assert_eq!(stats.thin_cells, 0, "case {case}: {:?}", stats.thin_region);
    }
}

/// A slot thinner than a cell cut through a ball: both walls meshed, the
/// slot's volume missing from the ball's.
#[test]
fn a_slot_thinner_than_a_cell_is_cut_through() {
    let mut rng = Rng(0x7419);
    for case in 0..4 {
        let n = normal(&mut rng);
        let width = 0.3 * cell();
        let slot = plate(n, width, 0.0);
        let solid = sphere([0.0; 3], 0.5).min(-slot);
        let (g, stats) = mesh(&solid);
        let report = g.topology().manifold_report(&g);
        assert!(report.is_closed_manifold(), "case {case}: {report:?}");
        let ball = 4.0 / 3.0 * std::f64::consts::PI * 0.125;
        let cut = std::f64::consts::PI * 0.25 * width;
        let volume = ops::signed_volume(&g) as f64;
        eprintln!(
            "slot {case}: removed {:.3} of the slot's volume, {} thin cells",
            (ball - volume) / cut,
            stats.thin_cells
        );
        assert!(
            ((ball - volume) - cut).abs() <= 0.15 * cut,
            "case {case}: the ball keeps {volume} of {ball}, the slot is {cut}"
        );
        let walls = [-0.5, 0.5].map(|s| {
            covered(
                &g,
                &disc_points(n, s * width, 0.5 - 2.0 * cell()),
                0.05 * cell(),
            )
        });
        assert!(walls.iter().all(|&w| w >= 0.99), "case {case}: {walls:?}");
    }
}

/// A speck thinner than a cell that no grid edge passes through cannot be
/// meshed at this resolution: it is reported (cells and region), not lost
/// in silence.
#[test]
fn a_speck_inside_a_cell_is_reported() {
    // A ball of radius 0.3 cell at the centre of a cell: every corner and
    // every edge of the cell lies outside it.
    let h = cell();
    let centre = [0.5 * h, 0.5 * h, 0.5 * h].map(|x| x - HALF - h + 33.0 * h);
    let (g, stats) = mesh(&sphere(centre, 0.3 * h));
    assert_eq!(g.num_prims(), 0);
    assert!(stats.thin_cells > 0, "{stats:?}");
    let (lo, hi) = stats.thin_region.unwrap();
    for a in 0..3 {
        assert!(lo[a] <= centre[a] && centre[a] <= hi[a], "{lo:?} {hi:?}");
    }
}

/// Solids whose walls are thicker than two cells report nothing: the
/// probes find no surface the corners miss.
#[test]
fn thick_solids_report_nothing() {
    let mut rng = Rng(0x7418);
    let mut solids = vec![
        sphere([0.1, -0.05, 0.0], 0.5),
        (Field::x() * 9.0).sin() * (Field::y() * 9.0).cos()
            + (Field::y() * 9.0).sin() * (Field::z() * 9.0).cos()
            + (Field::z() * 9.0).sin() * (Field::x() * 9.0).cos(),
    ];
    for _ in 0..4 {
        let n = normal(&mut rng);
        solids.push(plate(n, 3.0 * cell(), 0.0));
        let r = rng.rotation();
        let rotated = block([0.0; 3], [0.4, 0.3, 0.2]).affine_inverse(r, [0.0; 3]);
        solids.push(rotated);
    }
    for (i, f) in solids.iter().enumerate() {
        let (_, stats) = mesh(f);
        assert_eq!(stats.thin_cells, 0, "solid {i}: {:?}", stats.thin_region);
    }
}
