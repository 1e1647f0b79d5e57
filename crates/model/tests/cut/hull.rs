//! `convex_hull` against scipy's Qhull: random, degenerate, coplanar and
//! lattice clouds, attributes carried.

use super::*;

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

#[test]
fn the_hull_of_a_lattice_on_a_cubes_surface_is_the_cube() {
    let lattice = primitives::box_mesh(Vec3::splat(2.0), [20, 20, 20]);
    check_hull(&lattice, "lattice");
    let h = convex_hull(&lattice, true, &never).unwrap();
    assert_eq!(h.num_points(), 8);
    assert_eq!(h.num_prims(), 12);
    assert!((volume(&h) - 8.0).abs() < 1e-6);
}
