//! Bevel against closed-form answers: the chamfered and rounded unit box
//! (volume and area), a triangular prism, a cube corner cut by a point
//! bevel; closedness and winding checked by trimesh (PyPI) as well as by
//! edge counts and the Euler characteristic; clamping, groups,
//! attributes, determinism, cancellation and refusals; no face crossing
//! another, checked by pymeshlab (PyPI).

mod common;
use common::*;

use std::f64::consts::PI;

use geode_geo::glam::{Vec2, Vec3};
use geode_geo::{primitives, AttribClass, AttribData, Attribute, Geometry, Group, TypeInfo};
use geode_model::bevel::{bevel, Affect, Bevel, CORNER_GROUP, EDGE_GROUP};
use geode_model::ModelError;

fn run(g: &Geometry, group: Option<&Group>, how: Bevel) -> Geometry {
    bevel(g, group, &how, &|| false).unwrap().0
}

fn edges(offset: f32, segments: u32) -> Bevel {
    Bevel {
        offset,
        segments,
        ..Bevel::default()
    }
}

fn count(g: &Geometry, group: &str) -> usize {
    g.prim_groups()[group].count()
}

fn area(g: &Geometry) -> f64 {
    let p = g.positions();
    (0..g.num_prims())
        .map(|k| {
            let q = g.prim_points(k);
            let mut n = geode_geo::glam::DVec3::ZERO;
            for j in 0..q.len() {
                let (a, b) = (
                    p[q[j] as usize].as_dvec3(),
                    p[q[(j + 1) % q.len()] as usize].as_dvec3(),
                );
                n += a.cross(b);
            }
            n.length() / 2.0
        })
        .sum()
}

/// The chamfered unit box: each edge's prism of legs d between the
/// corners, and at each corner the d-cube less the small tetrahedron the
/// corner triangle leaves (x + y + z >= 2d in it keeps d^3 / 6).
fn chamfer_volume(d: f64) -> f64 {
    1.0 - 12.0 * (d * d / 2.0) * (1.0 - 2.0 * d) - 8.0 * (5.0 / 6.0) * d.powi(3)
}

/// Faces shrunk to (1 - 2d)^2, strips (1 - 2d) by d sqrt 2, corner
/// triangles equilateral of side d sqrt 2.
fn chamfer_area(d: f64) -> f64 {
    6.0 * (1.0 - 2.0 * d).powi(2)
        + 12.0 * 2f64.sqrt() * d * (1.0 - 2.0 * d)
        + 8.0 * 3f64.sqrt() / 4.0 * 2.0 * d * d
}

fn rounded_volume(a: f64, r: f64) -> f64 {
    let s = a - 2.0 * r;
    s.powi(3) + 6.0 * s * s * r + 3.0 * PI * s * r * r + 4.0 / 3.0 * PI * r.powi(3)
}

fn trimesh_closed(g: &Geometry) {
    let script = r#"
import json, sys, numpy as np, trimesh
d = json.load(sys.stdin)
m = trimesh.Trimesh(vertices=np.array(d["v"]), faces=np.array(d["f"]), process=True)
print(json.dumps({"watertight": bool(m.is_watertight), "consistent": bool(m.is_winding_consistent), "volume": float(m.volume)}))
"#;
    if let Some(r) = oracle(script, &mesh_json(g)) {
        assert!(
            r["watertight"].as_bool().unwrap() && r["consistent"].as_bool().unwrap(),
            "{r}"
        );
        assert!(
            (r["volume"].as_f64().unwrap() - volume(g)).abs() < 1e-5,
            "{r}"
        );
    }
}

#[test]
fn a_chamfered_box_has_the_closed_form_volume_and_area() {
    for d in [0.05f32, 0.1, 0.25] {
        let out = run(&primitives::cube(1.0), None, edges(d, 1));
        let d = d as f64;
        assert!(
            (volume(&out) - chamfer_volume(d)).abs() < 1e-5,
            "{d}: {}",
            volume(&out)
        );
        assert!(
            (area(&out) - chamfer_area(d)).abs() < 1e-5,
            "{d}: {}",
            area(&out)
        );
        assert_eq!(euler_and_closed(&out), (2, true));
        assert_eq!(
            (count(&out, EDGE_GROUP), count(&out, CORNER_GROUP)),
            (12, 8)
        );
        assert_eq!((out.num_points(), out.num_prims()), (24, 26));
    }
    trimesh_closed(&run(&primitives::cube(1.0), None, edges(0.1, 1)));
}

#[test]
fn many_circular_segments_converge_to_the_rounded_box() {
    let r = 0.2f64;
    let want = rounded_volume(1.0, r);
    let mut errors = Vec::new();
    for n in [4u32, 8, 16] {
        let out = run(&primitives::cube(1.0), None, edges(r as f32, n));
        assert_eq!(euler_and_closed(&out), (2, true), "{n}");
        let v = volume(&out);
        // Every point lies on the rounded box, a convex solid: the
        // polyhedron is inside it. The edges lose exactly the quarter
        // discs less their inscribed n-gons; each corner's octant of
        // sphere loses at most its area times the sagitta of a cell
        // (angular size at most pi / 2n), twice over for the grid's
        // uneven cells.
        let edge_loss = 12.0
            * (1.0 - 2.0 * r)
            * r
            * r
            * (PI / 4.0 - n as f64 / 2.0 * (PI / (2.0 * n as f64)).sin());
        let sagitta = r * (1.0 - (PI / (2.0 * n as f64)).cos());
        let corner_loss = 8.0 * (PI * r * r / 2.0) * sagitta * 2.0;
        assert!(v <= want + 1e-5, "{n}: {v} > {want}");
        assert!(
            want - v <= edge_loss + corner_loss + 1e-5,
            "{n}: {v} vs {want}"
        );
        errors.push(want - v);
    }
    // Second order: halving the segments' angle quarters the error.
    assert!(
        errors[2] < errors[1] / 3.0 && errors[1] < errors[0] / 3.0,
        "{errors:?}"
    );
    trimesh_closed(&run(&primitives::cube(1.0), None, edges(0.2, 5)));
}

/// An equilateral prism of side 1 and height 2, along y.
fn prism() -> Geometry {
    let s3 = 3f32.sqrt();
    let tri = [
        Vec2::new(0.0, -s3 / 3.0),
        Vec2::new(0.5, s3 / 6.0),
        Vec2::new(-0.5, s3 / 6.0),
    ];
    let mut g = Geometry::new();
    for y in [0.0, 2.0] {
        let pts: Vec<Vec3> = tri.iter().map(|t| Vec3::new(t.x, y, t.y)).collect();
        g.add_points(&pts);
    }
    // Bottom faces down (-y), top up, sides out.
    g.add_polygon(&[0, 1, 2]).unwrap();
    g.add_polygon(&[3, 5, 4]).unwrap();
    for i in 0..3u32 {
        let j = (i + 1) % 3;
        g.add_polygon(&[i, i + 3, j + 3, j]).unwrap();
    }
    if volume(&g) < 0.0 {
        geode_geo::ops::reverse_prims(&mut g, None);
    }
    g
}

#[test]
fn a_prism_with_its_long_edges_bevelled_loses_its_corners() {
    let g = prism();
    let base = volume(&g);
    assert!((base - 2.0 * 3f64.sqrt() / 4.0).abs() < 1e-5, "{base}");
    // Long edges turn by 120 degrees, the caps' edges by 90: above 100
    // only the long ones are sharp.
    let d = 0.1f32;
    let out = run(
        &g,
        None,
        Bevel {
            flat_angle: Some(100.0),
            ..edges(d, 1)
        },
    );
    let d = d as f64;
    let want = 2.0 * 3f64.sqrt() / 4.0 * (1.0 - 3.0 * d * d);
    assert!(
        (volume(&out) - want).abs() < 1e-5,
        "{} vs {want}",
        volume(&out)
    );
    assert_eq!(euler_and_closed(&out), (2, true));
    assert_eq!((count(&out, EDGE_GROUP), count(&out, CORNER_GROUP)), (3, 0));
    // Every edge, rounded: still closed, between the all-chamfered prism
    // and the prism itself, and trimesh agrees.
    let chamfered = volume(&run(&g, None, edges(0.1, 1)));
    let all = run(&g, None, edges(0.1, 4));
    assert_eq!(euler_and_closed(&all), (2, true));
    assert!(
        chamfered < volume(&all) && volume(&all) < base,
        "{}",
        volume(&all)
    );
    trimesh_closed(&all);
}

#[test]
fn a_point_bevel_cuts_a_tetrahedron_off_a_cube_corner() {
    let cube = primitives::cube(1.0);
    let one = Group::from_members(cube.num_points(), [0]);
    for d in [0.1f32, 0.3] {
        let out = run(
            &cube,
            Some(&one),
            Bevel {
                affect: Affect::Points,
                ..edges(d, 1)
            },
        );
        let d = d as f64;
        assert!((volume(&out) - (1.0 - d.powi(3) / 6.0)).abs() < 1e-6);
        assert_eq!(euler_and_closed(&out), (2, true));
        assert_eq!(count(&out, CORNER_GROUP), 1);
        assert_eq!(out.num_points(), 10);
    }
    // Every corner with rounded cuts: closed, and inside the cube.
    let round = run(
        &cube,
        None,
        Bevel {
            affect: Affect::Points,
            ..edges(0.2, 4)
        },
    );
    assert_eq!(euler_and_closed(&round), (2, true));
    // Arcs bulge past the flat cuts toward the corner.
    let v = volume(&round);
    assert!(v > 1.0 - 8.0 * 0.2f64.powi(3) / 6.0 && v < 1.0, "{v}");
    trimesh_closed(&round);
}

#[test]
fn a_divided_box_bevels_its_sharp_edges_as_the_plain_cube_does() {
    let divided = primitives::box_mesh(Vec3::ONE, [3, 2, 4]);
    for n in [1u32, 4] {
        let how = Bevel {
            flat_angle: Some(2.0),
            ..edges(0.15, n)
        };
        let out = run(&divided, None, how.clone());
        let plain = run(&primitives::cube(1.0), None, how);
        assert_eq!(euler_and_closed(&out), (2, true), "{n}");
        assert!((volume(&out) - volume(&plain)).abs() < 1e-5, "{n}");
        assert!((area(&out) - area(&plain)).abs() < 1e-4, "{n}");
        trimesh_closed(&out);
    }
}

#[test]
fn some_edges_of_a_cube_one_or_two_meeting_at_a_corner() {
    let cube = primitives::cube(1.0);
    // Points with y > 0 and z > 0: one edge along x. Add x > 0: two edges
    // meeting at a corner (the third pair is a diagonal, not an edge).
    let p = cube.positions().to_vec();
    let single = Group::from_flags(p.iter().map(|q| q.y > 0.0 && q.z > 0.0));
    let pair = Group::from_flags(p.iter().map(|q| q.y > 0.0 && (q.z > 0.0 || q.x > 0.0)));
    let d = 0.2f64;
    for (group, edges_cut) in [(&single, 1usize), (&pair, 2)] {
        for n in [1u32, 3] {
            let out = run(&cube, Some(group), edges(d as f32, n));
            assert_eq!(euler_and_closed(&out), (2, true), "{edges_cut} {n}");
            assert_eq!(count(&out, EDGE_GROUP), edges_cut * n as usize);
            trimesh_closed(&out);
            if n == 1 && edges_cut == 1 {
                assert!((volume(&out) - (1.0 - d * d / 2.0)).abs() < 1e-6);
            }
        }
    }
}

#[test]
fn an_offset_past_half_an_edge_is_clamped_and_nothing_inverts() {
    let cube = primitives::cube(1.0);
    let (out, report) = bevel(&cube, None, &edges(0.8, 1), &|| false).unwrap();
    assert!((report.offset - 0.5).abs() < 1e-6, "{report:?}");
    // At half the edge the faces shrink to points: an octahedron.
    assert!((volume(&out) - 1.0 / 6.0).abs() < 1e-5, "{}", volume(&out));
    // A long box: the short edges limit it.
    let long = primitives::box_mesh(Vec3::new(1.0, 0.4, 2.0), [1, 1, 1]);
    for n in [1u32, 3] {
        let (out, report) = bevel(&long, None, &edges(1.0, n), &|| false).unwrap();
        assert!((report.offset - 0.2).abs() < 1e-6, "{report:?}");
        assert_eq!(euler_and_closed(&out), (2, true));
        let p = out.positions();
        for k in 0..out.num_prims() {
            let q = out.prim_points(k);
            let n = geode_geo::ops::polygon_normal(p, q);
            let c = q.iter().map(|&i| p[i as usize]).sum::<Vec3>() / q.len() as f32;
            assert!(n.dot(c) >= -1e-6, "face {k} turns inward");
        }
        assert!(volume(&out) > 0.0 && volume(&out) < 0.8);
    }
    // Without the clamp the asked offset is kept.
    let (_, report) = bevel(
        &cube,
        None,
        &Bevel {
            clamp: false,
            ..edges(0.8, 1)
        },
        &|| false,
    )
    .unwrap();
    assert_eq!(report.offset, 0.8);
    // ... and the limit it passed is reported (the node warns with it).
    assert!((report.limit - 0.5).abs() < 1e-6, "{report:?}");
}

#[test]
fn groups_and_attributes_follow_their_sources() {
    let mut cube = primitives::cube(1.0);
    let ids: Vec<i32> = (0..cube.num_points() as i32).collect();
    cube.set_attrib(
        AttribClass::Point,
        "id",
        Attribute::from_data(AttribData::Int(ids), TypeInfo::None),
    )
    .unwrap();
    let colour: Vec<f32> = (0..cube.num_prims()).map(|k| k as f32).collect();
    cube.set_attrib(
        AttribClass::Primitive,
        "c",
        Attribute::from_data(AttribData::Float(colour), TypeInfo::None),
    )
    .unwrap();
    let w: Vec<f32> = (0..cube.num_vertices()).map(|v| v as f32).collect();
    cube.set_attrib(
        AttribClass::Vertex,
        "w",
        Attribute::from_data(AttribData::Float(w), TypeInfo::None),
    )
    .unwrap();
    let top = Group::from_flags((0..cube.num_prims()).map(|k| k == 0));
    cube.set_prim_group("first", top).unwrap();
    let out = run(
        &cube,
        None,
        Bevel {
            edge_group: "strips".into(),
            corner_group: "".into(),
            ..edges(0.1, 2)
        },
    );
    assert_eq!(count(&out, "strips"), 24);
    assert!(!out.prim_groups().contains_key(CORNER_GROUP));
    // The input's face 0 is still face 0 and alone in its group.
    assert_eq!(count(&out, "first"), 1);
    assert!(out.prim_groups()["first"].contains(0));
    let c = out
        .attrib(AttribClass::Primitive, "c")
        .unwrap()
        .as_f32()
        .unwrap();
    for (k, &ck) in c.iter().enumerate().take(6) {
        assert_eq!(ck, k as f32);
    }
    assert!(c
        .iter()
        .all(|&x| (0.0..6.0).contains(&x) && x.fract() == 0.0));
    // Each new point is its source corner's.
    let id = out
        .attrib(AttribClass::Point, "id")
        .unwrap()
        .as_i32()
        .unwrap();
    for (p, &i) in out.positions().iter().zip(id) {
        let src = cube.positions()[i as usize];
        assert!(
            (*p - src).length() < 0.1 * 3f32.sqrt() + 1e-5,
            "{p} from {src}"
        );
    }
    // Face corners keep their vertex values (the corner of a face sits
    // where its source corner was cut).
    let w = out
        .attrib(AttribClass::Vertex, "w")
        .unwrap()
        .as_f32()
        .unwrap();
    assert!(w.iter().all(|&x| (0.0..24.0).contains(&x)));
}

#[test]
fn an_open_grid_stays_manifold_and_keeps_its_outline() {
    let grid = primitives::grid(Vec2::new(2.0, 2.0), 4, 4);
    for affect in [Affect::Edges, Affect::Points] {
        let out = run(
            &grid,
            None,
            Bevel {
                affect,
                ..edges(0.1, 2)
            },
        );
        let mut uses = std::collections::HashMap::new();
        for k in 0..out.num_prims() {
            let q = out.prim_points(k);
            for j in 0..q.len() {
                let (a, b) = (q[j], q[(j + 1) % q.len()]);
                *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        assert!(uses.values().all(|&u| u <= 2), "{affect:?}");
        // Flat: the area is the grid's less the corners points cut off.
        assert!(
            area(&out) <= 4.0 + 1e-5 && area(&out) > 3.5,
            "{affect:?} {}",
            area(&out)
        );
    }
}

#[test]
fn one_and_two_threads_give_the_same_bytes() {
    let g = primitives::box_mesh(Vec3::ONE, [6, 5, 7]);
    for affect in [Affect::Edges, Affect::Points] {
        let how = Bevel {
            affect,
            ..edges(0.05, 3)
        };
        let in_pool = |n: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
                .install(|| run(&g, None, how.clone()).content_hash())
        };
        assert_eq!(in_pool(1), in_pool(2), "{affect:?}");
    }
}

#[test]
fn a_cancelled_bevel_stops() {
    let g = primitives::box_mesh(Vec3::ONE, [4, 4, 4]);
    let err = bevel(&g, None, &Bevel::default(), &|| true).unwrap_err();
    assert!(matches!(err, ModelError::Cancelled), "{err}");
}

#[test]
fn bad_parameters_and_inputs_are_refused_clearly() {
    let cube = primitives::cube(1.0);
    let refuse = |how: Bevel, word: &str| {
        let err = bevel(&cube, None, &how, &|| false).unwrap_err();
        assert!(err.to_string().contains(word), "{err}");
    };
    refuse(edges(0.1, 0), "segments");
    refuse(edges(-0.1, 1), "offset");
    refuse(edges(f32::NAN, 1), "offset");
    refuse(
        Bevel {
            profile: 1.5,
            ..Bevel::default()
        },
        "profile",
    );
    refuse(
        Bevel {
            flat_angle: Some(200.0),
            ..Bevel::default()
        },
        "flat angle",
    );
    // Three faces on one edge.
    let mut fin = Geometry::new();
    fin.add_points(&[
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Vec3::Z,
        Vec3::new(0.5, -1.0, 0.0),
    ]);
    for third in [2u32, 3, 4] {
        fin.add_polygon(&[0, 1, third]).unwrap();
    }
    let err = bevel(&fin, None, &Bevel::default(), &|| false).unwrap_err();
    assert!(err.to_string().contains("manifold"), "{err}");
    let mut line = Geometry::new();
    line.add_points(&[Vec3::ZERO, Vec3::X]);
    line.add_polyline(&[0, 1]).unwrap();
    let err = bevel(&line, None, &Bevel::default(), &|| false).unwrap_err();
    assert!(err.to_string().contains("polygons"), "{err}");
}

/// Faces of `g` that cross another face, by pymeshlab (PyPI).
fn self_intersections(g: &Geometry) -> Option<u64> {
    let script = r#"
import json, sys, numpy as np, pymeshlab
d = json.load(sys.stdin)
ms = pymeshlab.MeshSet()
ms.add_mesh(pymeshlab.Mesh(vertex_matrix=np.array(d["v"], dtype=float), face_matrix=np.array(d["f"], dtype=np.int32)))
ms.compute_selection_by_self_intersections_per_face()
print(json.dumps({"crossing": int(ms.current_mesh().selected_face_number())}))
"#;
    oracle(script, &mesh_json(g)).map(|r| r["crossing"].as_u64().unwrap())
}

#[test]
fn bevels_do_not_cross_themselves_pymeshlab_agrees() {
    let long = primitives::box_mesh(Vec3::new(1.0, 0.4, 2.0), [2, 1, 3]);
    let cases = [
        run(&primitives::cube(1.0), None, edges(0.3, 5)),
        run(&long, None, edges(0.15, 3)),
        // Clamped to just under the short edges' half.
        run(&long, None, edges(0.199, 2)),
        run(
            &long,
            None,
            Bevel {
                affect: Affect::Points,
                ..edges(0.3, 4)
            },
        ),
    ];
    for (k, out) in cases.iter().enumerate() {
        assert_eq!(euler_and_closed(out), (2, true), "case {k}");
        if let Some(n) = self_intersections(out) {
            assert_eq!(n, 0, "case {k}");
        }
    }
}

#[test]
fn a_straight_profile_in_segments_is_the_chamfer_and_a_square_one_the_box() {
    let cube = primitives::cube(1.0);
    let d = 0.2f32;
    let straight = run(
        &cube,
        None,
        Bevel {
            profile: 0.25,
            ..edges(d, 3)
        },
    );
    assert!((volume(&straight) - chamfer_volume(d as f64)).abs() < 1e-5);
    assert!((area(&straight) - chamfer_area(d as f64)).abs() < 1e-4);
    // Toward 1 the profile hugs the sharp edge: nearly the whole cube.
    let square = run(
        &cube,
        None,
        Bevel {
            profile: 1.0,
            ..edges(d, 4)
        },
    );
    assert_eq!(euler_and_closed(&square), (2, true));
    let v = volume(&square);
    assert!(v > rounded_volume(1.0, d as f64) && v <= 1.0 + 1e-6, "{v}");
}

/// Zero width (where an animated offset starts) gives the input's faces
/// back, edges and points mode alike, with the groups there and empty.
#[test]
fn a_zero_offset_changes_nothing() {
    let g = primitives::box_mesh(geode_geo::glam::Vec3::ONE, [2, 2, 2]);
    for affect in [Affect::Edges, Affect::Points] {
        let how = Bevel {
            affect,
            ..edges(0.0, 3)
        };
        let out = run(&g, None, how);
        assert_eq!(out.num_prims(), g.num_prims());
        assert_eq!(out.num_points(), g.num_points());
        assert!((area(&out) - 6.0).abs() < 1e-5, "{}", area(&out));
        if affect == Affect::Edges {
            assert_eq!(count(&out, EDGE_GROUP), 0);
        }
    }
}
