//! The cut family (clip, mirror, polyfill, convex hull, revolve) against
//! answers from outside geode: trimesh (closed, wound, volume, area),
//! manifold3d (a plane trim of the same mesh), scipy (Qhull's hull) and
//! closed forms.

mod common;

use common::{euler_and_closed, mesh_json, oracle, volume};
use geode_geo::glam::{Vec2, Vec3};
use geode_geo::{ops, primitives, AttribClass, AttribData, Attribute, Geometry, Group, TypeInfo};
use geode_model::clip::{clip, Cap, ClipOptions, Keep};
use geode_model::fill::{polyfill, FillMode, FillOptions, Triangulation};
use geode_model::hull::convex_hull;
use geode_model::mirror::{mirror, MirrorOptions};
use geode_model::revolve::{revolve, RevolveOptions};
use serde_json::{json, Value};

fn never() -> bool {
    false
}

/// trimesh's view of a mesh (polygons fanned), vertices not merged.
const TRIMESH: &str = r#"
import sys, json, numpy as np, trimesh
d = json.load(sys.stdin)
m = trimesh.Trimesh(np.array(d['v'], dtype=float).reshape(-1, 3), np.array(d['f'], dtype=np.int64).reshape(-1, 3), process=False)
print(json.dumps({'watertight': bool(m.is_watertight), 'winding': bool(m.is_winding_consistent),
  'volume': float(m.volume), 'area': float(m.area),
  'min_face_area': float(m.area_faces.min()) if len(m.faces) else 0.0}))
"#;

fn trimesh(g: &Geometry) -> Option<Value> {
    oracle(TRIMESH, &mesh_json(g))
}

fn closed_and_wound(t: &Value, what: &str) {
    assert_eq!(t["watertight"], true, "{what}: not watertight");
    assert_eq!(t["winding"], true, "{what}: winding not consistent");
    assert!(t["volume"].as_f64().unwrap() > 0.0, "{what}: faces inward");
}

fn f(t: &Value, k: &str) -> f64 {
    t[k].as_f64().unwrap()
}

fn clip_z(g: &Geometry, distance: f32, keep: Keep, cap: Cap) -> Geometry {
    let o = ClipOptions {
        normal: Vec3::Z,
        distance,
        keep,
        cap,
        ..ClipOptions::default()
    };
    clip(g, &o, &never).unwrap().geometry
}

fn sphere_triangles(cols: u32, rows: u32) -> Geometry {
    ops::triangulate(&primitives::uv_sphere(1.0, cols, rows), None)
}

// ----- clip -----

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

fn polygon_area(g: &Geometry, prim: usize) -> f32 {
    let p = g.positions();
    let n = ops::polygon_normal(p, g.prim_points(prim));
    let pts = g.prim_points(prim);
    let mut a = Vec3::ZERO;
    for i in 0..pts.len() {
        a += p[pts[i] as usize].cross(p[pts[(i + 1) % pts.len()] as usize]);
    }
    a.dot(n) / 2.0
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

fn holed_sphere() -> Geometry {
    let mut g = primitives::uv_sphere(1.0, 32, 16);
    // Two holes: a patch of quads, and the north pole's fan.
    let np = g.num_prims();
    let hole = Group::from_flags(
        (0..np).map(|p| (p < 32) || (100..104).contains(&p) || (132..136).contains(&p)),
    );
    ops::delete_prims(&mut g, &hole, true);
    g
}

#[test]
fn filled_holes_close_the_sphere_in_every_mode() {
    let g = holed_sphere();
    assert_eq!(g.topology().boundary_edges().len(), 32 + 12);
    for mode in [FillMode::Triangles, FillMode::Polygon, FillMode::Fan] {
        for how in [Triangulation::MinWeight, Triangulation::EarClip] {
            let o = FillOptions {
                mode,
                triangulation: how,
                ..FillOptions::default()
            };
            let r = polyfill(&g, &o, &never).unwrap();
            assert_eq!((r.holes_filled, r.holes_skipped), (2, 0));
            let out = &r.geometry;
            assert!(
                out.topology().manifold_report(out).is_closed_manifold(),
                "{mode:?}"
            );
            assert!(volume(out) > 4.0, "{mode:?}: {}", volume(out));
            let filled = &out.prim_groups()["polyfill"];
            assert_eq!(out.num_prims() - filled.count(), g.num_prims());
            if let Some(t) = trimesh(out) {
                closed_and_wound(&t, &format!("{mode:?} {how:?}"));
            }
        }
    }
    let limited = FillOptions {
        max_points: 20,
        ..FillOptions::default()
    };
    let r = polyfill(&g, &limited, &never).unwrap();
    assert_eq!((r.holes_filled, r.holes_skipped), (1, 1));
}

#[test]
fn a_cut_torus_fills_with_ring_shaped_faces_as_clips_cap() {
    // Cut through its middle plane (the torus lies in the XZ plane): the
    // cut leaves an outer and an inner circle in one plane, and their fill
    // is a ring.
    let torus = primitives::torus(1.0, 0.4, 48, 24);
    let half = |cap| {
        let o = ClipOptions {
            normal: Vec3::Y,
            keep: Keep::Above,
            cap,
            ..ClipOptions::default()
        };
        clip(&torus, &o, &never).unwrap().geometry
    };
    let open = half(Cap::None);
    let capped = half(Cap::Triangles);
    for mode in [FillMode::Triangles, FillMode::Polygon] {
        let o = FillOptions {
            mode,
            ..FillOptions::default()
        };
        let r = polyfill(&open, &o, &never).unwrap();
        assert_eq!((r.holes_filled, r.holes_skipped), (2, 0));
        let out = &r.geometry;
        // The same solid as clip's own cap closes.
        assert!(
            (volume(out) - volume(&capped)).abs() < 1e-5,
            "{mode:?}: {} against {}",
            volume(out),
            volume(&capped)
        );
        let filled = &out.prim_groups()["polyfill"];
        let area: f32 = filled.members().map(|p| polygon_area(out, p)).sum();
        // A ring between radii 0.6 and 1.4 (polygons of 48 sides).
        let ring = |r: f32| 24.0 * r * r * (std::f32::consts::TAU / 48.0).sin();
        let want = ring(1.4) - ring(0.6);
        assert!(
            (area - want).abs() < 1e-3 * want,
            "{mode:?}: {area} against {want}"
        );
        if mode == FillMode::Triangles {
            // Half a torus along its middle plane is still a ring:
            // closed, Euler characteristic 0.
            assert_eq!(euler_and_closed(out), (0, true));
            if let Some(t) = trimesh(out) {
                closed_and_wound(&t, "filled half torus");
            }
        }
    }
    // Off, as Houdini's PolyFill: each circle gets its own disc.
    let separate = FillOptions {
        holes: false,
        ..FillOptions::default()
    };
    let out = polyfill(&open, &separate, &never).unwrap().geometry;
    let filled = &out.prim_groups()["polyfill"];
    let area: f32 = filled.members().map(|p| polygon_area(&out, p)).sum();
    let disc = |r: f32| 24.0 * r * r * (std::f32::consts::TAU / 48.0).sin();
    assert!((area - (disc(1.4) + disc(0.6))).abs() < 1e-2, "{area}");
}

#[test]
fn a_fill_never_folds_back_onto_a_face_of_the_mesh() {
    // A quarter sphere: its one loop turns a right angle at the pole,
    // around the corner of one face, whose three points are consecutive on
    // the loop. An ear there would be that face again, wound the other way.
    let sphere = primitives::uv_sphere(1.0, 32, 16);
    let cut = |g: &Geometry, normal: Vec3| {
        let o = ClipOptions {
            normal,
            cap: Cap::None,
            ..ClipOptions::default()
        };
        clip(g, &o, &never).unwrap().geometry
    };
    let quarter = cut(&cut(&sphere, Vec3::Y), Vec3::X);
    for how in [Triangulation::MinWeight, Triangulation::EarClip] {
        let o = FillOptions {
            triangulation: how,
            ..FillOptions::default()
        };
        let out = polyfill(&quarter, &o, &never).unwrap().geometry;
        let filled = &out.prim_groups()["polyfill"];
        let topo = quarter.topology();
        for f in filled.members() {
            let q = out.prim_points(f);
            let shared = topo.point_prims(q[0] as usize).iter().any(|p| {
                topo.point_prims(q[1] as usize).contains(p)
                    && topo.point_prims(q[2] as usize).contains(p)
            });
            assert!(!shared, "{how:?}: fill triangle {f} lies on a face");
        }
        let t = ops::triangulate(&out, None);
        assert_eq!(euler_and_closed(&t), (2, true), "{how:?}");
    }
}

#[test]
fn a_sheets_hole_and_border_fill_on_their_own() {
    // The hole and the grid's outline share a plane, but the grid already
    // covers the ring between them: both are filled whole.
    let mut g = primitives::grid(Vec2::new(6.0, 6.0), 6, 6);
    let hole =
        Group::from_flags((0..36).map(|q| (2..4).contains(&(q % 6)) && (2..4).contains(&(q / 6))));
    ops::delete_prims(&mut g, &hole, true);
    let r = polyfill(&g, &FillOptions::default(), &never).unwrap();
    assert_eq!(r.holes_filled, 2);
    let out = &r.geometry;
    let filled = &out.prim_groups()["polyfill"];
    let area: f32 = filled.members().map(|p| polygon_area(out, p)).sum();
    assert!((area - 40.0).abs() < 1e-4, "{area}");
}

#[test]
fn the_fill_of_a_square_hole_has_the_holes_area() {
    let mut g = primitives::grid(Vec2::new(6.0, 6.0), 6, 6);
    // The 2x2 block of quads in the middle (columns and rows 2 and 3).
    let hole =
        Group::from_flags((0..36).map(|q| (2..4).contains(&(q % 6)) && (2..4).contains(&(q / 6))));
    ops::delete_prims(&mut g, &hole, true);
    for mode in [FillMode::Triangles, FillMode::Polygon, FillMode::Fan] {
        for how in [Triangulation::MinWeight, Triangulation::EarClip] {
            // The grid's outline is a loop too (24 points): left open.
            let o = FillOptions {
                mode,
                triangulation: how,
                max_points: 8,
                ..FillOptions::default()
            };
            let r = polyfill(&g, &o, &never).unwrap().geometry;
            let filled = &r.prim_groups()["polyfill"];
            let area: f32 = filled.members().map(|p| polygon_area(&r, p)).sum();
            // The grid faces +Y and so do the fills.
            assert!((area - 4.0).abs() < 1e-5, "{mode:?} {how:?}: {area}");
            for p in filled.members() {
                let n = ops::polygon_normal(r.positions(), r.prim_points(p));
                assert!(n.y > 0.999, "{mode:?}: {n}");
                if mode == FillMode::Triangles {
                    assert!(polygon_area(&r, p) > 0.1, "a sliver");
                }
            }
            let uv = r
                .attrib(AttribClass::Point, "uv")
                .unwrap()
                .as_vec2()
                .unwrap();
            if mode == FillMode::Fan {
                // The centre's uv is the mean of the loop's.
                assert!((uv[r.num_points() - 1] - Vec2::new(0.5, 0.5)).length() < 1e-6);
            }
        }
    }
}

// ----- convex hull -----

/// scipy's (Qhull's) hull: volume (area in 2D) and vertex positions.
const SCIPY_HULL: &str = r#"
import sys, json, numpy as np
from scipy.spatial import ConvexHull
d = json.load(sys.stdin)
p = np.array(d['p'], dtype=np.float64)
h = ConvexHull(p)
print(json.dumps({'volume': float(h.volume), 'vertices': p[h.vertices].tolist()}))
"#;

fn cloud(n: u64, seed: u64, f: impl Fn([f32; 3], u64) -> Vec3) -> Geometry {
    let pts: Vec<Vec3> = (0..n)
        .map(|i| {
            let u = [0, 1, 2].map(|c| geode_geo::random::unit(seed, i, c));
            f(u, i)
        })
        .collect();
    let mut g = Geometry::new();
    g.add_points(&pts);
    g
}

fn sorted_points(p: impl Iterator<Item = [f64; 3]>) -> Vec<[f64; 3]> {
    let mut v: Vec<[f64; 3]> = p.collect();
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v.dedup();
    v
}

fn check_hull(g: &Geometry, what: &str) {
    let h = convex_hull(g, true, &never).unwrap();
    assert_eq!(euler_and_closed(&h), (2, true), "{what}");
    assert!(
        h.topology().manifold_report(&h).is_closed_manifold(),
        "{what}"
    );
    let ours = volume(&h);
    let input = json!({"p": g.positions().iter().map(|p| p.to_array()).collect::<Vec<_>>()});
    let Some(s) = oracle(SCIPY_HULL, &input) else {
        return;
    };
    let theirs = f(&s, "volume");
    assert!(
        ((ours - theirs) / theirs).abs() < 1e-6,
        "{what}: {ours} vs {theirs}"
    );
    let qhull = sorted_points(
        s["vertices"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| [0, 1, 2].map(|k| v[k].as_f64().unwrap())),
    );
    let mine = sorted_points(h.positions().iter().map(|p| p.to_array().map(f64::from)));
    assert_eq!(mine.len(), qhull.len(), "{what}: vertex counts");
    assert_eq!(mine, qhull, "{what}: vertex sets");
    closed_and_wound(&trimesh(&h).unwrap(), what);
}

#[test]
fn hulls_of_random_clouds_match_qhull() {
    let ball = cloud(10_000, 7, |u, _| {
        let d = Vec3::new(u[0] - 0.5, u[1] - 0.5, u[2] - 0.5);
        d.normalize() * (0.9 + 0.1 * u[0])
    });
    check_hull(&ball, "sphere-ish");
    let cube = cloud(10_000, 8, |u, _| Vec3::from(u) * 2.0 - 1.0);
    check_hull(&cube, "cube-ish");
}

#[test]
fn hulls_of_degenerate_clouds_match_qhull() {
    // Points on the faces of a cube: exactly coplanar per face.
    let faces = cloud(10_000, 9, |u, i| {
        let mut p = Vec3::from(u) - 0.5;
        p[(i % 3) as usize] = if i % 2 == 0 { 0.5 } else { -0.5 };
        p
    });
    check_hull(&faces, "points on cube faces");
    // Every point three times.
    let once = cloud(3_000, 10, |u, _| Vec3::from(u));
    let mut thrice = Geometry::new();
    for _ in 0..3 {
        thrice.add_points(once.positions());
    }
    check_hull(&thrice, "duplicates");
    // A UV sphere: every point a vertex, each latitude ring coplanar.
    check_hull(&primitives::uv_sphere(1.0, 48, 24), "uv sphere");
}

/// scipy's 2D hull of points in a plane, in coordinates of the plane.
const SCIPY_HULL_2D: &str = r#"
import sys, json, numpy as np
from scipy.spatial import ConvexHull
d = json.load(sys.stdin)
p = np.array(d['p'], dtype=np.float64)
h = ConvexHull(p)
print(json.dumps({'area': float(h.volume), 'vertices': p[h.vertices].tolist()}))
"#;

#[test]
fn a_hull_of_coplanar_points_is_one_polygon_matching_qhull_in_2d() {
    let grid = primitives::grid(Vec2::new(3.0, 2.0), 30, 20);
    let mut pts = cloud(500, 12, |u, _| {
        Vec3::new(u[0] * 3.0 - 1.5, 0.0, u[1] * 2.0 - 1.0)
    });
    pts.add_points(grid.positions());
    let h = convex_hull(&pts, true, &never).unwrap();
    assert_eq!(h.num_prims(), 1);
    let n = ops::polygon_normal(h.positions(), h.prim_points(0));
    assert_eq!(n, Vec3::Y, "wound to face +Y");
    assert!((polygon_area(&h, 0) - 6.0).abs() < 1e-5);
    assert_eq!(h.num_points(), 4, "the grid's corners only");
    // A tilted plane with points exactly on it (dyadic coordinates).
    let tilted = cloud(2_000, 13, |u, _| {
        let (x, y) = ((u[0] * 64.0).floor() / 16.0, (u[1] * 64.0).floor() / 16.0);
        Vec3::new(x, y, 0.5 * x - 0.25 * y)
    });
    let h = convex_hull(&tilted, true, &never).unwrap();
    assert_eq!(h.num_prims(), 1);
    let input = json!({"p": tilted.positions().iter().map(|p| [p.x, p.y]).collect::<Vec<_>>()});
    let Some(s) = oracle(SCIPY_HULL_2D, &input) else {
        return;
    };
    let xy = |p: &Vec3| [p.x as f64, p.y as f64, 0.0];
    let mine = sorted_points(h.positions().iter().map(xy));
    let qhull = sorted_points(
        s["vertices"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| [v[0].as_f64().unwrap(), v[1].as_f64().unwrap(), 0.0]),
    );
    assert_eq!(mine, qhull);
    // Projected onto XY, the polygon's area is scipy's.
    let q: Vec<[f64; 2]> = h
        .prim_points(0)
        .iter()
        .map(|&i| h.positions()[i as usize])
        .map(|p| [p.x as f64, p.y as f64])
        .collect();
    let area: f64 = (0..q.len())
        .map(|i| {
            let (a, b) = (q[i], q[(i + 1) % q.len()]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f64>()
        / 2.0;
    assert!((area.abs() - f(&s, "area")).abs() < 1e-9);
}

#[test]
fn hull_point_attributes_are_carried() {
    let mut g = cloud(1_000, 14, |u, _| Vec3::from(u));
    let ids: Vec<i32> = (0..1_000).collect();
    g.set_attrib(
        AttribClass::Point,
        "id",
        Attribute::from_data(AttribData::Int(ids), TypeInfo::None),
    )
    .unwrap();
    let h = convex_hull(&g, true, &never).unwrap();
    let id = h
        .attrib(AttribClass::Point, "id")
        .unwrap()
        .as_i32()
        .unwrap();
    for (p, &i) in h.positions().iter().zip(id) {
        assert_eq!(*p, g.positions()[i as usize]);
    }
    let all = convex_hull(&g, false, &never).unwrap();
    assert_eq!(all.num_points(), 1_000);
    assert_eq!(all.num_prims(), h.num_prims());
}

// ----- revolve -----

fn curve(points: &[(f32, f32)], closed: bool) -> Geometry {
    let mut g = Geometry::new();
    let p: Vec<Vec3> = points.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
    g.add_points(&p);
    let idx: Vec<u32> = (0..p.len() as u32).collect();
    if closed {
        g.add_polygon(&idx).unwrap();
    } else {
        g.add_polyline(&idx).unwrap();
    }
    g
}

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

#[test]
fn the_hull_of_a_lattice_on_a_cubes_surface_is_the_cube() {
    let lattice = primitives::box_mesh(Vec3::splat(2.0), [20, 20, 20]);
    check_hull(&lattice, "lattice");
    let h = convex_hull(&lattice, true, &never).unwrap();
    assert_eq!(h.num_points(), 8);
    assert_eq!(h.num_prims(), 12);
    assert!((volume(&h) - 8.0).abs() < 1e-6);
}

#[test]
fn results_are_the_same_on_any_thread_count() {
    let sphere = sphere_triangles(64, 32);
    let cloud = cloud(50_000, 15, |u, _| Vec3::from(u));
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let o = ClipOptions {
                normal: Vec3::new(1.0, 2.0, 3.0),
                distance: 0.1,
                keep: Keep::Both,
                cap: Cap::Triangles,
                ..ClipOptions::default()
            };
            (
                clip(&sphere, &o, &never).unwrap().geometry,
                convex_hull(&cloud, true, &never).unwrap(),
                mirror(&sphere, &MirrorOptions::default(), &never)
                    .unwrap()
                    .geometry,
            )
        })
    };
    assert!(run(1) == run(3));
}

#[test]
fn every_kernel_stops_when_cancelled() {
    let g = sphere_triangles(64, 32);
    let yes = || true;
    let cancelled = |r: Result<(), geode_model::ModelError>| {
        matches!(r, Err(geode_model::ModelError::Cancelled))
    };
    assert!(cancelled(
        clip(&g, &ClipOptions::default(), &yes).map(|_| ())
    ));
    assert!(cancelled(convex_hull(&g, true, &yes).map(|_| ())));
    assert!(cancelled(
        mirror(&g, &MirrorOptions::default(), &yes).map(|_| ())
    ));
    let mut holed = g.clone();
    ops::delete_prims(&mut holed, &Group::from_members(g.num_prims(), [5]), true);
    assert!(cancelled(
        polyfill(&holed, &FillOptions::default(), &yes).map(|_| ())
    ));
    let line = curve(&[(1.0, 0.0), (1.0, 1.0)], false);
    assert!(cancelled(
        revolve(&line, &RevolveOptions::default(), &yes).map(|_| ())
    ));
}

/// One plane across an open grid makes one open cut, whatever order its
/// edges are met in (a bumpy quad grid's was counted as eleven).
#[test]
fn one_open_cut_is_counted_once() {
    let mut grid = primitives::grid(Vec2::splat(10.0), 10, 10);
    for p in grid.positions_mut() {
        p.y = 0.3 * (1.7 * p.x).sin() * (1.3 * p.z).cos();
    }
    for keep in [Keep::Above, Keep::Below] {
        let o = ClipOptions {
            normal: Vec3::X,
            distance: 0.5,
            keep,
            cap: Cap::Polygon,
            ..ClipOptions::default()
        };
        let r = clip(&grid, &o, &never).unwrap();
        assert_eq!(r.open_loops, 1, "{keep:?}");
    }
}
