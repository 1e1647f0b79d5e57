//! Extrusion against closed-form answers: volumes of boxes, prisms and
//! frustums, areas of extruded curves, groups and attributes carried, and
//! closedness checked by trimesh (PyPI) as well as by edge counts.

mod common;
use common::*;

use geode_geo::glam::{Vec2, Vec3};
use geode_geo::{primitives, AttribClass, AttribData, Attribute, Geometry, Group, TypeInfo};
use geode_model::extrude::{extrude, Extrude, FRONT, SIDE};

/// The primitives of `g` whose centre is above `y`.
fn above(g: &Geometry, y: f32) -> Group {
    Group::from_flags((0..g.num_prims()).map(|k| {
        let q = g.prim_points(k);
        q.iter().map(|&p| g.positions()[p as usize].y).sum::<f32>() / q.len() as f32 > y
    }))
}

fn run(g: &Geometry, group: Option<&Group>, how: Extrude) -> Geometry {
    extrude(g, group, None, &how, &|| false).unwrap().geometry
}

fn count(g: &Geometry, group: &str) -> usize {
    g.prim_groups()[group].count()
}

#[test]
fn the_top_of_a_cube_extrudes_into_a_taller_box() {
    let cube = primitives::cube(1.0);
    let top = above(&cube, 0.4);
    let out = run(
        &cube,
        Some(&top),
        Extrude {
            distance: 0.5,
            ..Extrude::default()
        },
    );
    assert!((volume(&out) - 1.5).abs() < 1e-5, "{}", volume(&out));
    assert!(euler_and_closed(&out).1);
    assert_eq!((count(&out, FRONT), count(&out, SIDE)), (1, 4));
    assert_eq!(out.num_points(), 12);
}

#[test]
fn divisions_ring_the_walls_without_changing_the_volume() {
    let cube = primitives::cube(1.0);
    let top = above(&cube, 0.4);
    let out = run(
        &cube,
        Some(&top),
        Extrude {
            distance: 0.5,
            divisions: 4,
            ..Extrude::default()
        },
    );
    assert!((volume(&out) - 1.5).abs() < 1e-5);
    assert!(euler_and_closed(&out).1);
    assert_eq!(count(&out, SIDE), 16);
}

#[test]
fn inset_and_front_scale_make_the_closed_form_solids() {
    let cube = primitives::cube(1.0);
    let top = above(&cube, 0.4);
    // Inset 0.1 with the distance: the walls slant from the unit square to
    // the 0.8 square 0.5 above, a frustum (as Houdini's PolyExtrude).
    let inset = run(
        &cube,
        Some(&top),
        Extrude {
            distance: 0.5,
            inset: 0.1,
            ..Extrude::default()
        },
    );
    let want = 1.0 + 0.5 / 3.0 * (1.0 + 0.64 + 0.8);
    assert!(
        (volume(&inset) - want).abs() < 1e-5,
        "{} vs {want}",
        volume(&inset)
    );
    assert!(euler_and_closed(&inset).1);
    // A frustum: the front scaled by one half over a height of 1:
    // h / 3 (A1 + A2 + sqrt(A1 A2)).
    let frustum = run(
        &cube,
        Some(&top),
        Extrude {
            distance: 1.0,
            front_scale: 0.5,
            ..Extrude::default()
        },
    );
    let want = 1.0 + (1.0 + 0.25 + 0.5) / 3.0;
    assert!(
        (volume(&frustum) - want).abs() < 1e-5,
        "{} vs {want}",
        volume(&frustum)
    );
}

#[test]
fn individual_faces_each_get_their_own_walls() {
    let cube = primitives::cube(1.0);
    let out = run(
        &cube,
        None,
        Extrude {
            distance: 0.25,
            connected: false,
            ..Extrude::default()
        },
    );
    // Six slabs of 1 x 1 x 0.25 on the cube.
    assert!((volume(&out) - 2.5).abs() < 1e-5, "{}", volume(&out));
    assert_eq!((count(&out, FRONT), count(&out, SIDE)), (6, 24));
    assert_eq!(out.num_points(), 8 + 24);
}

#[test]
fn connected_faces_extrude_as_one_piece() {
    let boxy = primitives::box_mesh(Vec3::ONE, [2, 2, 2]);
    let top = above(&boxy, 0.4);
    assert_eq!(top.count(), 4);
    let out = run(
        &boxy,
        Some(&top),
        Extrude {
            distance: 0.5,
            ..Extrude::default()
        },
    );
    assert!((volume(&out) - 1.5).abs() < 1e-5, "{}", volume(&out));
    assert!(euler_and_closed(&out).1);
    // Walls only on the outline: two per side.
    assert_eq!(count(&out, SIDE), 8);
    // The top's middle point moved up with the front (no orphan left).
    assert!(out
        .positions()
        .iter()
        .any(|p| (*p - Vec3::new(0.0, 1.0, 0.0)).length() < 1e-6));
    assert!(!out
        .positions()
        .iter()
        .any(|p| (*p - Vec3::new(0.0, 0.5, 0.0)).length() < 1e-6));
}

#[test]
fn an_open_grid_with_its_back_becomes_a_closed_slab_trimesh_agrees() {
    let grid = primitives::grid(Vec2::new(2.0, 3.0), 4, 6);
    let out = run(
        &grid,
        None,
        Extrude {
            distance: 0.5,
            output_back: true,
            ..Extrude::default()
        },
    );
    assert!((volume(&out).abs() - 3.0).abs() < 1e-5, "{}", volume(&out));
    assert!(euler_and_closed(&out).1);
    let script = r#"
import json, sys, numpy as np, trimesh
d = json.load(sys.stdin)
m = trimesh.Trimesh(vertices=np.array(d["v"]), faces=np.array(d["f"]), process=True)
print(json.dumps({"watertight": bool(m.is_watertight), "consistent": bool(m.is_winding_consistent), "volume": float(m.volume)}))
"#;
    if let Some(r) = oracle(script, &mesh_json(&out)) {
        assert!(
            r["watertight"].as_bool().unwrap() && r["consistent"].as_bool().unwrap(),
            "{r}"
        );
        assert!(
            (r["volume"].as_f64().unwrap().abs() - 3.0).abs() < 1e-5,
            "{r}"
        );
    }
}

#[test]
fn twist_turns_the_front_about_the_piece_normal() {
    let cube = primitives::cube(1.0);
    let top = above(&cube, 0.4);
    let out = run(
        &cube,
        Some(&top),
        Extrude {
            distance: 1.0,
            twist: 45.0,
            ..Extrude::default()
        },
    );
    let front = &out.prim_groups()[FRONT];
    let k = (0..out.num_prims()).find(|&k| front.contains(k)).unwrap();
    for &p in out.prim_points(k) {
        let q = out.positions()[p as usize];
        assert!((q.y - 1.5).abs() < 1e-6);
        // A corner at 45° turned 45° lies on an axis.
        let r = Vec2::new(q.x, q.z);
        assert!((r.length() - 0.5f32.sqrt()).abs() < 1e-5);
        assert!(r.x.abs() < 1e-5 || r.y.abs() < 1e-5, "{r}");
    }
}

#[test]
fn attributes_follow_their_sources() {
    let mut cube = primitives::cube(1.0);
    let n = cube.num_points();
    let ids: Vec<i32> = (0..n as i32).collect();
    cube.set_attrib(
        AttribClass::Point,
        "id",
        Attribute::from_data(AttribData::Int(ids), TypeInfo::None),
    )
    .unwrap();
    let np = cube.num_prims();
    let colour: Vec<f32> = (0..np).map(|k| k as f32).collect();
    cube.set_attrib(
        AttribClass::Primitive,
        "c",
        Attribute::from_data(AttribData::Float(colour), TypeInfo::None),
    )
    .unwrap();
    let top = above(&cube, 0.4);
    let t = (0..np).find(|&k| top.contains(k)).unwrap();
    let out = run(
        &cube,
        Some(&top),
        Extrude {
            distance: 0.5,
            ..Extrude::default()
        },
    );
    let id = out
        .attrib(AttribClass::Point, "id")
        .unwrap()
        .as_i32()
        .unwrap();
    let c = out
        .attrib(AttribClass::Primitive, "c")
        .unwrap()
        .as_f32()
        .unwrap();
    for (k, &ck) in c.iter().enumerate() {
        if out.prim_groups()[SIDE].contains(k) || out.prim_groups()[FRONT].contains(k) {
            assert_eq!(ck, t as f32, "walls and front take the face's attributes");
        }
    }
    // A front point is its source point moved up.
    for (p, &i) in out.positions().iter().zip(id) {
        let src = cube.positions()[i as usize];
        assert!((*p - src).length() < 1e-6 || (*p - src - Vec3::Y * 0.5).length() < 1e-6);
    }
}

#[test]
fn a_curve_extrudes_into_a_strip() {
    let mut g = Geometry::new();
    g.add_points(&[Vec3::ZERO, Vec3::X, Vec3::new(3.0, 0.0, 0.0)]);
    g.add_polyline(&[0, 1, 2]).unwrap();
    let out = run(
        &g,
        None,
        Extrude {
            distance: 2.0,
            direction: Vec3::Z,
            divisions: 2,
            ..Extrude::default()
        },
    );
    assert_eq!(count(&out, SIDE), 4);
    let area: f32 = (0..out.num_prims())
        .filter(|&k| out.prim_groups()[SIDE].contains(k))
        .map(|k| {
            let q: Vec<Vec3> = out
                .prim_points(k)
                .iter()
                .map(|&p| out.positions()[p as usize])
                .collect();
            0.5 * ((q[1] - q[0]).cross(q[2] - q[0]).length()
                + (q[2] - q[0]).cross(q[3] - q[0]).length())
        })
        .sum();
    assert!((area - 6.0).abs() < 1e-5, "{area}");
}

#[test]
fn zero_divisions_are_refused() {
    let cube = primitives::cube(1.0);
    let err = extrude(
        &cube,
        None,
        None,
        &Extrude {
            divisions: 0,
            ..Extrude::default()
        },
        &|| false,
    )
    .unwrap_err();
    assert!(err.to_string().contains("divisions"), "{err}");
}

#[test]
fn one_and_two_threads_give_the_same_bytes() {
    let g = primitives::grid(Vec2::ONE, 60, 60);
    for connected in [true, false] {
        let how = Extrude {
            distance: 0.1,
            inset: 0.002,
            divisions: 2,
            twist: 10.0,
            connected,
            ..Extrude::default()
        };
        let in_pool = |n: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
                .install(|| run(&g, None, how.clone()).content_hash())
        };
        assert_eq!(in_pool(1), in_pool(2), "connected {connected}");
    }
}

#[test]
fn an_inset_past_where_a_fronts_edges_meet_is_reported() {
    // A unit cube's faces on their own: an inset of 0.5 shrinks each front
    // to a point; past it every front turns inside out.
    let cube = primitives::cube(1.0);
    let overrun = |inset: f32, twist: f32| {
        let how = Extrude {
            distance: 0.2,
            inset,
            twist,
            connected: false,
            ..Extrude::default()
        };
        extrude(&cube, None, None, &how, &|| false)
            .unwrap()
            .overrun_fronts
    };
    assert_eq!(overrun(0.0, 0.0), 0);
    assert_eq!(overrun(0.4, 0.0), 0);
    assert_eq!(overrun(0.6, 0.0), 6);
    assert_eq!(overrun(5.0, 0.0), 6);
    // A half turn reverses every edge, inset or not: not an overrun.
    assert_eq!(overrun(0.4, 180.0), 0);
    assert_eq!(overrun(0.6, 180.0), 6);
    // Connected, the cube's faces have no outline: nothing insets.
    let how = Extrude {
        inset: 5.0,
        ..Extrude::default()
    };
    assert_eq!(
        extrude(&cube, None, None, &how, &|| false)
            .unwrap()
            .overrun_fronts,
        0
    );
}
