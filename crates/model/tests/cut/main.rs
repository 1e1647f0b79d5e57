//! The cut family (clip, mirror, polyfill, convex hull, revolve) against
//! answers from outside geode: trimesh (closed, wound, volume, area),
//! manifold3d (a plane trim of the same mesh), scipy (Qhull's hull) and
//! closed forms.

#[path = "../common/mod.rs"]
mod common;

mod clip;
mod fill;
mod hull;
mod mirror;
mod revolve;

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

/// scipy's (Qhull's) hull: volume (area in 2D) and vertex positions.
const SCIPY_HULL: &str = r#"
import sys, json, numpy as np
from scipy.spatial import ConvexHull
d = json.load(sys.stdin)
p = np.array(d['p'], dtype=np.float64)
h = ConvexHull(p)
print(json.dumps({'volume': float(h.volume), 'vertices': p[h.vertices].tolist()}))
"#;
