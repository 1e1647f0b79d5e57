//! Projections against hand-worked values: planar, cylindrical, spherical
//! and box, through frames, with the uv transform, and seam continuity.

use std::f32::consts::FRAC_1_SQRT_2;

use geode_geo::glam::{Mat4, Vec2, Vec3};
use geode_geo::{primitives, Geometry, PrimKind};
use geode_uv::{
    frame_from_trs, project, write_uv, Axis, ProjectOptions, Projection, UvError, UvTransform,
};

/// Polylines of two vertices over consecutive pairs of points.
fn points(ps: &[Vec3]) -> Geometry {
    assert!(ps.len().is_multiple_of(2));
    let n = ps.len() as u32;
    let counts = vec![2; ps.len() / 2];
    let kinds = vec![PrimKind::Polyline; counts.len()];
    Geometry::from_prims(ps.to_vec(), (0..n).collect(), &counts, kinds).unwrap()
}

fn run(g: &Geometry, projection: Projection, frame: Mat4) -> Vec<Vec2> {
    let options = ProjectOptions {
        projection,
        frame,
        transform: UvTransform::default(),
    };
    project(g, &options)
        .unwrap()
        .iter()
        .map(|t| {
            assert_eq!(t.z, 0.0);
            Vec2::new(t.x, t.y)
        })
        .collect()
}

fn close(a: Vec2, b: Vec2) -> bool {
    (a - b).abs().max_element() < 1e-5
}

#[test]
fn planar_along_each_axis() {
    let g = points(&[Vec3::new(0.2, -0.3, 0.4), Vec3::new(-0.5, 0.5, 0.1)]);
    let z = run(&g, Projection::Planar { axis: Axis::Z }, Mat4::IDENTITY);
    assert!(close(z[0], Vec2::new(0.7, 0.2)), "{z:?}");
    assert!(close(z[1], Vec2::new(0.0, 1.0)));
    let x = run(&g, Projection::Planar { axis: Axis::X }, Mat4::IDENTITY);
    assert!(close(x[0], Vec2::new(0.1, 0.2)), "{x:?}"); // (-z, y) + 0.5
    let y = run(&g, Projection::Planar { axis: Axis::Y }, Mat4::IDENTITY);
    assert!(close(y[0], Vec2::new(0.7, 0.1)), "{y:?}"); // (x, -z) + 0.5
}

#[test]
fn planar_through_a_frame() {
    // A frame at (1, 2, 3), turned 90 degrees about Z, twice as large:
    // world (1, 3, 3) is frame (0.5, 0, 0): u = 1.0, v = 0.5.
    let frame = frame_from_trs(
        Vec3::new(1.0, 2.0, 3.0),
        Vec3::new(0.0, 0.0, 90.0),
        Vec3::splat(2.0),
    );
    let g = points(&[Vec3::new(1.0, 3.0, 3.0), Vec3::new(0.0, 2.0, 3.0)]);
    let uv = run(&g, Projection::Planar { axis: Axis::Z }, frame);
    assert!(close(uv[0], Vec2::new(1.0, 0.5)), "{uv:?}");
    // World (0, 2, 3) is frame (0, 0.5, 0).
    assert!(close(uv[1], Vec2::new(0.5, 1.0)), "{uv:?}");
    let singular = ProjectOptions {
        frame: Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0)),
        ..ProjectOptions::default()
    };
    assert!(matches!(project(&g, &singular), Err(UvError::Invalid(_))));
}

#[test]
fn cylindrical_angles_and_heights() {
    let g = points(&[
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 0.25, -2.0),
        Vec3::new(-3.0, -0.5, 0.0),
        Vec3::new(FRAC_1_SQRT_2, 0.1, FRAC_1_SQRT_2),
    ]);
    let uv = run(
        &g,
        Projection::Cylindrical { axis: Axis::Y },
        Mat4::IDENTITY,
    );
    // Each polyline is unwrapped: the second vertex within half a turn of
    // the first.
    assert!(close(uv[0], Vec2::new(0.0, 0.5)), "{uv:?}");
    assert!(close(uv[1], Vec2::new(0.25, 0.75)), "{uv:?}");
    assert!(close(uv[2], Vec2::new(0.5, 0.0)), "{uv:?}");
    // 315 degrees, unwrapped next to 0.5: 0.875.
    assert!(close(uv[3], Vec2::new(0.875, 0.6)), "{uv:?}");
    // About X: the angle is measured in the (z, y) plane, height along x.
    let gx = points(&[Vec3::new(0.3, 0.0, 1.0), Vec3::new(0.3, -1.0, 0.0)]);
    let ux = run(
        &gx,
        Projection::Cylindrical { axis: Axis::X },
        Mat4::IDENTITY,
    );
    assert!(close(ux[0], Vec2::new(0.0, 0.8)), "{ux:?}");
    assert!(close(ux[1], Vec2::new(0.25, 0.8)), "{ux:?}");
}

#[test]
fn spherical_latitude_and_longitude() {
    let s = 0.5f32.sqrt();
    let g = points(&[
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(0.0, s, -s),
        Vec3::new(0.0, -1.0, 0.0),
        Vec3::new(-1.0, 0.0, 0.0),
    ]);
    let uv = run(&g, Projection::Spherical { axis: Axis::Y }, Mat4::IDENTITY);
    assert!(close(uv[0], Vec2::new(0.0, 0.5)), "{uv:?}");
    assert!(close(uv[1], Vec2::new(0.25, 0.75)), "{uv:?}");
    // The south pole takes its polyline partner's u.
    assert!(close(uv[2], Vec2::new(0.5, 0.0)), "{uv:?}");
    assert!(close(uv[3], Vec2::new(0.5, 0.5)), "{uv:?}");
}

#[test]
fn box_projects_each_polygon_along_its_normal() {
    let g = primitives::cube(1.0);
    let uv = run(&g, Projection::Box, Mat4::IDENTITY);
    let p = g.positions();
    for prim in 0..g.num_prims() {
        let pts = g.prim_points(prim);
        let normal = (p[pts[1] as usize] - p[pts[0] as usize])
            .cross(p[pts[2] as usize] - p[pts[0] as usize]);
        for (k, v) in g.prim_vertex_range(prim).enumerate() {
            let q = p[pts[k] as usize];
            let expect = if normal.x > 0.5 * normal.length() {
                Vec2::new(-q.z, q.y)
            } else if normal.x < -0.5 * normal.length() {
                Vec2::new(q.z, q.y)
            } else if normal.y > 0.5 * normal.length() {
                Vec2::new(q.x, -q.z)
            } else if normal.y < -0.5 * normal.length() {
                Vec2::new(q.x, q.z)
            } else if normal.z > 0.0 {
                Vec2::new(q.x, q.y)
            } else {
                Vec2::new(-q.x, q.y)
            } + Vec2::splat(0.5);
            assert!(
                close(uv[v], expect),
                "prim {prim}: {:?} vs {expect:?}",
                uv[v]
            );
        }
        // Seen from outside, every face keeps its winding in uv.
        let r = g.prim_vertex_range(prim);
        let (a, b, c) = (uv[r.start], uv[r.start + 1], uv[r.start + 2]);
        assert!((b - a).perp_dot(c - a) > 0.0, "face {prim} mirrored");
    }
}

#[test]
fn uv_transform_scales_rotates_and_offsets() {
    let t = UvTransform {
        scale: Vec2::new(2.0, 3.0),
        rotate_degrees: 90.0,
        offset: Vec2::new(0.5, -1.0),
    };
    // (1, 1) -> (2, 3) -> (-3, 2) -> (-2.5, 1).
    assert!(close(t.apply(Vec2::ONE), Vec2::new(-2.5, 1.0)));
    let g = points(&[Vec3::new(0.5, 0.5, 0.0), Vec3::ZERO]);
    let options = ProjectOptions {
        transform: t,
        ..ProjectOptions::default()
    };
    let uv = project(&g, &options).unwrap();
    assert!(
        close(Vec2::new(uv[0].x, uv[0].y), Vec2::new(-2.5, 1.0)),
        "{uv:?}"
    );
}

/// Cylindrical and spherical projections of a tube and a sphere: every
/// polygon continuous (no polygon spans more than its share of a turn),
/// and the polygons on the seam run past u = 1 rather than back to 0.
#[test]
fn seams_do_not_smear_polygons() {
    let segments = 16;
    for (g, projection) in [
        (
            primitives::tube(1.0, 1.0, segments, 4, false),
            Projection::Cylindrical { axis: Axis::Y },
        ),
        (
            primitives::uv_sphere(1.0, segments, 8),
            Projection::Spherical { axis: Axis::Y },
        ),
    ] {
        let uv = run(&g, projection, Mat4::IDENTITY);
        let mut past_one = 0;
        for prim in 0..g.num_prims() {
            let us: Vec<f32> = g.prim_vertex_range(prim).map(|v| uv[v].x).collect();
            let span = us.iter().cloned().fold(f32::MIN, f32::max)
                - us.iter().cloned().fold(f32::MAX, f32::min);
            assert!(
                span <= 1.0 / segments as f32 + 1e-5,
                "{projection:?} prim {prim}: {us:?}"
            );
            if us.iter().any(|&u| u > 1.0 - 1e-6) {
                past_one += 1;
            }
        }
        assert!(
            past_one > 0,
            "{projection:?}: the seam column reaches u = 1"
        );
    }
    // The pole vertices sit in the middle of their triangle's u.
    let g = primitives::uv_sphere(1.0, 4, 2);
    let uv = run(&g, Projection::Spherical { axis: Axis::Y }, Mat4::IDENTITY);
    let r = g.prim_vertex_range(0);
    assert!((uv[r.start].x - 0.5 * (uv[r.start + 1].x + uv[r.start + 2].x)).abs() < 1e-6);
    assert!((uv[r.start].y - 1.0).abs() < 1e-6);
}

#[test]
fn written_as_the_vertex_attribute() {
    let mut g = primitives::grid(Vec2::ONE, 2, 2);
    let uv = project(&g, &ProjectOptions::default()).unwrap();
    write_uv(&mut g, geode_uv::UV, uv.clone()).unwrap();
    let column = g
        .attrib(geode_geo::AttribClass::Vertex, "uv")
        .and_then(|a| a.as_vec3().map(|v| v.to_vec()));
    assert_eq!(column, Some(uv));
    assert!(write_uv(&mut g, "uv", vec![Vec3::ZERO]).is_err());
}
