//! The surface kernels against answers from outside geode: smoothing
//! against the plane and sphere it should keep or approach, peak and
//! mountain against the sphere's analytic normals, bounds against the
//! analytic extents of rotated boxes and spheres and against trimesh's
//! oriented box and minimum sphere, match size against hand-computed
//! boxes; and byte-identical results on one and two threads.

mod common;

use common::{mesh_json, oracle, volume};
use geode_geo::glam::{Mat3, Mat4, Quat, Vec2, Vec3};
use geode_geo::ops::{self, Aabb};
use geode_geo::{
    primitives, random, AttribClass, AttribData, Attribute, Geometry, Group, TypeInfo,
};
use geode_model::bound::{
    axis_aligned_box, bounding_sphere, box_geometry, match_size, oriented_box, Justify, ScaleMode,
};
use geode_model::deform::{area_weighted_normals, mountain, peak, Fractal};
use geode_model::smooth::{smooth, SmoothMethod, SmoothOptions};
use geode_model::ModelError;

fn never() -> bool {
    false
}

fn on_threads<T: Send>(n: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .unwrap()
        .install(f)
}

fn bits(g: &Geometry) -> Vec<[u32; 3]> {
    g.positions()
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect()
}

fn options(method: SmoothMethod, iterations: u32) -> SmoothOptions<'static> {
    SmoothOptions {
        method,
        strength: 0.5,
        iterations,
        pin_border: false,
        pinned: None,
        keep_volume: false,
    }
}

const TAUBIN: SmoothMethod = SmoothMethod::Taubin { pass_band: 0.1 };

/// A 10 x 10 grid of 60 x 60 quads in XZ, each point lifted by up to
/// ±0.1 along Y.
fn noisy_plane() -> Geometry {
    let mut g = primitives::grid(Vec2::splat(10.0), 60, 60);
    for (i, p) in g.positions_mut().iter_mut().enumerate() {
        p.y = 0.2 * (random::unit(7, i as u64, 0) - 0.5);
    }
    g
}

fn radii(g: &Geometry) -> (f64, f64, f64) {
    let r: Vec<f64> = g
        .positions()
        .iter()
        .map(|p| p.as_dvec3().length())
        .collect();
    let mean = r.iter().sum::<f64>() / r.len() as f64;
    let (lo, hi) = r
        .iter()
        .fold((f64::MAX, 0.0f64), |(lo, hi), &x| (lo.min(x), hi.max(x)));
    (mean, lo, hi)
}

fn max_abs_y(g: &Geometry) -> f32 {
    g.positions().iter().map(|p| p.y.abs()).fold(0.0, f32::max)
}

fn rms_y(g: &Geometry) -> f64 {
    let sum: f64 = g.positions().iter().map(|p| f64::from(p.y).powi(2)).sum();
    (sum / g.num_points() as f64).sqrt()
}

/// White noise on a plane under Laplacian smoothing diffuses: each point
/// becomes an average over an area growing with the iterations, so the
/// noise's RMS falls as 1/sqrt(iterations) (ten times the iterations, about
/// 0.32 times the RMS), and the largest offset with it.
#[test]
fn laplacian_smoothing_flattens_a_noisy_plane() {
    let input = noisy_plane();
    let smoothed = |iterations| {
        let mut g = input.clone();
        smooth(
            &mut g,
            &options(SmoothMethod::Laplacian, iterations),
            &never,
        )
        .unwrap();
        g
    };
    let (g30, g300) = (smoothed(30), smoothed(300));
    let (before, after) = (max_abs_y(&input), max_abs_y(&g300));
    let ratio = rms_y(&g300) / rms_y(&g30);
    eprintln!(
        "max |y|: {before} -> {} (30) -> {after} (300); rms ratio {ratio}",
        max_abs_y(&g30)
    );
    assert!(after < before / 10.0, "max |y| {before} -> {after}");
    assert!((0.25..0.45).contains(&ratio), "rms ratio {ratio}");
}

#[test]
fn taubin_keeps_a_spheres_radius_where_laplacian_shrinks_it() {
    let sphere = primitives::uv_sphere(1.0, 64, 32);
    let mut taubin = sphere.clone();
    smooth(&mut taubin, &options(TAUBIN, 20), &never).unwrap();
    let mut laplacian = sphere.clone();
    smooth(
        &mut laplacian,
        &options(SmoothMethod::Laplacian, 20),
        &never,
    )
    .unwrap();
    let (t, l) = (radii(&taubin), radii(&laplacian));
    eprintln!("taubin radius mean/min/max {t:?}, laplacian {l:?}");
    assert!((t.0 - 1.0).abs() < 0.01, "taubin mean radius {}", t.0);
    assert!(t.1 > 0.98 && t.2 < 1.02, "taubin radii {t:?}");
    assert!(l.0 < 0.97, "laplacian mean radius {}", l.0);
}

#[test]
fn pinned_points_do_not_move_by_a_bit() {
    let input = noisy_plane();
    let mut g = input.clone();
    let opts = SmoothOptions {
        pin_border: true,
        ..options(SmoothMethod::Laplacian, 10)
    };
    smooth(&mut g, &opts, &never).unwrap();
    let (a, b) = (bits(&input), bits(&g));
    let mut border = 0;
    for (i, p) in input.positions().iter().enumerate() {
        let on_edge = p.x.abs() == 5.0 || p.z.abs() == 5.0;
        if on_edge {
            border += 1;
            assert_eq!(a[i], b[i], "border point {i} moved");
        } else {
            assert_ne!(a[i], b[i], "interior point {i} did not move");
        }
    }
    assert_eq!(border, 4 * 60);

    let sphere = primitives::uv_sphere(1.0, 32, 16);
    let pinned = Group::from_flags(sphere.positions().iter().map(|p| p.y > 0.5));
    let mut s = sphere.clone();
    let opts = SmoothOptions {
        pinned: Some(&pinned),
        ..options(TAUBIN, 10)
    };
    smooth(&mut s, &opts, &never).unwrap();
    let (a, b) = (bits(&sphere), bits(&s));
    for i in pinned.members() {
        assert_eq!(a[i], b[i], "pinned point {i} moved");
    }
    assert!(pinned.count() > 10);
}

#[test]
fn volume_keeping_restores_a_closed_meshs_volume() {
    for (name, mesh) in [
        ("sphere", primitives::uv_sphere(1.0, 48, 24)),
        (
            "box",
            primitives::box_mesh(Vec3::new(2.0, 1.0, 0.5), [8, 4, 2]),
        ),
        ("torus", primitives::torus(1.0, 0.3, 48, 16)),
    ] {
        let before = volume(&mesh);
        for keep in [false, true] {
            let mut g = mesh.clone();
            let opts = SmoothOptions {
                keep_volume: keep,
                ..options(SmoothMethod::Laplacian, 10)
            };
            smooth(&mut g, &opts, &never).unwrap();
            let relative = (volume(&g) / before - 1.0).abs();
            eprintln!("{name} keep {keep}: volume off by {relative:.2e}");
            if keep {
                assert!(relative < 1e-4, "{name}: {relative}");
            } else {
                assert!(relative > 1e-2, "{name}: plain smoothing should shrink");
            }
        }
    }
    // With pins the free points alone restore it.
    let mesh = primitives::uv_sphere(1.0, 48, 24);
    let pinned = Group::from_flags(mesh.positions().iter().map(|p| p.x > 0.6));
    let mut g = mesh.clone();
    let opts = SmoothOptions {
        keep_volume: true,
        pinned: Some(&pinned),
        ..options(SmoothMethod::Laplacian, 10)
    };
    smooth(&mut g, &opts, &never).unwrap();
    let relative = (volume(&g) / volume(&mesh) - 1.0).abs();
    assert!(relative < 1e-4, "pinned: {relative}");
}

#[test]
fn volume_keeping_refuses_an_open_mesh() {
    let mut g = noisy_plane();
    let opts = SmoothOptions {
        keep_volume: true,
        ..options(SmoothMethod::Laplacian, 1)
    };
    match smooth(&mut g, &opts, &never) {
        Err(ModelError::NotClosed { why, .. }) => assert!(why.contains("edges"), "{why}"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_polylines_neighbours_are_its_adjacent_points() {
    // A zigzag: one step of strength 1/2 puts every inner point on the
    // mean of its two neighbours' mean and itself: y = 0; the ends stay.
    let n = 9;
    let pts: Vec<Vec3> = (0..n)
        .map(|i| Vec3::new(i as f32, if i % 2 == 0 { 1.0 } else { -1.0 }, 0.0))
        .collect();
    let mut g = Geometry::new();
    g.add_points(&pts);
    g.add_polyline(&(0..n as u32).collect::<Vec<_>>()).unwrap();
    let opts = SmoothOptions {
        pin_border: true,
        ..options(SmoothMethod::Laplacian, 1)
    };
    smooth(&mut g, &opts, &never).unwrap();
    let p = g.positions();
    assert_eq!(p[0], pts[0]);
    assert_eq!(p[n - 1], pts[n - 1]);
    for (i, q) in p.iter().enumerate().take(n - 1).skip(1) {
        assert_eq!(*q, Vec3::new(i as f32, 0.0, 0.0), "point {i}");
    }
}

#[test]
fn smoothing_is_the_same_bytes_on_one_and_two_threads() {
    let mut noisy = primitives::uv_sphere(1.0, 256, 128);
    for (i, p) in noisy.positions_mut().iter_mut().enumerate() {
        *p *= 1.0 + 0.05 * random::unit(3, i as u64, 0);
    }
    let run = |threads| {
        on_threads(threads, || {
            let mut g = noisy.clone();
            let opts = SmoothOptions {
                keep_volume: true,
                ..options(TAUBIN, 5)
            };
            smooth(&mut g, &opts, &never).unwrap();
            bits(&g)
        })
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn smoothing_stops_when_cancelled() {
    let mut g = noisy_plane();
    let r = smooth(&mut g, &options(SmoothMethod::Laplacian, 5), &|| true);
    assert!(matches!(r, Err(ModelError::Cancelled)));
}

fn with_point_normals(mut g: Geometry, n: Vec<Vec3>) -> Geometry {
    g.set_attrib(
        AttribClass::Point,
        "N",
        Attribute::from_data(AttribData::Vec3(n), TypeInfo::Normal),
    )
    .unwrap();
    g
}

#[test]
fn peak_moves_a_unit_sphere_to_radius_one_plus_d() {
    let sphere = primitives::uv_sphere(1.0, 96, 48);
    let d = 0.25;
    // The exact normal (the position) gives the exact radius...
    let exact: Vec<Vec3> = sphere.positions().iter().map(|p| p.normalize()).collect();
    let mut g = sphere.clone();
    peak(&mut g, &exact, None, d, &never).unwrap();
    for p in g.positions() {
        assert!((p.length() - 1.25).abs() < 2e-6, "{p} at {}", p.length());
    }
    // ...and area-weighted normals of the mesh nearly so.
    let mut g = sphere.clone();
    let computed = area_weighted_normals(&g);
    peak(&mut g, &computed, None, d, &never).unwrap();
    let worst = g
        .positions()
        .iter()
        .map(|p| (p.length() - 1.25).abs())
        .fold(0.0, f32::max);
    eprintln!("computed normals: radius off by at most {worst}");
    assert!(worst < 1e-4, "{worst}");
    // A group moves alone.
    let upper = Group::from_flags(sphere.positions().iter().map(|p| p.y > 0.0));
    let mut g = sphere.clone();
    peak(&mut g, &exact, Some(&upper), -d, &never).unwrap();
    for (i, (p, q)) in sphere.positions().iter().zip(g.positions()).enumerate() {
        let expected = if upper.contains(i) { 0.75 } else { p.length() };
        assert!((q.length() - expected).abs() < 2e-6, "point {i}");
    }
}

/// A smooth analytic basis in [-1, 1] (the node passes geode-vex's noise).
fn waves(q: [f32; 3]) -> f32 {
    (q[0] * 1.7).sin() * (q[1] * 2.3).cos() + 0.5 * (q[2] * 3.1).sin()
}

fn fractal(seed: u64) -> Fractal {
    Fractal {
        height: 0.2,
        element_size: 0.5,
        offset: Vec3::new(0.1, 0.2, 0.3),
        octaves: 5,
        roughness: 0.5,
        lacunarity: 2.0,
        seed,
    }
}

#[test]
fn mountain_moves_along_normals_within_its_height_and_the_same_everywhere() {
    let sphere = primitives::uv_sphere(1.0, 128, 64);
    let normals: Vec<Vec3> = sphere.positions().iter().map(|p| p.normalize()).collect();
    let run = |seed, threads| {
        on_threads(threads, || {
            let mut g = sphere.clone();
            mountain(&mut g, &normals, None, &fractal(seed), &waves, &never).unwrap();
            g
        })
    };
    let g = run(1, 2);
    assert_eq!(bits(&g), bits(&run(1, 1)), "thread counts");
    assert_eq!(bits(&g), bits(&run(1, 2)), "twice");
    let mut spread = 0.0f32;
    for ((p, q), n) in sphere.positions().iter().zip(g.positions()).zip(&normals) {
        let d = *q - *p;
        assert!(d.length() <= 0.2 + 1e-6, "moved {}", d.length());
        assert!(
            d.cross(*n).length() <= 1e-6 * (1.0 + d.length() * 10.0),
            "tangential {d}"
        );
        spread = spread.max(d.length());
    }
    assert!(spread > 0.05, "hardly moved: {spread}");
    let other = run(2, 2);
    let differ = g
        .positions()
        .iter()
        .zip(other.positions())
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        differ > g.num_points() * 9 / 10,
        "seeds 1 and 2 differ at {differ}"
    );
    // A basis beyond [-1, 1] is clamped: the bound holds for any noise.
    let mut wild = sphere.clone();
    mountain(
        &mut wild,
        &normals,
        None,
        &fractal(1),
        &|q| 50.0 * waves(q),
        &never,
    )
    .unwrap();
    for (p, q) in sphere.positions().iter().zip(wild.positions()) {
        assert!((*q - *p).length() <= 0.2 + 1e-6);
    }
}

#[test]
fn mountain_refuses_a_zero_element_size() {
    let mut g = primitives::uv_sphere(1.0, 8, 4);
    let n = area_weighted_normals(&g);
    let f = Fractal {
        element_size: 0.0,
        ..fractal(1)
    };
    let e = mountain(&mut g, &n, None, &f, &waves, &never).unwrap_err();
    assert!(e.to_string().contains("element size"), "{e}");
}

/// A rotation about an oblique axis.
fn tilt() -> Quat {
    Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7)
}

fn rotated(g: &Geometry, q: Quat, t: Vec3) -> Geometry {
    ops::transformed(g, Mat4::from_rotation_translation(q, t))
}

#[test]
fn the_axis_aligned_box_of_a_rotated_box_has_the_analytic_extents() {
    let half = Vec3::new(1.0, 0.5, 0.25);
    let (q, t) = (tilt(), Vec3::new(3.0, -1.0, 2.0));
    let g = rotated(&primitives::box_mesh(2.0 * half, [3, 3, 3]), q, t);
    let b = axis_aligned_box(g.positions()).unwrap();
    let m = Mat3::from_quat(q);
    // Half extent along world axis i: Σ_j |R_ij| h_j.
    let rows = m.transpose();
    let expected = Vec3::new(
        rows.x_axis.abs().dot(half),
        rows.y_axis.abs().dot(half),
        rows.z_axis.abs().dot(half),
    );
    assert!((b.min - (t - expected)).abs().max_element() < 1e-5, "{b:?}");
    assert!((b.max - (t + expected)).abs().max_element() < 1e-5, "{b:?}");
}

fn contains_all(b: &geode_model::bound::OrientedBox, points: &[Vec3], tol: f32) -> bool {
    points.iter().all(|p| {
        let d = *p - b.center;
        (0..3).all(|k| d.dot(b.axes[k]).abs() <= b.half_size[k] + tol)
    })
}

#[test]
fn the_oriented_box_of_a_rotated_box_is_that_box() {
    let size = Vec3::new(2.0, 1.0, 0.5);
    let (q, t) = (tilt(), Vec3::new(3.0, -1.0, 2.0));
    for divisions in [[1, 1, 1], [6, 4, 3]] {
        let g = rotated(&primitives::box_mesh(size, divisions), q, t);
        let obb = oriented_box(g.positions(), &never).unwrap().unwrap();
        let aabb = axis_aligned_box(g.positions()).unwrap();
        let aabb_volume = aabb.size().as_dvec3().element_product();
        eprintln!(
            "divisions {divisions:?}: obb {} (true 1), aabb {aabb_volume}",
            obb.volume()
        );
        assert!((obb.volume() - 1.0).abs() < 0.01, "{obb:?}");
        assert!(aabb_volume > 1.5, "{aabb_volume}");
        assert!(contains_all(&obb, g.positions(), 1e-5));
        // Each box axis is one of the rotated box's.
        let frame = Mat3::from_quat(q);
        for a in obb.axes {
            let best = [frame.x_axis, frame.y_axis, frame.z_axis]
                .iter()
                .map(|b| a.dot(*b).abs())
                .fold(0.0, f32::max);
            assert!(best > 0.9999, "axis {a}");
        }
        assert!((obb.center - t).length() < 1e-5);
    }
    // Random points inside the rotated box and its eight corners.
    let half = size * 0.5;
    let mut pts: Vec<Vec3> = (0..20_000u64)
        .map(|i| {
            let u = Vec3::new(
                random::unit(5, i, 0),
                random::unit(5, i, 1),
                random::unit(5, i, 2),
            );
            q * ((u * 2.0 - 1.0) * half) + t
        })
        .collect();
    for c in 0..8 {
        let s = Vec3::new(
            if c & 1 == 0 { -1.0 } else { 1.0 },
            if c & 2 == 0 { -1.0 } else { 1.0 },
            if c & 4 == 0 { -1.0 } else { 1.0 },
        );
        pts.push(q * (s * half) + t);
    }
    let obb = oriented_box(&pts, &never).unwrap().unwrap();
    assert!((obb.volume() - 1.0).abs() < 0.01, "cloud: {}", obb.volume());
    assert!(contains_all(&obb, &pts, 1e-5));
}

#[test]
fn a_flat_point_set_gets_a_flat_box() {
    let g = rotated(
        &primitives::grid(Vec2::new(4.0, 2.0), 8, 8),
        tilt(),
        Vec3::ZERO,
    );
    let obb = oriented_box(g.positions(), &never).unwrap().unwrap();
    let mut h = obb.half_size.to_array();
    h.sort_by(f32::total_cmp);
    assert!(h[0] < 1e-5, "{h:?}");
    assert!(
        (h[1] - 1.0).abs() < 1e-5 && (h[2] - 2.0).abs() < 1e-5,
        "{h:?}"
    );
}

/// Points spread evenly over a sphere (Fibonacci lattice).
fn fibonacci_sphere(n: usize, radius: f32, center: Vec3) -> Vec<Vec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - y * y).sqrt();
            let phi = golden * i as f64;
            let p = geode_geo::glam::DVec3::new(r * phi.cos(), y, r * phi.sin());
            (p * f64::from(radius)).as_vec3() + center
        })
        .collect()
}

#[test]
fn the_bounding_sphere_of_points_on_a_sphere_is_that_sphere() {
    let center = Vec3::new(1.0, -2.0, 3.0);
    let pts = fibonacci_sphere(5000, 2.5, center);
    let s = bounding_sphere(&pts, &never).unwrap().unwrap();
    assert!((s.radius - 2.5).abs() < 1e-4, "{s:?}");
    assert!((s.center - center).length() < 1e-4, "{s:?}");
    // A hemisphere's cap: the minimum is the rim's circle, not the sphere.
    let cap: Vec<Vec3> = pts
        .iter()
        .copied()
        .filter(|p| p.y - center.y > 1.5)
        .collect();
    let s = bounding_sphere(&cap, &never).unwrap().unwrap();
    let rim = (2.5f32 * 2.5 - 1.5 * 1.5).sqrt();
    // At most the rim circle's ball (it holds the cap), at least half the
    // widest pair's distance.
    let widest = cap
        .iter()
        .flat_map(|p| cap.iter().map(move |q| p.distance(*q)))
        .fold(0.0, f32::max);
    assert!(
        s.radius <= rim + 1e-4 && s.radius >= widest / 2.0 - 1e-4,
        "{s:?} rim {rim}"
    );
    for p in &cap {
        assert!(p.distance(s.center) <= s.radius);
    }
}

#[test]
fn bounds_are_the_same_bytes_on_one_and_two_threads() {
    let g = rotated(&primitives::torus(1.0, 0.3, 200, 60), tilt(), Vec3::X);
    let run = |threads| {
        on_threads(threads, || {
            (
                oriented_box(g.positions(), &never).unwrap(),
                bounding_sphere(g.positions(), &never).unwrap(),
            )
        })
    };
    assert_eq!(run(1), run(2));
}

/// Trimesh's oriented box (the smallest over every hull face direction)
/// and its minimum sphere (furthest-site Voronoi vertices only, so not
/// always minimal: an enclosing sphere ours must not exceed), and the
/// minimum sphere as a convex program (scipy's SLSQP: least r² with every
/// hull vertex within r of the centre).
const PYTHON_BOUNDS: &str = r#"
import json, sys
import numpy as np
import trimesh
from scipy.optimize import minimize
from scipy.spatial import ConvexHull
d = json.load(sys.stdin)
v = np.array(d["v"], dtype=np.float64)
_, extents = trimesh.bounds.oriented_bounds(v)
_, trimesh_radius = trimesh.nsphere.minimum_nsphere(v)
h = v[ConvexHull(v).vertices]
c0 = (h.max(0) + h.min(0)) / 2
x0 = np.append(c0, ((h - c0) ** 2).sum(1).max())
inside = {"type": "ineq", "fun": lambda x: x[3] - ((h - x[:3]) ** 2).sum(1),
          "jac": lambda x: np.hstack([2 * (h - x[:3]), np.ones((len(h), 1))])}
r = minimize(lambda x: x[3], x0, jac=lambda x: np.array([0, 0, 0, 1.0]),
             constraints=[inside], method="SLSQP", options={"ftol": 1e-15, "maxiter": 1000})
c = r.x[:3]
print(json.dumps({"obb_volume": float(np.prod(extents)), "trimesh_radius": float(trimesh_radius),
                  "radius": float(np.sqrt(((v - c) ** 2).sum(1).max())),
                  "center": [float(x) for x in c]}))
"#;

#[test]
fn bounds_match_trimesh_and_scipy() {
    let mut noisy = primitives::uv_sphere(1.0, 40, 20);
    for (i, p) in noisy.positions_mut().iter_mut().enumerate() {
        *p *= Vec3::new(1.5, 1.0, 0.6) * (1.0 + 0.1 * random::unit(9, i as u64, 0));
    }
    let cases = [
        (
            "torus",
            rotated(&primitives::torus(1.0, 0.3, 48, 16), tilt(), Vec3::X),
        ),
        (
            "noisy ellipsoid",
            rotated(&noisy, tilt(), Vec3::new(0.0, 2.0, 0.0)),
        ),
        (
            "tube",
            rotated(&primitives::tube(0.5, 3.0, 24, 4, true), tilt(), Vec3::ZERO),
        ),
    ];
    for (name, g) in cases {
        let Some(r) = oracle(PYTHON_BOUNDS, &mesh_json(&g)) else {
            eprintln!("skipping: trimesh or scipy is not installed");
            return;
        };
        let obb = oriented_box(g.positions(), &never).unwrap().unwrap();
        let s = bounding_sphere(g.positions(), &never).unwrap().unwrap();
        let number = |k: &str| r[k].as_f64().unwrap();
        eprintln!(
            "{name}: obb {} (trimesh {}), sphere {} (scipy {}, trimesh {})",
            obb.volume(),
            number("obb_volume"),
            s.radius,
            number("radius"),
            number("trimesh_radius")
        );
        assert!(
            number("obb_volume") >= obb.volume() * 0.99,
            "{name}: trimesh's box is smaller"
        );
        let radius = f64::from(s.radius);
        assert!((radius - number("radius")).abs() < 1e-4, "{name}: radius");
        assert!(
            radius <= number("trimesh_radius") + 1e-6,
            "{name}: larger than trimesh's"
        );
        let c: Vec<f64> = r["center"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let d = s.center.as_dvec3() - geode_geo::glam::DVec3::new(c[0], c[1], c[2]);
        assert!(d.length() < 1e-3, "{name}: centre off by {}", d.length());
    }
}

#[test]
fn a_box_mesh_is_closed_and_holds_its_volume() {
    let g = rotated(
        &primitives::box_mesh(Vec3::new(2.0, 1.0, 0.5), [2, 2, 2]),
        tilt(),
        Vec3::X,
    );
    let obb = oriented_box(g.positions(), &never)
        .unwrap()
        .unwrap()
        .padded(0.1);
    let mesh = box_geometry(&obb);
    let (euler, closed) = common::euler_and_closed(&mesh);
    assert!(closed && euler == 2);
    assert!(
        (volume(&mesh) - 2.2 * 1.2 * 0.7).abs() < 1e-4,
        "{}",
        volume(&mesh)
    );
}

fn bounds_of(g: &Geometry) -> Aabb {
    ops::bounds(g).unwrap()
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-5
}

#[test]
fn match_size_puts_bounds_where_asked() {
    // A 2 x 4 x 6 box centred at (1, 1, 1): bounds (0, -1, -2) to (2, 3, 4).
    let mut source = primitives::box_mesh(Vec3::new(2.0, 4.0, 6.0), [1, 1, 1]);
    ops::transform(&mut source, Mat4::from_translation(Vec3::ONE));
    let target = Aabb {
        min: Vec3::new(-1.0, 0.0, 0.0),
        max: Vec3::new(1.0, 1.0, 1.0),
    };
    let centre = [Justify::Center; 3];

    let mut g = source.clone();
    match_size(&mut g, &target, centre, ScaleMode::PerAxis).unwrap();
    let b = bounds_of(&g);
    assert!(
        close(b.min, target.min) && close(b.max, target.max),
        "{b:?}"
    );

    // Uniform: the factor that fits every side, 1/6 (the z side), each
    // axis to the target's min.
    let mut g = source.clone();
    match_size(&mut g, &target, [Justify::Min; 3], ScaleMode::Uniform).unwrap();
    let b = bounds_of(&g);
    assert!(close(b.min, target.min), "{b:?}");
    assert!(close(b.size(), Vec3::new(2.0, 4.0, 6.0) / 6.0), "{b:?}");

    // Translation only, per-axis justification: x to the max, y to the
    // centre, z left alone.
    let mut g = source.clone();
    match_size(
        &mut g,
        &target,
        [Justify::Max, Justify::Center, Justify::None],
        ScaleMode::None,
    )
    .unwrap();
    let b = bounds_of(&g);
    assert!(close(b.size(), Vec3::new(2.0, 4.0, 6.0)), "{b:?}");
    assert!((b.max.x - 1.0).abs() < 1e-6, "{b:?}");
    assert!((b.center().y - 0.5).abs() < 1e-6, "{b:?}");
    assert!(
        (b.min.z + 2.0).abs() < 1e-6 && (b.max.z - 4.0).abs() < 1e-6,
        "{b:?}"
    );

    // Normals follow a non-uniform scale (still unit, still normal).
    let mut g = primitives::uv_sphere(1.0, 16, 8);
    let n = area_weighted_normals(&g);
    g = with_point_normals(g, n);
    match_size(&mut g, &target, centre, ScaleMode::PerAxis).unwrap();
    let Some(AttribData::Vec3(n)) = g.attrib(AttribClass::Point, "N").map(|a| a.data()) else {
        panic!("N lost");
    };
    assert!(n.iter().all(|v| (v.length() - 1.0).abs() < 1e-4));
    let b = bounds_of(&g);
    assert!(
        close(b.min, target.min) && close(b.max, target.max),
        "{b:?}"
    );
}
