//! `mirror` with fuse: closed results, normals outward.

use super::*;

#[test]
fn half_a_box_mirrored_with_fuse_is_the_closed_box() {
    let cube = primitives::box_mesh(Vec3::ONE, [2, 2, 2]);
    let half = clip(
        &cube,
        &ClipOptions {
            normal: Vec3::X,
            ..ClipOptions::default()
        },
        &never,
    )
    .unwrap()
    .geometry;
    assert!(!euler_and_closed(&half).1);
    let m = mirror(&half, &MirrorOptions::default(), &never).unwrap();
    let g = m.geometry;
    assert_eq!(euler_and_closed(&g), (2, true));
    assert_eq!(g.num_points(), cube.num_points());
    assert!(g.topology().manifold_report(&g).is_closed_manifold());
    assert!((volume(&g) - 1.0).abs() < 1e-6);
    let mirrored = &g.prim_groups()["mirror"];
    assert_eq!(mirrored.count() * 2, g.num_prims());
    let Some(t) = trimesh(&g) else { return };
    closed_and_wound(&t, "mirrored box");
    // Double the half closed by a cap.
    let capped = clip(
        &cube,
        &ClipOptions {
            normal: Vec3::X,
            cap: Cap::Polygon,
            ..ClipOptions::default()
        },
        &never,
    )
    .unwrap()
    .geometry;
    assert!((volume(&capped) - 0.5).abs() < 1e-6);
    assert!((f(&t, "volume") - 2.0 * volume(&capped)).abs() < 1e-5);
    // The capped half mirrored: its cap would be a wall inside the whole
    // (each of its edges in three faces); it goes, and the box is closed.
    let whole = mirror(&capped, &MirrorOptions::default(), &never)
        .unwrap()
        .geometry;
    assert_eq!(euler_and_closed(&whole), (2, true));
    assert!(whole
        .topology()
        .manifold_report(&whole)
        .is_closed_manifold());
    assert!((volume(&whole) - 1.0).abs() < 1e-6);
    // A sheet lying on the plane stays, once.
    let sheet = primitives::grid(Vec2::ONE, 2, 2);
    let on_plane = mirror(
        &sheet,
        &MirrorOptions {
            normal: Vec3::Y,
            ..MirrorOptions::default()
        },
        &never,
    )
    .unwrap()
    .geometry;
    assert_eq!(on_plane.num_prims(), sheet.num_prims());
}

#[test]
fn a_mirrored_half_sphere_is_the_sphere_with_normals_outward() {
    let sphere = sphere_triangles(48, 24);
    let plane = Vec3::new(0.2, 0.0, 1.0).normalize();
    let mut half = clip(
        &sphere,
        &ClipOptions {
            normal: plane,
            ..ClipOptions::default()
        },
        &never,
    )
    .unwrap()
    .geometry;
    let n = ops::point_normals(&half);
    half.set_attrib(
        AttribClass::Point,
        "N",
        Attribute::from_data(AttribData::Vec3(n), TypeInfo::Normal),
    )
    .unwrap();
    let velocity: Vec<Vec3> = half.positions().iter().map(|p| *p + Vec3::X).collect();
    half.set_attrib(
        AttribClass::Point,
        "v",
        Attribute::from_data(AttribData::Vec3(velocity), TypeInfo::Vector),
    )
    .unwrap();
    let rest = half.positions().to_vec();
    half.set_attrib(
        AttribClass::Point,
        "rest",
        Attribute::from_data(AttribData::Vec3(rest), TypeInfo::Position),
    )
    .unwrap();
    let o = MirrorOptions {
        normal: plane,
        fuse_distance: 1e-5,
        ..MirrorOptions::default()
    };
    let g = mirror(&half, &o, &never).unwrap().geometry;
    assert_eq!(euler_and_closed(&g), (2, true));
    assert!((volume(&g) - volume(&sphere)).abs() < 1e-4);
    let reflect = |x: Vec3| x - 2.0 * x.dot(plane) * plane;
    let (n, v) = (
        g.attrib(AttribClass::Point, "N")
            .unwrap()
            .as_vec3()
            .unwrap(),
        g.attrib(AttribClass::Point, "v")
            .unwrap()
            .as_vec3()
            .unwrap(),
    );
    let rest = g
        .attrib(AttribClass::Point, "rest")
        .unwrap()
        .as_vec3()
        .unwrap();
    for (i, p) in g.positions().iter().enumerate() {
        assert!(n[i].dot(*p) > 0.9, "N points out at {p}");
        assert!(
            (rest[i] - *p).length() < 2e-5,
            "rest reflects about the plane"
        );
        // Images carry reflected vectors: v = p + X before, so after the
        // reflection v = p + reflect(X) on the image's side.
        if p.dot(plane) < -1e-4 {
            assert!((v[i] - (*p + reflect(Vec3::X))).length() < 1e-5);
        }
    }
    let Some(t) = trimesh(&g) else { return };
    closed_and_wound(&t, "mirrored sphere");
    let whole = trimesh(&sphere).unwrap();
    assert!((f(&t, "volume") - f(&whole, "volume")).abs() < 1e-4);
}

// ----- polyfill -----
