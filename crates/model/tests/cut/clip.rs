//! `clip` against trimesh, manifold3d's plane trim and closed forms: caps,
//! interpolated attributes, split pieces and polylines.

use super::*;

#[test]
fn a_cube_clipped_below_with_a_cap_is_closed_with_volume_0_8() {
    let cube = primitives::cube(1.0);
    for cap in [Cap::Triangles, Cap::Polygon] {
        let g = clip_z(&cube, 0.3, Keep::Below, cap);
        assert_eq!(euler_and_closed(&g), (2, true), "{cap:?}");
        assert!((volume(&g) - 0.8).abs() < 1e-6, "{cap:?}: {}", volume(&g));
        let Some(t) = trimesh(&g) else { return };
        closed_and_wound(&t, "clipped cube");
        assert!((f(&t, "volume") - 0.8).abs() < 1e-5, "{}", t["volume"]);
    }
}

/// manifold3d's trim of the same triangles by the same plane.
const MANIFOLD_TRIM: &str = r#"
import sys, json, numpy as np, manifold3d
d = json.load(sys.stdin)
mesh = manifold3d.Mesh(vert_properties=np.array(d['v'], dtype=np.float32), tri_verts=np.array(d['f'], dtype=np.uint32))
m = manifold3d.Manifold(mesh)
whole = m.volume()
r = m.trim_by_plane(d['normal'], d['offset'])
print(json.dumps({'volume': r.volume(), 'whole': whole}))
"#;

#[test]
fn a_clipped_sphere_matches_manifolds_trim_and_the_spherical_cap() {
    let sphere = sphere_triangles(96, 48);
    let n = Vec3::new(0.3, -0.5, 0.8).normalize();
    let (offset, cases) = (0.35f32, [(Keep::Above, 1.0f32), (Keep::Below, -1.0)]);
    for (keep, sign) in cases {
        let o = ClipOptions {
            normal: n,
            distance: offset,
            keep,
            cap: Cap::Triangles,
            ..ClipOptions::default()
        };
        let r = clip(&sphere, &o, &never).unwrap();
        assert_eq!(r.open_loops, 0);
        assert_eq!(euler_and_closed(&r.geometry), (2, true));
        let ours = volume(&r.geometry);
        // The analytic cap of the unit sphere, to mesh tolerance.
        let h = if sign > 0.0 {
            1.0 - offset
        } else {
            1.0 + offset
        } as f64;
        let cap = std::f64::consts::PI * h * h * (3.0 - h) / 3.0;
        assert!((ours - cap).abs() / cap < 0.01, "{ours} vs {cap}");
        let mut input = mesh_json(&sphere);
        input["normal"] = json!((n * sign).to_array());
        input["offset"] = json!(offset * sign);
        let Some(m) = oracle(MANIFOLD_TRIM, &input) else {
            return;
        };
        assert!(
            (ours - f(&m, "volume")).abs() < 1e-5,
            "{keep:?}: {ours} vs manifold {}",
            m["volume"]
        );
        let t = trimesh(&r.geometry).unwrap();
        closed_and_wound(&t, "clipped sphere");
        assert!((f(&t, "volume") - f(&m, "volume")).abs() < 1e-5);
    }
}

#[test]
fn cut_points_interpolate_attributes_and_faces_keep_theirs() {
    let mut g = sphere_triangles(40, 20);
    let z: Vec<f32> = g.positions().iter().map(|p| p.z).collect();
    g.set_attrib(
        AttribClass::Point,
        "h",
        Attribute::from_data(AttribData::Float(z), TypeInfo::None),
    )
    .unwrap();
    let ids: Vec<i32> = (0..g.num_prims() as i32).collect();
    g.set_attrib(
        AttribClass::Primitive,
        "id",
        Attribute::from_data(AttribData::Int(ids), TypeInfo::None),
    )
    .unwrap();
    let first_half = Group::from_flags((0..g.num_prims()).map(|p| p < g.num_prims() / 2));
    g.set_prim_group("first", first_half).unwrap();
    let r = clip_z(&g, 0.123, Keep::Above, Cap::Polygon);
    let h = r.attrib(AttribClass::Point, "h").unwrap().as_f32().unwrap();
    for (p, h) in r.positions().iter().zip(h) {
        assert!((p.z - h).abs() < 1e-5, "{} vs {h}", p.z);
    }
    assert!(r.positions().iter().any(|p| (p.z - 0.123).abs() < 1e-6));
    // Each piece lies inside its source triangle's z range.
    let id = r
        .attrib(AttribClass::Primitive, "id")
        .unwrap()
        .as_i32()
        .unwrap();
    let caps = &r.prim_groups()["cap"];
    for (prim, &source) in id.iter().enumerate() {
        if caps.contains(prim) {
            continue;
        }
        let src = g.prim_points(source as usize);
        let lo = src
            .iter()
            .map(|&p| g.positions()[p as usize].z)
            .fold(f32::MAX, f32::min);
        for &p in r.prim_points(prim) {
            assert!(r.positions()[p as usize].z >= lo - 1e-6);
        }
        assert_eq!(
            r.prim_groups()["first"].contains(prim),
            (source as usize) < g.num_prims() / 2
        );
    }
    assert!(caps.count() == 1 && !r.prim_groups()["first"].contains(r.num_prims() - 1));
}

#[test]
fn a_torus_cut_through_its_ring_gets_annulus_caps() {
    let torus = ops::triangulate(&primitives::torus(1.0, 0.3, 48, 24), None);
    let o = ClipOptions {
        normal: Vec3::new(0.1, 1.0, 0.05).normalize(),
        distance: 0.05,
        keep: Keep::Above,
        cap: Cap::Triangles,
        ..ClipOptions::default()
    };
    let r = clip(&torus, &o, &never).unwrap();
    assert_eq!(r.open_loops, 0);
    // Genus one: the annulus cap keeps the torus's hole.
    assert_eq!(euler_and_closed(&r.geometry), (0, true));
    let mut input = mesh_json(&torus);
    input["normal"] = json!(o.normal.to_array());
    input["offset"] = json!(0.05);
    let Some(m) = oracle(MANIFOLD_TRIM, &input) else {
        return;
    };
    assert!((volume(&r.geometry) - f(&m, "volume")).abs() < 1e-5);
    closed_and_wound(&trimesh(&r.geometry).unwrap(), "clipped torus");
}

#[test]
fn both_sides_with_split_points_are_two_closed_solids() {
    let sphere = sphere_triangles(32, 16);
    let o = ClipOptions {
        normal: Vec3::new(1.0, 1.0, 0.0),
        distance: -0.2,
        keep: Keep::Both,
        cap: Cap::Triangles,
        split_points: true,
        ..ClipOptions::default()
    };
    let g = clip(&sphere, &o, &never).unwrap().geometry;
    assert!((volume(&g) - volume(&sphere)).abs() < 1e-5);
    let above = &g.prim_groups()["above"];
    let below = &g.prim_groups()["below"];
    assert_eq!(above.count() + below.count(), g.num_prims());
    for side in [above, below] {
        let mut part = g.clone();
        let other = Group::from_flags((0..g.num_prims()).map(|p| !side.contains(p)));
        ops::delete_prims(&mut part, &other, true);
        assert_eq!(euler_and_closed(&part), (2, true));
    }
    let Some(t) = trimesh(&g) else { return };
    closed_and_wound(&t, "both halves");
    // Shared cut points instead: the cut edges have four faces.
    let shared = ClipOptions {
        split_points: false,
        ..o
    };
    let one = clip(&sphere, &shared, &never).unwrap().geometry;
    assert!(!euler_and_closed(&one).1);
    assert!(one.num_points() < g.num_points());
}

#[test]
fn a_comb_polygon_splits_into_one_piece_per_tooth() {
    // A comb in the XY plane: a spine along y in [0, 1], three teeth up
    // to y = 3; area 2*... = 7 + 3*2*... see below.
    let pts: Vec<Vec3> = [
        (0., 0.),
        (5., 0.),
        (5., 3.),
        (4., 3.),
        (4., 1.),
        (3., 1.),
        (3., 3.),
        (2., 3.),
        (2., 1.),
        (1., 1.),
        (1., 3.),
        (0., 3.),
    ]
    .iter()
    .map(|&(x, y)| Vec3::new(x, y, 0.0))
    .collect();
    let g = Geometry::from_polygons(pts, (0..12).collect(), &[12]).unwrap();
    let o = ClipOptions {
        normal: Vec3::Y,
        distance: 2.0,
        keep: Keep::Both,
        ..ClipOptions::default()
    };
    let r = clip(&g, &o, &never).unwrap().geometry;
    let above = &r.prim_groups()["above"];
    assert_eq!(above.count(), 3, "three teeth above");
    assert_eq!(r.num_prims(), 4);
    let mut areas = [0.0f32; 2];
    for prim in 0..r.num_prims() {
        areas[above.contains(prim) as usize] += polygon_area(&r, prim);
        if above.contains(prim) {
            assert!((polygon_area(&r, prim) - 1.0).abs() < 1e-6);
        }
    }
    assert!((areas[1] - 3.0).abs() < 1e-5 && (areas[0] - 8.0).abs() < 1e-5);
}

#[test]
fn polylines_split_into_their_runs() {
    let mut g = Geometry::new();
    let pts: Vec<Vec3> = (0..=8)
        .map(|i| Vec3::new(i as f32, (i as f32 * 1.3).sin(), 0.0))
        .collect();
    g.add_points(&pts);
    g.add_polyline(&(0..=8).collect::<Vec<u32>>()).unwrap();
    let r = clip(
        &g,
        &ClipOptions {
            normal: Vec3::Y,
            ..ClipOptions::default()
        },
        &never,
    )
    .unwrap()
    .geometry;
    // sin(1.3 i) > 0 for i = 1, 2 | 5, 6, 7: two runs, ends on the plane.
    assert_eq!(r.num_prims(), 2);
    for prim in 0..2 {
        let q = r.prim_points(prim);
        for end in [q[0], q[q.len() - 1]] {
            assert!(r.positions()[end as usize].y.abs() < 1e-6);
        }
    }
}

// ----- mirror -----

#[test]
fn a_plane_through_a_row_of_points_caps_from_the_existing_edges() {
    // The box's points at z = 0 lie on the plane: no edge is cut, the
    // cap's loop is made of edges the mesh already has.
    let cube = primitives::box_mesh(Vec3::ONE, [2, 2, 2]);
    for keep in [Keep::Below, Keep::Above] {
        let g = clip_z(&cube, 0.0, keep, Cap::Triangles);
        assert_eq!(euler_and_closed(&g), (2, true), "{keep:?}");
        assert!((volume(&g) - 0.5).abs() < 1e-6);
        assert_eq!(g.num_points(), 9 + 8, "no new point");
    }
    // A plane holding a whole face: the face bounds what is below it.
    let g = clip_z(&cube, 0.5, Keep::Below, Cap::Triangles);
    assert_eq!(g.num_prims(), cube.num_prims(), "nothing to cap");
    assert!(clip_z(&cube, 0.5, Keep::Above, Cap::Triangles).num_prims() == 0);
}
