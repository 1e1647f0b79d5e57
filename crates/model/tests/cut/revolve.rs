//! `revolve`: exact areas, closed spheres and capped partial revolutions,
//! attributes and uv turned with their step.

use super::*;

fn revolved(g: &Geometry, end: f32, divisions: u32) -> Geometry {
    let o = RevolveOptions {
        end_angle: end,
        divisions,
        ..RevolveOptions::default()
    };
    revolve(g, &o, &never).unwrap()
}

#[test]
fn a_revolved_segment_is_a_prism_of_the_exact_area() {
    let (r, h, d) = (0.7f64, 1.5f64, 24u32);
    let side = 2.0 * r * (std::f64::consts::PI / d as f64).sin();
    let tube = revolved(&curve(&[(0.7, 0.0), (0.7, 1.5)], false), 360.0, d);
    assert_eq!(
        (tube.num_points(), tube.num_prims()),
        (2 * d as usize, d as usize)
    );
    let Some(t) = trimesh(&tube) else { return };
    assert!((f(&t, "area") - d as f64 * side * h).abs() < 1e-5);
    // With its ends run in to the axis: a closed prism.
    let can = revolved(
        &curve(&[(0.0, 0.0), (0.7, 0.0), (0.7, 1.5), (0.0, 1.5)], false),
        360.0,
        d,
    );
    assert_eq!(can.num_points(), 2 * d as usize + 2);
    let t = trimesh(&can).unwrap();
    closed_and_wound(&t, "revolved can");
    let base = 0.5 * d as f64 * r * r * (2.0 * std::f64::consts::PI / d as f64).sin();
    assert!((f(&t, "volume") - base * h).abs() < 1e-5, "{}", t["volume"]);
    assert!((f(&t, "area") - (d as f64 * side * h + 2.0 * base)).abs() < 1e-5);
}

#[test]
fn a_half_circle_with_its_ends_on_the_axis_is_a_closed_sphere() {
    let half: Vec<(f32, f32)> = (0..=16)
        .map(|i| {
            let a = std::f32::consts::PI * (i as f32 / 16.0 - 0.5);
            (a.cos(), a.sin())
        })
        .collect();
    let g = revolved(&curve(&half, false), 360.0, 32);
    assert_eq!(g.num_points(), 15 * 32 + 2);
    assert!(g.topology().manifold_report(&g).is_closed_manifold());
    let Some(t) = trimesh(&g) else { return };
    closed_and_wound(&t, "revolved sphere");
    assert!(f(&t, "min_face_area") > 1e-4, "a degenerate face");
    let exact = 4.0 / 3.0 * std::f64::consts::PI;
    assert!((f(&t, "volume") - exact).abs() / exact < 0.03);
}

#[test]
fn a_partial_revolution_of_a_closed_profile_is_capped_and_closed() {
    let square = curve(&[(1.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0)], true);
    for (end, d) in [(90.0f32, 6u32), (-120.0, 5)] {
        let g = revolved(&square, end, d);
        assert_eq!(euler_and_closed(&g), (2, true), "{end}");
        let alpha = (end as f64).abs().to_radians();
        let exact = 0.5 * d as f64 * (4.0 - 1.0) * (alpha / d as f64).sin();
        assert!(
            (volume(&g) - exact).abs() < 1e-5,
            "{end}: {} vs {exact}",
            volume(&g)
        );
        if let Some(t) = trimesh(&g) {
            closed_and_wound(&t, "capped sector");
        }
    }
    let ring = revolved(&square, 360.0, 12);
    assert_eq!(euler_and_closed(&ring), (0, true), "a full turn: a torus");
}

#[test]
fn revolved_attributes_turn_with_their_step_and_uv_runs_along() {
    let mut g = curve(&[(1.0, 0.0), (1.0, 1.0)], false);
    g.set_attrib(
        AttribClass::Point,
        "N",
        Attribute::from_data(AttribData::Vec3(vec![Vec3::X; 2]), TypeInfo::Normal),
    )
    .unwrap();
    let o = RevolveOptions {
        divisions: 8,
        uv: true,
        ..RevolveOptions::default()
    };
    let r = revolve(&g, &o, &never).unwrap();
    let n = r
        .attrib(AttribClass::Point, "N")
        .unwrap()
        .as_vec3()
        .unwrap();
    for (p, n) in r.positions().iter().zip(n) {
        assert!(
            (Vec3::new(p.x, 0.0, p.z) - *n).length() < 1e-5,
            "N follows the surface"
        );
    }
    let uv = r
        .attrib(AttribClass::Vertex, "uv")
        .unwrap()
        .as_vec2()
        .unwrap();
    assert_eq!(uv[0], Vec2::new(0.0, 0.0));
    assert!(uv.iter().any(|t| *t == Vec2::new(1.0, 1.0)));
}

// ----- degenerate inputs, threads, cancellation -----
