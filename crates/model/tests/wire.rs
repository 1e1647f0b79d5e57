//! The wire family (polywire, edge_divide, divide) against closed forms
//! and trimesh (closed, wound, volume) through `tests/common`.

mod common;

use std::f64::consts::PI;

use common::{euler_and_closed, mesh_json, oracle, volume};
use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, AttribData, Attribute, Geometry, PrimKind, TypeInfo};
use geode_model::polywire::{polywire, PolywireOptions};
use geode_model::ModelError;
use serde_json::Value;

fn never() -> bool {
    false
}

const TRIMESH: &str = r#"
import sys, json, numpy as np, trimesh
d = json.load(sys.stdin)
m = trimesh.Trimesh(np.array(d['v'], dtype=float).reshape(-1, 3), np.array(d['f'], dtype=np.int64).reshape(-1, 3), process=False)
print(json.dumps({'watertight': bool(m.is_watertight), 'winding': bool(m.is_winding_consistent),
  'volume': float(m.volume), 'euler': int(m.euler_number)}))
"#;

/// Checks with trimesh (when present) that `g` is closed, consistently
/// wound outward, with Euler characteristic `euler`; and the same with
/// geode's own count.
fn closed_with_euler(g: &Geometry, euler: i64, what: &str) {
    let (e, closed) = euler_and_closed(g);
    assert!(closed, "{what}: an edge is not in exactly two faces");
    assert_eq!(e, euler, "{what}: Euler characteristic");
    assert!(volume(g) > 0.0, "{what}: faces inward");
    if let Some(t) = oracle(TRIMESH, &mesh_json(g)) {
        let t: Value = t;
        assert_eq!(t["watertight"], true, "{what}: trimesh says not watertight");
        assert_eq!(
            t["winding"], true,
            "{what}: trimesh says winding inconsistent"
        );
        assert!(
            t["volume"].as_f64().unwrap() > 0.0,
            "{what}: trimesh volume"
        );
        assert_eq!(t["euler"].as_i64().unwrap(), euler, "{what}: trimesh Euler");
    }
}

/// Polylines over `points`, one per `lines` entry.
fn lines(points: &[Vec3], lines: &[&[u32]]) -> Geometry {
    let counts: Vec<u32> = lines.iter().map(|l| l.len() as u32).collect();
    let verts: Vec<u32> = lines.iter().flat_map(|l| l.iter().copied()).collect();
    Geometry::from_prims(
        points.to_vec(),
        verts,
        &counts,
        vec![PrimKind::Polyline; lines.len()],
    )
    .unwrap()
}

fn wire(g: &Geometry, radius: f32, divisions: u32, segments: u32) -> Geometry {
    let o = PolywireOptions {
        radius,
        divisions,
        segments,
        ..PolywireOptions::default()
    };
    polywire(g, None, &o, &never).unwrap()
}

/// Surface area of a polygon mesh (fans).
fn area(g: &Geometry) -> f64 {
    let p = g.positions();
    let mut a = 0.0;
    for k in 0..g.num_prims() {
        let q = g.prim_points(k);
        for j in 1..q.len() - 1 {
            let (x, y, z) = (
                p[q[0] as usize].as_dvec3(),
                p[q[j] as usize].as_dvec3(),
                p[q[j + 1] as usize].as_dvec3(),
            );
            a += (y - x).cross(z - x).length() / 2.0;
        }
    }
    a
}

#[test]
fn a_straight_tube_is_a_capped_prism() {
    let (l, r, n) = (3.0f64, 0.25f64, 12u32);
    let g = lines(
        &[
            Vec3::new(0.5, 1.0, -1.0),
            Vec3::new(0.5 + l as f32, 1.0, -1.0),
        ],
        &[&[0, 1]],
    );
    let out = wire(&g, r as f32, n, 4);
    let ngon = 0.5 * n as f64 * r * r * (2.0 * PI / n as f64).sin();
    let side = 2.0 * r * (PI / n as f64).sin();
    assert!(
        (volume(&out) - ngon * l).abs() < 1e-5,
        "volume {}",
        volume(&out)
    );
    let want = 2.0 * ngon + n as f64 * side * l;
    assert!(
        (area(&out) - want).abs() < 1e-5,
        "area {} vs {want}",
        area(&out)
    );
    assert_eq!(out.num_points(), 5 * n as usize);
    assert_eq!(out.num_prims(), 4 * n as usize + 2);
    closed_with_euler(&out, 2, "straight tube");
}

#[test]
fn a_bent_polyline_is_mitred_and_keeps_its_volume() {
    // An L of two arms: the mitred tube's volume is the two prisms'
    // measured along the centre line (a mitre adds what it takes).
    let (r, n) = (0.1f64, 16u32);
    let g = lines(
        &[
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 2.0, 0.0),
        ],
        &[&[0, 1, 2]],
    );
    let out = wire(&g, r as f32, n, 1);
    let ngon = 0.5 * n as f64 * r * r * (2.0 * PI / n as f64).sin();
    assert!(
        (volume(&out) - 3.0 * ngon).abs() < 1e-4,
        "volume {}",
        volume(&out)
    );
    closed_with_euler(&out, 2, "L");
}

#[test]
fn y_and_star_junctions_are_closed_spheres() {
    let y = lines(
        &[
            Vec3::ZERO,
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(0.7, 0.7, 0.0),
            Vec3::new(-0.7, 0.7, 0.1),
        ],
        &[&[1, 0, 2], &[0, 3]],
    );
    closed_with_euler(&wire(&y, 0.1, 8, 2), 2, "Y");
    let dirs = [
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::new(0.3, 0.4, -0.8),
        Vec3::new(0.9, 0.1, 0.5),
    ];
    let mut pts = vec![Vec3::new(0.2, 0.1, 0.3)];
    let c = pts[0];
    pts.extend(dirs.iter().map(|d| c + *d));
    let star: Vec<[u32; 2]> = (1..=dirs.len() as u32).map(|k| [0, k]).collect();
    let star_refs: Vec<&[u32]> = star.iter().map(|e| &e[..]).collect();
    closed_with_euler(&wire(&lines(&pts, &star_refs), 0.08, 10, 1), 2, "star");
}

/// Closed, wound outward, watertight for trimesh, one or more spheres
/// (left-out twigs' tubes are closed pieces of their own).
fn closed_spheres(g: &Geometry, what: &str) {
    let (e, closed) = euler_and_closed(g);
    assert!(closed, "{what}: an edge is not in exactly two faces");
    assert!(e >= 2 && e % 2 == 0, "{what}: Euler characteristic {e}");
    assert!(volume(g) > 0.0, "{what}: faces inward");
    if let Some(t) = oracle(TRIMESH, &mesh_json(g)) {
        let t: Value = t;
        assert_eq!(t["watertight"], true, "{what}: trimesh says not watertight");
        assert_eq!(t["winding"], true, "{what}: trimesh winding");
        assert_eq!(t["euler"].as_i64().unwrap(), e, "{what}: trimesh Euler");
    }
}

// Space colonization can leave a point with dozens of short twigs a
// degree or two apart (the coral at full growth): no hull of their rings
// shows every ring, so the joint leaves the nearest twigs out and caps
// them. Two edges along the same direction are the limit case.
#[test]
fn a_brush_of_near_parallel_twigs_and_overlapping_edges_close() {
    let c = Vec3::new(0.3, 1.2, -0.4);
    let mut pts = vec![c, c - Vec3::Y * 0.2];
    let edges: Vec<[u32; 2]> = vec![[1, 0]];
    let mut twigs: Vec<[u32; 3]> = Vec::new();
    for k in 0..32 {
        // A fan 1.6 degrees apart in three rows, each twig bending after
        // a short first edge (rings out on the bent part).
        let a = ((k / 3) as f32 - 5.0) * 1.6f32.to_radians();
        let b = ((k % 3) as f32 - 1.0) * 1.6f32.to_radians();
        let d = Vec3::new(a.sin(), a.cos() * b.cos(), b.sin()).normalize();
        let bend = Vec3::new(
            0.3 * ((k * 7 % 5) as f32 - 2.0),
            1.0,
            0.2 * ((k % 4) as f32 - 1.5),
        );
        let mid = c + d * 0.012;
        pts.push(mid);
        pts.push(mid + bend.normalize() * (0.03 + 0.003 * (k % 5) as f32));
        let n = pts.len() as u32;
        twigs.push([0, n - 2, n - 1]);
    }
    let mut refs: Vec<&[u32]> = edges.iter().map(|e| &e[..]).collect();
    refs.extend(twigs.iter().map(|t| &t[..]));
    let g = lines(&pts, &refs);
    let o = PolywireOptions {
        radius: 0.012,
        ..PolywireOptions::default()
    };
    let unioned = polywire(&g, None, &o, &never).unwrap();
    closed_spheres(&unioned, "brush");
    // The twigs left out overlap the kept tubes as closed pieces of their
    // own; unioned (the default), one solid. What crossing remains (11
    // faces against 1417) is inside one piece, kept tubes grazing each
    // other near the joint, which a union of pieces cannot reach.
    let apart = PolywireOptions {
        union: false,
        ..o.clone()
    };
    let pieces = polywire(&g, None, &apart, &never).unwrap();
    closed_spheres(&pieces, "brush in pieces");
    assert!(euler_and_closed(&pieces).0 > 2);
    assert_eq!(euler_and_closed(&unioned).0, 2);
    let crossing = |g: &Geometry| {
        oracle(SELF_INTERSECTIONS, &mesh_json(g)).map(|t: Value| t["crossing"].as_i64().unwrap())
    };
    if let (Some(before), Some(after)) = (crossing(&pieces), crossing(&unioned)) {
        assert!(
            after * 50 < before,
            "crossing faces: {before} in pieces, {after} unioned"
        );
    }
    // Which twigs are left out does not depend on the threads.
    let in_pool = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| polywire(&g, None, &o, &never).unwrap().content_hash())
    };
    assert_eq!(in_pool(1), in_pool(2));
    let same = lines(
        &[Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::Y, Vec3::NEG_Y],
        &[&[0, 1], &[0, 2], &[0, 3], &[0, 4]],
    );
    closed_spheres(&wire(&same, 0.1, 8, 1), "overlapping edges");
}

#[test]
fn a_broom_of_edges_leaving_one_side_reaches_its_joint_point() {
    // Three unit edges from the origin, all a few degrees off -Y: a hull
    // of their rings would close far down the edges, leaving the joint
    // point and most of every edge bare. The tubes run to the point and
    // are unioned there instead: one closed solid up to the origin.
    for degrees in [2.0f32, 5.0, 20.0] {
        let a = degrees.to_radians();
        let mut pts = vec![Vec3::ZERO];
        for k in 0..3 {
            let phi = std::f32::consts::TAU * k as f32 / 3.0;
            pts.push(Vec3::new(
                a.sin() * phi.cos(),
                -a.cos(),
                a.sin() * phi.sin(),
            ));
        }
        let g = lines(&pts, &[&[0, 1], &[0, 2], &[0, 3]]);
        let out = wire(&g, 0.05, 8, 1);
        closed_with_euler(&out, 2, &format!("broom of {degrees} degrees"));
        let top = out.positions().iter().map(|p| p.y).fold(f32::MIN, f32::max);
        assert!(top > -0.01, "{degrees}: the solid ends at y = {top}");
        if let Some(t) = oracle(SELF_INTERSECTIONS, &mesh_json(&out)) {
            let t: Value = t;
            assert_eq!(t["crossing"], 0, "{degrees}: faces cross");
        }
    }
}

#[test]
fn a_closed_loop_is_a_torus_and_a_cube_frame_has_genus_five() {
    let square = Geometry::from_prims(
        vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
        vec![0, 1, 2, 3],
        &[4],
        vec![PrimKind::Polygon],
    )
    .unwrap();
    closed_with_euler(&wire(&square, 0.1, 8, 3), 0, "loop");
    // A box's 12 edges (shared by its faces, counted once): 8 joints of
    // three, 5 independent loops.
    let cube = geode_geo::primitives::cube(1.0);
    let out = wire(&cube, 0.05, 8, 1);
    closed_with_euler(&out, 2 - 2 * 5, "cube frame");
}

const SELF_INTERSECTIONS: &str = r#"
import sys, json, numpy as np, pymeshlab
d = json.load(sys.stdin)
ms = pymeshlab.MeshSet()
ms.add_mesh(pymeshlab.Mesh(np.array(d['v'], dtype=float).reshape(-1, 3), np.array(d['f'], dtype=np.int32).reshape(-1, 3)))
ms.compute_selection_by_self_intersections_per_face()
print(json.dumps({'crossing': int(ms.current_mesh().selected_face_number())}))
"#;

#[test]
fn a_radius_past_the_edges_pinches_the_bends_and_joints() {
    // A 3 by 3 grid of 2/3 edges: its corners bend, its other points are
    // joints. A radius of 2 (or 1e9) is narrowed at both until the tubes
    // fit: nothing reaches past a third beyond the grid, and nothing
    // crosses itself (pymeshlab's self-intersection test).
    let grid = geode_geo::primitives::grid(geode_geo::glam::Vec2::new(2.0, 2.0), 3, 3);
    for radius in [2.0, 1e9] {
        let out = wire(&grid, radius, 8, 1);
        // 16 points and 24 edges: 9 independent loops.
        closed_with_euler(&out, 2 - 2 * 9, "fat grid");
        for p in out.positions() {
            assert!(p.abs().max_element() <= 4.0 / 3.0 + 1e-4, "{radius}: {p}");
        }
        if let Some(t) = oracle(SELF_INTERSECTIONS, &mesh_json(&out)) {
            let t: Value = t;
            assert_eq!(t["crossing"], 0, "{radius}: faces cross");
        }
    }
}

#[test]
fn the_radius_comes_from_a_point_attribute() {
    let mut g = lines(&[Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0)], &[&[0, 1]]);
    g.set_attrib(
        AttribClass::Point,
        "pscale",
        Attribute::from_data(AttribData::Float(vec![1.0, 3.0]), TypeInfo::None),
    )
    .unwrap();
    let o = PolywireOptions {
        radius: 0.1,
        radius_attribute: Some("pscale".into()),
        divisions: 6,
        segments: 2,
        ..PolywireOptions::default()
    };
    let out = polywire(&g, None, &o, &never).unwrap();
    // Rings at x = 0, 1, 2 of radius 0.1, 0.2, 0.3.
    for p in out.positions() {
        let want = 0.1 + 0.1 * p.x as f64;
        let got = (p.y as f64).hypot(p.z as f64);
        assert!(
            (got - want).abs() < 1e-5,
            "{p:?}: radius {got}, want {want}"
        );
    }
    // pscale is carried (blended) onto the rings.
    let ps = out.attrib(AttribClass::Point, "pscale").unwrap();
    let AttribData::Float(v) = ps.data() else {
        panic!()
    };
    assert!(v.iter().any(|&x| (x - 2.0).abs() < 1e-6));
    let missing = PolywireOptions {
        radius_attribute: Some("width".into()),
        ..o
    };
    let err = polywire(&g, None, &missing, &never).unwrap_err();
    assert!(err.to_string().contains("width"), "{err}");
}

#[test]
fn clear_errors_and_cancellation() {
    let g = lines(&[Vec3::ZERO, Vec3::X, Vec3::X], &[&[0, 1], &[1, 2]]);
    let err = polywire(&g, None, &PolywireOptions::default(), &never).unwrap_err();
    assert!(err.to_string().contains("no length"), "{err}");
    let ok = lines(&[Vec3::ZERO, Vec3::X], &[&[0, 1]]);
    for o in [
        PolywireOptions {
            divisions: 2,
            ..PolywireOptions::default()
        },
        PolywireOptions {
            radius: 0.0,
            ..PolywireOptions::default()
        },
        PolywireOptions {
            segments: 0,
            ..PolywireOptions::default()
        },
    ] {
        assert!(matches!(
            polywire(&ok, None, &o, &never),
            Err(ModelError::Invalid(_))
        ));
    }
    let big = geode_geo::primitives::grid(geode_geo::glam::Vec2::ONE, 100, 100);
    let err = polywire(&big, None, &PolywireOptions::default(), &|| true).unwrap_err();
    assert!(matches!(err, ModelError::Cancelled), "{err}");
}

#[test]
fn one_and_two_threads_give_the_same_bytes() {
    let g = geode_geo::primitives::grid(geode_geo::glam::Vec2::ONE, 30, 30);
    let in_pool = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| wire(&g, 0.005, 6, 2).content_hash())
    };
    assert_eq!(in_pool(1), in_pool(2));
    // A grid of quads: every inner point a joint of four; closed.
    let out = wire(&g, 0.005, 6, 2);
    let (_, closed) = euler_and_closed(&out);
    assert!(closed);
}

// ----- edge_divide -----

use geode_model::edge_divide::{edge_divide, EdgeDivideOptions};

fn divide_edges(g: &Geometry, group: Option<&geode_geo::Group>, n: u32) -> Geometry {
    let o = EdgeDivideOptions {
        divisions: n,
        group_name: Some("new".into()),
    };
    edge_divide(g, group, &o, &never).unwrap()
}

#[test]
fn edge_divide_keeps_area_counts_and_closure() {
    let sphere = geode_geo::ops::triangulate(&geode_geo::primitives::uv_sphere(1.0, 24, 12), None);
    let (e0, closed0) = euler_and_closed(&sphere);
    assert!(closed0);
    let edges = sphere.num_vertices() / 2;
    for n in [1u32, 3] {
        let out = divide_edges(&sphere, None, n);
        assert_eq!(out.num_points(), sphere.num_points() + edges * n as usize);
        assert_eq!(out.num_vertices(), sphere.num_vertices() * (1 + n as usize));
        assert_eq!(out.num_prims(), sphere.num_prims());
        assert!((area(&out) - area(&sphere)).abs() < 1e-9 * area(&sphere).max(1.0) + 1e-5);
        assert!((volume(&out) - volume(&sphere)).abs() < 1e-5);
        // geode's own edge count (trimesh's fans of a polygon with points
        // along its sides are degenerate triangles it does not pair up).
        assert_eq!(euler_and_closed(&out), (e0, true), "divided sphere");
        assert_eq!(out.point_groups()["new"].count(), edges * n as usize);
    }
}

#[test]
fn edge_divide_blends_attributes_and_follows_the_point_group() {
    let mut g = geode_geo::primitives::cube(2.0);
    let h: Vec<f32> = g.positions().iter().map(|p| p.x + 2.0 * p.y).collect();
    g.set_attrib(
        AttribClass::Point,
        "h",
        Attribute::from_data(AttribData::Float(h), TypeInfo::None),
    )
    .unwrap();
    let out = divide_edges(&g, None, 2);
    let AttribData::Float(h) = out.attrib(AttribClass::Point, "h").unwrap().data() else {
        panic!()
    };
    for (p, h) in out.positions().iter().zip(h) {
        assert!((p.x + 2.0 * p.y - h).abs() < 1e-5, "h follows the blend");
    }
    // Only the top face's edges (points with y > 0): its 4 edges.
    let top = geode_geo::Group::from_flags(g.positions().iter().map(|p| p.y > 0.0));
    let out = divide_edges(&g, Some(&top), 1);
    assert_eq!(out.num_points(), g.num_points() + 4);
    assert!(euler_and_closed(&out).1);
    let one = || {
        rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| divide_edges(&g, None, 3).content_hash())
    };
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap()
        .install(|| divide_edges(&g, None, 3).content_hash());
    assert_eq!(one(), two);
    let err = edge_divide(
        &g,
        None,
        &EdgeDivideOptions {
            divisions: 0,
            group_name: None,
        },
        &never,
    )
    .unwrap_err();
    assert!(err.to_string().contains("division"), "{err}");
    assert!(matches!(
        edge_divide(
            &g,
            None,
            &EdgeDivideOptions {
                divisions: 1,
                group_name: None
            },
            &|| true
        ),
        Err(ModelError::Cancelled)
    ));
}

// ----- divide -----

use geode_model::divide::{convex_polygons, DivideOptions};

/// Whether every polygon of `g` turns one way at every corner in its
/// Newell plane.
fn all_convex(g: &Geometry) -> bool {
    let p = g.positions();
    (0..g.num_prims()).all(|k| {
        let q: Vec<geode_geo::glam::DVec3> = g
            .prim_points(k)
            .iter()
            .map(|&i| p[i as usize].as_dvec3())
            .collect();
        let n: geode_geo::glam::DVec3 =
            (0..q.len()).map(|i| q[i].cross(q[(i + 1) % q.len()])).sum();
        (0..q.len()).all(|i| {
            let (a, b, c) = (q[i], q[(i + 1) % q.len()], q[(i + 2) % q.len()]);
            (b - a).cross(c - b).dot(n) >= -1e-9
        })
    })
}

/// An L-shaped prism: 2 x 2 less a 1 x 1 corner, height 1 (closed; its
/// caps are non-convex hexagons).
fn l_prism() -> Geometry {
    let ring = [
        (0.0, 0.0),
        (2.0, 0.0),
        (2.0, 1.0),
        (1.0, 1.0),
        (1.0, 2.0),
        (0.0, 2.0),
    ];
    let mut pts = Vec::new();
    for z in [0.0, 1.0] {
        pts.extend(ring.iter().map(|&(x, y)| Vec3::new(x, y, z)));
    }
    let mut verts: Vec<u32> = (0..6).rev().collect();
    verts.extend(6..12);
    let mut counts = vec![6, 6];
    for i in 0..6u32 {
        let j = (i + 1) % 6;
        verts.extend([i, j, j + 6, i + 6]);
        counts.push(4);
    }
    Geometry::from_prims(pts, verts, &counts, vec![PrimKind::Polygon; 8]).unwrap()
}

#[test]
fn convex_pieces_keep_area_and_closure() {
    let g = l_prism();
    assert!(!all_convex(&g));
    let out = convex_polygons(&g, &DivideOptions::default(), &never).unwrap();
    assert!(all_convex(&out));
    // Each L cap splits into two convex pieces (Hertel-Mehlhorn's best here).
    assert_eq!(out.num_prims(), 6 + 2 * 2);
    assert!((area(&out) - (2.0 * 3.0 + 8.0)).abs() < 1e-9);
    assert!((volume(&out) - 3.0).abs() < 1e-9);
    let (e, closed) = euler_and_closed(&out);
    assert!(closed && e == 2);
    // A regular 12-gon with at most 4 sides a piece.
    let pts: Vec<Vec3> = (0..12)
        .map(|k| {
            let a = std::f32::consts::TAU * k as f32 / 12.0;
            Vec3::new(a.cos(), 0.3, a.sin())
        })
        .collect();
    let disc =
        Geometry::from_prims(pts, (0..12).collect(), &[12], vec![PrimKind::Polygon]).unwrap();
    let out = convex_polygons(&disc, &DivideOptions { max_edges: 4 }, &never).unwrap();
    assert!(out.num_prims() >= 5 && (0..out.num_prims()).all(|k| out.prim_points(k).len() <= 4));
    assert!((area(&out) - area(&disc)).abs() < 1e-6);
    assert!(all_convex(&out));
    // A star: ten corners, five reflex.
    let star: Vec<Vec3> = (0..10)
        .map(|k| {
            let a = std::f32::consts::TAU * k as f32 / 10.0;
            let r = if k % 2 == 0 { 1.0 } else { 0.4 };
            Vec3::new(r * a.cos(), r * a.sin(), 0.0)
        })
        .collect();
    let g = Geometry::from_prims(star, (0..10).collect(), &[10], vec![PrimKind::Polygon]).unwrap();
    let out = convex_polygons(&g, &DivideOptions::default(), &never).unwrap();
    assert!(
        all_convex(&out) && out.num_prims() <= 6,
        "{} pieces",
        out.num_prims()
    );
    // Ten triangles from the centre (sides 1 and 0.4, 36 degrees apart).
    let want = 10.0 * 0.5 * 0.4 * (PI / 5.0).sin();
    assert!((area(&out) - want).abs() < 1e-6, "{} vs {want}", area(&out));
    assert!(convex_polygons(&g, &DivideOptions { max_edges: 2 }, &never).is_err());
}

#[test]
fn bricks_keep_area_closure_and_lie_in_one_cell() {
    use geode_model::divide::bricker;
    let sphere = geode_geo::primitives::uv_sphere(1.0, 20, 10);
    let (size, offset) = (Vec3::new(0.3, 0.45, 0.25), Vec3::new(0.05, -0.1, 0.0));
    let out = bricker(&sphere, size, offset, &never).unwrap();
    assert!(out.num_prims() > 3 * sphere.num_prims());
    assert!(
        (area(&out) - area(&sphere)).abs() < 1e-4,
        "{} vs {}",
        area(&out),
        area(&sphere)
    );
    assert!((volume(&out) - volume(&sphere)).abs() < 1e-4);
    let (e, closed) = euler_and_closed(&out);
    assert!(closed && e == 2, "closed {closed}, euler {e}");
    assert!(all_convex(&out));
    let p = out.positions();
    for k in 0..out.num_prims() {
        let q = out.prim_points(k);
        let centre = q.iter().map(|&i| p[i as usize]).sum::<Vec3>() / q.len() as f32;
        let cell = ((centre - offset) / size).floor();
        let (lo, hi) = (offset + cell * size, offset + (cell + Vec3::ONE) * size);
        for &i in q {
            let x = p[i as usize];
            assert!(
                x.cmpge(lo - 1e-5).all() && x.cmple(hi + 1e-5).all(),
                "piece {k}: {x} outside cell {lo}..{hi}"
            );
        }
    }
    let in_pool = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| {
                bricker(&sphere, size, offset, &never)
                    .unwrap()
                    .content_hash()
            })
    };
    assert_eq!(in_pool(1), in_pool(2));
    assert!(bricker(&sphere, Vec3::new(0.0, 1.0, 1.0), offset, &never).is_err());
    assert!(matches!(
        bricker(&sphere, size, offset, &|| true),
        Err(ModelError::Cancelled)
    ));
}
