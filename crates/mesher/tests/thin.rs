//! Thin features: a plate thinner than a cell, at seeded random
//! orientations, is either meshed to within 10% of its volume or reported
//! (cells and region); solids whose features are larger than a cell report
//! nothing.

mod common;

use common::Rng;
use geode_frep::shapes::{block, sphere};
use geode_frep::Field;
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

/// A disc-shaped plate `thickness` thick, radius 0.6, normal `n`, offset
/// from the origin by `shift` along it.
fn plate(n: [f64; 3], thickness: f64, shift: f64) -> Field {
    let (x, y, z) = (Field::x(), Field::y(), Field::z());
    let along = &x * n[0] + &y * n[1] + &z * n[2] - shift;
    let slab = thickness * 0.5 - along.abs();
    slab.min(sphere([0.0; 3], 0.6))
}

fn normal(rng: &mut Rng) -> [f64; 3] {
    rng.rotation()[2]
}

#[test]
fn a_plate_thinner_than_a_cell_is_meshed_or_reported() {
    let mut rng = Rng(0x7417);
    let thickness = 0.3 * cell();
    let exact = std::f64::consts::PI * 0.36 * thickness;
    let mut reported = 0;
    for _ in 0..8 {
        let n = normal(&mut rng);
        let shift = (rng.next() - 0.5) * cell();
        let (g, stats) = mesh(&plate(n, thickness, shift));
        let volume = ops::signed_volume(&g) as f64;
        let close = (volume - exact).abs() <= 0.1 * exact;
        eprintln!(
            "n {n:.3?}: volume {:.3} of exact, {} thin cells",
            volume / exact,
            stats.thin_cells
        );
        if stats.thin_cells > 0 {
            reported += 1;
            // The region lies on the plate's disc.
            let (lo, hi) = stats.thin_region.unwrap();
            for a in 0..3 {
                assert!(
                    lo[a] >= -0.6 - cell() && hi[a] <= 0.6 + cell(),
                    "{lo:?} {hi:?}"
                );
            }
        }
        assert!(
            close || stats.thin_cells > 0,
            "n {n:?}: volume {volume} vs {exact}, not reported"
        );
    }
    assert!(reported > 0);
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

/// A gap thinner than a cell (a slot cut through a block) is reported too.
#[test]
fn a_thin_gap_is_reported() {
    let mut rng = Rng(0x7419);
    let n = normal(&mut rng);
    let slot = plate(n, 0.3 * cell(), 0.0);
    let solid = sphere([0.0; 3], 0.5).min(-slot);
    let (_, stats) = mesh(&solid);
    assert!(stats.thin_cells > 0);
}
