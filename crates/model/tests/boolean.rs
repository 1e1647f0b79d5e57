//! Booleans against manifold3d (PyPI): the same operations on the same
//! meshes give the same volume and genus, and the result is closed; and
//! what geode adds: attributes carried, origin groups, shatter pieces,
//! errors that name the input, the same bytes on any thread count.

mod common;
use common::*;

use geode_geo::glam::{Mat4, Quat, Vec3};
use geode_geo::{ops, primitives, AttribClass, AttribData, Attribute, Geometry, TypeInfo};
use geode_model::boolean::{boolean, BooleanOp};

fn moved(mut g: Geometry, m: Mat4) -> Geometry {
    ops::transform(&mut g, m);
    g
}

fn run(a: &Geometry, b: &Geometry, op: BooleanOp) -> Geometry {
    boolean(a, b, op, &|| false).unwrap_or_else(|e| panic!("{op:?}: {e}"))
}

/// manifold3d's volume, genus and triangle count of `a op b` for each op.
const MANIFOLD: &str = r#"
import json, sys
import numpy as np
import manifold3d as m3
d = json.load(sys.stdin)
def solid(m):
    return m3.Manifold(m3.Mesh(vert_properties=np.array(m["v"], dtype=np.float32),
                               tri_verts=np.array(m["f"], dtype=np.uint32)))
a, b = solid(d["a"]), solid(d["b"])
out = {}
for op in d["ops"]:
    r = {"union": lambda: a + b, "intersect": lambda: a ^ b, "subtract": lambda: a - b}[op]()
    out[op] = {"volume": r.volume(), "genus": r.genus(), "status": str(r.status())}
print(json.dumps(out))
"#;

/// Checks geode's three booleans of `a` and `b` against manifold3d:
/// volume within `tol` (relative), the same genus, closed.
fn against_manifold(a: &Geometry, b: &Geometry, tol: f64) {
    let ops_ = ["union", "intersect", "subtract"];
    let input = serde_json::json!({ "a": mesh_json(a), "b": mesh_json(b), "ops": ops_ });
    let Some(want) = oracle(MANIFOLD, &input) else {
        return;
    };
    for name in ops_ {
        let op = BooleanOp::from_name(name).unwrap();
        let got = run(a, b, op);
        let w = &want[name];
        assert!(w["status"].as_str().unwrap().ends_with("NoError"), "{w}");
        let (euler, closed) = euler_and_closed(&got);
        assert!(closed, "{name}: the result has open or shared edges");
        let _ = components;
        let v = volume(&got);
        let wv = w["volume"].as_f64().unwrap();
        assert!(
            (v - wv).abs() <= tol * wv.abs().max(1e-9),
            "{name}: volume {v}, manifold3d {wv}"
        );
        // manifold3d's genus is 1 - chi / 2 over the whole mesh.
        if wv > 1e-9 {
            let chi = 2 - 2 * w["genus"].as_i64().unwrap();
            assert_eq!(euler, chi, "{name}: Euler characteristic");
        }
    }
}

/// Connected pieces of a polygon mesh (faces sharing points).
fn components(g: &Geometry) -> usize {
    let mut parent: Vec<u32> = (0..g.num_points() as u32).collect();
    fn find(p: &mut [u32], x: u32) -> u32 {
        let mut r = x;
        while p[r as usize] != r {
            r = p[r as usize];
        }
        let mut y = x;
        while p[y as usize] != r {
            let next = p[y as usize];
            p[y as usize] = r;
            y = next;
        }
        r
    }
    for k in 0..g.num_prims() {
        let q = g.prim_points(k);
        for w in q.windows(2) {
            let (x, y) = (find(&mut parent, w[0]), find(&mut parent, w[1]));
            parent[x as usize] = y;
        }
    }
    let used: std::collections::BTreeSet<u32> = (0..g.num_prims())
        .flat_map(|k| g.prim_points(k).to_vec())
        .map(|p| find(&mut parent, p))
        .collect();
    used.len()
}

#[test]
fn rotated_cubes_match_manifold3d() {
    let a = primitives::cube(1.0);
    let b = moved(
        primitives::cube(1.0),
        Mat4::from_rotation_translation(
            Quat::from_euler(geode_geo::glam::EulerRot::XYZ, 0.3, 0.5, 0.7),
            Vec3::new(0.4, 0.3, 0.2),
        ),
    );
    against_manifold(&a, &b, 1e-5);
}

#[test]
fn coplanar_and_touching_cubes_match_manifold3d() {
    let a = primitives::cube(1.0);
    // Sharing the top face's plane, half overlapping.
    let b = moved(
        primitives::cube(1.0),
        Mat4::from_translation(Vec3::new(0.5, 0.5, 0.0)),
    );
    against_manifold(&a, &b, 1e-5);
    // Stacked: touching along a whole face.
    let c = moved(
        primitives::cube(1.0),
        Mat4::from_translation(Vec3::new(0.0, 0.0, 1.0)),
    );
    let u = run(&a, &c, BooleanOp::Union);
    assert!((volume(&u) - 2.0).abs() < 1e-5, "{}", volume(&u));
    assert!(euler_and_closed(&u).1);
    // Touching along an edge only.
    let e = moved(
        primitives::cube(1.0),
        Mat4::from_translation(Vec3::new(1.0, 1.0, 0.0)),
    );
    against_manifold(&a, &e, 1e-5);
}

#[test]
fn a_torus_through_a_sphere_matches_manifold3d() {
    let a = primitives::uv_sphere(0.8, 48, 24);
    let b = moved(
        primitives::torus(0.9, 0.25, 48, 24),
        Mat4::from_rotation_x(0.4),
    );
    against_manifold(&a, &b, 1e-4);
}

#[test]
fn the_opensubdiv_car_matches_manifold3d() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/catmark_car.obj");
    let car =
        geode_io::read(std::path::Path::new(path), &geode_io::NoProgress).expect("the car reads");
    // The cage is open under the body (60 edges): each hole is closed
    // with a fan about its centre first.
    assert!(!euler_and_closed(&car).1);
    let car = fan_holes(&car);
    assert!(euler_and_closed(&car).1, "the car cage is closed");
    let bounds = ops::bounds(&car).expect("bounds");
    let center = (bounds.min + bounds.max) * 0.5;
    let size = bounds.max - bounds.min;
    let cutter = moved(
        primitives::uv_sphere(size.max_element() * 0.3, 40, 20),
        Mat4::from_translation(center + Vec3::new(size.x * 0.3, 0.0, 0.0)),
    );
    against_manifold(&car, &cutter, 1e-4);
}

/// `g` with each boundary loop closed by a fan of triangles about the
/// loop's centre (the loops' edges run the other way round).
fn fan_holes(g: &Geometry) -> Geometry {
    let mut count = std::collections::HashMap::new();
    for k in 0..g.num_prims() {
        let q = g.prim_points(k);
        for j in 0..q.len() {
            let (a, b) = (q[j], q[(j + 1) % q.len()]);
            *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    // Open edges as their faces run them; a hole runs them backwards.
    let mut next = std::collections::BTreeMap::new();
    for k in 0..g.num_prims() {
        let q = g.prim_points(k);
        for j in 0..q.len() {
            let (a, b) = (q[j], q[(j + 1) % q.len()]);
            if count[&(a.min(b), a.max(b))] == 1 {
                next.insert(b, a);
            }
        }
    }
    let mut out = g.clone();
    while let Some((&start, _)) = next.iter().next() {
        let mut lp = vec![start];
        let mut at = next.remove(&start).unwrap();
        while at != start {
            lp.push(at);
            at = next.remove(&at).expect("a closed loop");
        }
        let c = lp.iter().map(|&p| g.positions()[p as usize]).sum::<Vec3>() / lp.len() as f32;
        let centre = out.add_point(c);
        for j in 0..lp.len() {
            out.add_polygon(&[lp[j], lp[(j + 1) % lp.len()], centre])
                .unwrap();
        }
    }
    out
}

/// A hundred small spheres in a cloud, unioned one by one: closed, and
/// the volume manifold3d gives for the same union.
#[test]
fn a_hundred_spheres_union_matches_manifold3d() {
    let ball = primitives::uv_sphere(0.3, 16, 8);
    let at = |i: u32| {
        let h = |k: u64| geode_geo::random::unit(i as u64, k, 11) * 2.0;
        Vec3::new(h(0), h(1), h(2))
    };
    let balls: Vec<Geometry> = (0..100)
        .map(|i| moved(ball.clone(), Mat4::from_translation(at(i))))
        .collect();
    let mut acc = balls[0].clone();
    for b in &balls[1..] {
        acc = strip(run(&acc, b, BooleanOp::Union));
    }
    assert!(euler_and_closed(&acc).1);
    let script = r#"
import json, sys
import numpy as np
import manifold3d as m3
d = json.load(sys.stdin)
acc = None
for m in d["balls"]:
    s = m3.Manifold(m3.Mesh(vert_properties=np.array(m["v"], dtype=np.float32), tri_verts=np.array(m["f"], dtype=np.uint32)))
    acc = s if acc is None else acc + s
print(json.dumps({"volume": acc.volume()}))
"#;
    let input = serde_json::json!({ "balls": balls.iter().map(mesh_json).collect::<Vec<_>>() });
    if let Some(want) = oracle(script, &input) {
        let wv = want["volume"].as_f64().unwrap();
        let v = volume(&acc);
        assert!((v - wv).abs() <= 1e-4 * wv, "volume {v}, manifold3d {wv}");
    }
}

/// Only the positions and faces (the origin groups of one union would
/// collide with the next's).
fn strip(g: Geometry) -> Geometry {
    let tris: Vec<[u32; 3]> = (0..g.num_prims())
        .map(|k| {
            let p = g.prim_points(k);
            [p[0], p[1], p[2]]
        })
        .collect();
    Geometry::from_triangles(g.positions().to_vec(), &tris).unwrap()
}

#[test]
fn attributes_carry_by_source_and_barycentric_weights() {
    let mut a = primitives::cube(1.0);
    let mut b = moved(
        primitives::cube(1.0),
        Mat4::from_translation(Vec3::new(0.3, 0.4, 0.2)),
    );
    // A linear point attribute: interpolating it anywhere on a face gives
    // the exact linear function of position.
    for (g, side) in [(&mut a, 1), (&mut b, 2)] {
        let f: Vec<f32> = g
            .positions()
            .iter()
            .map(|p| 2.0 * p.x - p.y + 0.5 * p.z)
            .collect();
        g.set_attrib(
            AttribClass::Point,
            "f",
            Attribute::from_data(AttribData::Float(f), TypeInfo::None),
        )
        .unwrap();
        let n = g.num_prims();
        g.set_attrib(
            AttribClass::Primitive,
            "side",
            Attribute::from_data(AttribData::Int(vec![side; n]), TypeInfo::None),
        )
        .unwrap();
    }
    let u = run(&a, &b, BooleanOp::Union);
    let f = u.attrib(AttribClass::Point, "f").unwrap().as_f32().unwrap();
    for (p, v) in u.positions().iter().zip(f) {
        let want = 2.0 * p.x - p.y + 0.5 * p.z;
        assert!((v - want).abs() < 1e-4, "f at {p}: {v}, want {want}");
    }
    let side = u
        .attrib(AttribClass::Primitive, "side")
        .unwrap()
        .as_i32()
        .unwrap();
    let a_out = &u.prim_groups()["a_outside_b"];
    let b_out = &u.prim_groups()["b_outside_a"];
    for (k, s) in side.iter().enumerate() {
        assert_eq!(*s == 1, a_out.contains(k));
        assert_eq!(*s == 2, b_out.contains(k));
    }
    // The seam: points on both A's and B's faces lie on both surfaces.
    let seam = &u.point_groups()["seam"];
    assert!(seam.count() > 0);
    let on_box = |p: Vec3, c: Vec3| {
        let d = (p - c).abs();
        (d.max_element() - 0.5).abs() < 1e-5
    };
    for (k, p) in u.positions().iter().enumerate() {
        if seam.contains(k) {
            assert!(
                on_box(*p, Vec3::ZERO) && on_box(*p, Vec3::new(0.3, 0.4, 0.2)),
                "{p}"
            );
        }
    }
}

#[test]
fn a_uv_seam_inside_a_flat_face_stays_an_edge() {
    // A box whose top is four quads, with a uv seam down its middle (the
    // quads left of x = 0 have u = x, those right of it u = x + 10), drilled
    // through the seam. Coplanar triangles are one face for manifold only
    // where their uvs meet, so no output triangle spans the seam: every
    // triangle's corners come from one side.
    let mut a = primitives::box_mesh(Vec3::splat(2.0), [2, 1, 2]);
    let uv: Vec<geode_geo::glam::Vec2> = (0..a.num_prims())
        .flat_map(|k| {
            let q = a.prim_points(k);
            let centre_x: f32 = q.iter().map(|&i| a.positions()[i as usize].x).sum::<f32>();
            let shift = if centre_x > 0.0 { 10.0 } else { 0.0 };
            q.iter()
                .map(|&i| {
                    let p = a.positions()[i as usize];
                    geode_geo::glam::Vec2::new(p.x + shift, p.z)
                })
                .collect::<Vec<_>>()
        })
        .collect();
    a.set_attrib(
        AttribClass::Vertex,
        "uv",
        Attribute::from_data(AttribData::Vec2(uv), TypeInfo::None),
    )
    .unwrap();
    let drill = primitives::tube(0.5, 3.0, 24, 1, true);
    let out = run(&a, &drill, BooleanOp::Subtract);
    let uv = out
        .attrib(AttribClass::Vertex, "uv")
        .unwrap()
        .as_vec2()
        .unwrap();
    let mut top = 0;
    for k in 0..out.num_prims() {
        let q = out.prim_points(k);
        let p: Vec<Vec3> = q.iter().map(|&i| out.positions()[i as usize]).collect();
        if p.iter().any(|p| (p.y - 1.0).abs() > 1e-5) {
            continue;
        }
        top += 1;
        let shifts: Vec<f32> = out
            .prim_vertex_range(k)
            .zip(&p)
            .map(|(v, p)| uv[v].x - p.x)
            .collect();
        for s in &shifts {
            assert!(
                (s - shifts[0]).abs() < 1e-4 && (s.abs() < 1e-4 || (s - 10.0).abs() < 1e-4),
                "triangle {k} spans the seam: u - x = {shifts:?}"
            );
        }
    }
    assert!(top > 0);
}

#[test]
fn shatter_gives_the_pieces_outside_and_inside() {
    let a = primitives::cube(1.0);
    let b = moved(
        primitives::uv_sphere(0.5, 32, 16),
        Mat4::from_translation(Vec3::new(0.5, 0.0, 0.0)),
    );
    let pieces = run(&a, &b, BooleanOp::Shatter);
    let piece = pieces
        .attrib(AttribClass::Primitive, "piece")
        .unwrap()
        .as_i32()
        .unwrap();
    let part = |k: i32| {
        let tris: Vec<[u32; 3]> = (0..pieces.num_prims())
            .filter(|&j| piece[j] == k)
            .map(|j| {
                let p = pieces.prim_points(j);
                [p[0], p[1], p[2]]
            })
            .collect();
        Geometry::from_triangles(pieces.positions().to_vec(), &tris).unwrap()
    };
    let (outside, inside) = (part(0), part(1));
    assert!(euler_and_closed(&outside).1 && euler_and_closed(&inside).1);
    let sub = volume(&run(&a, &b, BooleanOp::Subtract));
    let int = volume(&run(&a, &b, BooleanOp::Intersect));
    assert!((volume(&outside) - sub).abs() < 1e-6);
    assert!((volume(&inside) - int).abs() < 1e-6);
    assert!(
        (sub + int - 1.0).abs() < 1e-5,
        "the pieces make the cube: {}",
        sub + int
    );
}

#[test]
fn an_open_input_is_refused_by_name() {
    let a = primitives::cube(1.0);
    let open = primitives::grid(geode_geo::glam::Vec2::ONE, 4, 4);
    let err = boolean(&a, &open, BooleanOp::Union, &|| false)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("input B is not a closed manifold mesh"),
        "{err}"
    );
    assert!(err.contains("open edges"), "{err}");
    let mut curve = Geometry::new();
    curve.add_points(&[Vec3::ZERO, Vec3::X]);
    curve.add_polyline(&[0, 1]).unwrap();
    let err = boolean(&curve, &a, BooleanOp::Union, &|| false)
        .unwrap_err()
        .to_string();
    assert!(err.contains("input A") && err.contains("polyline"), "{err}");
}

/// An inside-out solid is named, not cut as given (manifold would return
/// two coincident copies of the other shell).
#[test]
fn an_inside_out_input_is_refused_by_name() {
    let a = primitives::cube(1.0);
    let mut b = moved(
        primitives::cube(1.0),
        Mat4::from_translation(Vec3::splat(0.5)),
    );
    ops::reverse_prims(&mut b, None);
    let err = boolean(&a, &b, BooleanOp::Union, &|| false)
        .unwrap_err()
        .to_string();
    assert!(err.contains("input B is inside out"), "{err}");
}

/// With nothing on one side the result is Houdini's: the other side for a
/// union, A less nothing is A, anything met with nothing is nothing.
#[test]
fn an_empty_side_gives_houdinis_answers() {
    let a = primitives::cube(1.0);
    let none = Geometry::new();
    let prims = |x: &Geometry, y: &Geometry, op| run(x, y, op).num_prims();
    assert_eq!(prims(&a, &none, BooleanOp::Union), a.num_prims());
    assert_eq!(prims(&none, &a, BooleanOp::Union), a.num_prims());
    assert_eq!(prims(&a, &none, BooleanOp::Subtract), a.num_prims());
    assert_eq!(prims(&a, &none, BooleanOp::Shatter), a.num_prims());
    assert_eq!(prims(&none, &a, BooleanOp::Subtract), 0);
    assert_eq!(prims(&a, &none, BooleanOp::Intersect), 0);
    assert_eq!(prims(&none, &none, BooleanOp::Union), 0);
}

#[test]
fn cancelled_before_the_boolean() {
    let a = primitives::cube(1.0);
    let err = boolean(&a, &a, BooleanOp::Union, &|| true).unwrap_err();
    assert!(matches!(err, geode_model::ModelError::Cancelled), "{err}");
}

/// A cancel during manifold's own work returns at once: the boolean runs
/// on a thread of its own that the cook no longer waits for.
#[test]
fn cancelled_during_the_boolean() {
    let a = primitives::uv_sphere(1.0, 500, 250);
    let b = moved(a.clone(), Mat4::from_translation(Vec3::new(0.5, 0.3, 0.2)));
    let start = std::time::Instant::now();
    let cancel = || start.elapsed() > std::time::Duration::from_millis(300);
    let err = boolean(&a, &b, BooleanOp::Union, &cancel).unwrap_err();
    assert!(matches!(err, geode_model::ModelError::Cancelled), "{err}");
}

#[test]
fn one_and_three_threads_give_the_same_bytes() {
    // Above manifold's parallel thresholds (1e5 elements), so that on TBB
    // its threads' findings are put in order: 160k triangles a side.
    let a = primitives::uv_sphere(0.8, 400, 200);
    let b = moved(
        primitives::torus(0.9, 0.25, 400, 200),
        Mat4::from_rotation_x(0.4),
    );
    let in_pool = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| run(&a, &b, BooleanOp::Subtract).content_hash())
    };
    assert_eq!(in_pool(1), in_pool(3));
}
