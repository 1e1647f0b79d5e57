//! Measures against closed forms: areas, perimeters and volumes of boxes
//! and spheres, mean and Gaussian curvature on a sphere and on a torus
//! (K = cos v / (r (R + r cos v)), H = (R + 2 r cos v) / (2 r (R + r cos v))).

use geode_attrib::measure::{curvature, per_piece, prim_areas, prim_perimeters, prim_volumes};
use geode_geo::glam::Vec3;
use geode_geo::ops::{connectivity, merge, Connect};
use geode_geo::primitives::{box_mesh, torus, uv_sphere};

const NONE: &(dyn Fn() -> bool + Sync) = &|| false;

#[test]
fn box_areas_perimeters_and_volume() {
    let b = box_mesh(Vec3::new(1.0, 2.0, 3.0), [1, 1, 1]);
    let mut areas: Vec<f32> = prim_areas(&b);
    areas.sort_by(f32::total_cmp);
    assert_eq!(areas, [2.0, 2.0, 3.0, 3.0, 6.0, 6.0]);
    let mut per: Vec<f32> = prim_perimeters(&b);
    per.sort_by(f32::total_cmp);
    assert_eq!(per, [6.0, 6.0, 8.0, 8.0, 10.0, 10.0]);
    let v: f64 = prim_volumes(&b).iter().sum();
    assert!((v - 6.0).abs() < 1e-9, "{v}");
}

#[test]
fn per_piece_volumes_of_merged_solids() {
    let a = box_mesh(Vec3::ONE, [2, 2, 2]);
    let mut s = uv_sphere(1.0, 64, 32);
    for p in s.positions_mut() {
        *p += Vec3::X * 5.0;
    }
    let g = merge(&[&a, &s]).unwrap();
    let pieces = connectivity(&g, Connect::SharedEdge, None);
    let v = per_piece(&prim_volumes(&g), &pieces.of_prim);
    assert!((v[0] - 1.0).abs() < 1e-6);
    // A 64x32 UV sphere's inscribed volume: within 0.5% of 4/3 pi.
    let sphere = *v.last().unwrap();
    assert!(
        (sphere / (4.0 / 3.0 * std::f64::consts::PI) - 1.0).abs() < 0.005,
        "{sphere}"
    );
}

#[test]
fn sphere_curvature_is_one_over_r() {
    let r = 2.0f32;
    let s = uv_sphere(r, 128, 64);
    let c = curvature(&s, NONE).unwrap();
    let p = s.positions();
    let mut checked = 0;
    for (i, q) in p.iter().enumerate() {
        // Away from the poles' fans.
        if (q.y / r).abs() > 0.95 {
            continue;
        }
        assert!(
            (c.mean[i] - 1.0 / r).abs() < 0.01 / r,
            "H at {i}: {}",
            c.mean[i]
        );
        assert!(
            (c.gaussian[i] - 1.0 / (r * r)).abs() < 0.02 / (r * r),
            "K at {i}: {}",
            c.gaussian[i]
        );
        checked += 1;
    }
    assert!(checked > 6000);
}

#[test]
fn torus_curvature_matches_the_closed_form() {
    let (big, small) = (2.0f64, 0.5f64);
    let t = torus(big as f32, small as f32, 256, 96);
    let c = curvature(&t, NONE).unwrap();
    let mut worst_h = 0.0f64;
    let mut worst_k = 0.0f64;
    for (i, q) in t.positions().iter().enumerate() {
        let rho = (f64::from(q.x).powi(2) + f64::from(q.z).powi(2)).sqrt();
        let cos_v = ((rho - big) / small).clamp(-1.0, 1.0);
        let k = cos_v / (small * (big + small * cos_v));
        let h = (big + 2.0 * small * cos_v) / (2.0 * small * (big + small * cos_v));
        worst_h = worst_h.max((f64::from(c.mean[i]) - h).abs() / h.abs());
        worst_k = worst_k.max((f64::from(c.gaussian[i]) - k).abs());
    }
    // K ranges over [-0.67, 0.4]; H over [0.67, 1.2].
    assert!(worst_h < 0.01, "mean curvature off by {worst_h}");
    assert!(worst_k < 0.01, "Gaussian curvature off by {worst_k}");
}

#[test]
fn curvature_is_cancellable() {
    assert!(curvature(&uv_sphere(1.0, 16, 8), &|| true).is_err());
}
