//! Flattening: a cut cylinder unrolls without angle distortion, packed
//! islands stay apart inside the unit square at one scale, the result
//! does not depend on the thread count, cancellation stops it, and
//! degenerate input passes without a panic.

mod common;

use std::sync::atomic::{AtomicUsize, Ordering};

use common::meshes::{cylinder, hemisphere};
use geode_geo::glam::{Vec2, Vec3};
use geode_geo::{ops, primitives, Geometry, PrimKind};
use geode_uv::{
    flatten, ConformalMethod, FlattenOptions, Flattened, LinearSolver, PackOptions, SolverOptions,
    UvError,
};

fn never() -> bool {
    false
}

fn uv2(f: &Flattened, v: usize) -> Vec2 {
    Vec2::new(f.uv[v].x, f.uv[v].y)
}

/// Every polygon fanned into triangles of vertex numbers (as the kernel
/// triangulates convex polygons).
fn fan_triangles(g: &Geometry) -> Vec<[usize; 3]> {
    let mut out = Vec::new();
    for prim in 0..g.num_prims() {
        if g.prim_kind(prim) != PrimKind::Polygon {
            continue;
        }
        let r = g.prim_vertex_range(prim);
        for k in 1..r.len() - 1 {
            out.push([r.start, r.start + k, r.start + k + 1]);
        }
    }
    out
}

fn angle(a: Vec3, b: Vec3) -> f32 {
    a.angle_between(b)
}

/// The largest difference between a corner's angle in 3D and in uv, over
/// every triangle corner.
fn max_angle_distortion(g: &Geometry, f: &Flattened) -> f32 {
    let p = g.positions();
    let vp = g.vertex_points();
    let mut worst = 0.0f32;
    for t in fan_triangles(g) {
        for k in 0..3 {
            let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            let pos = |v: usize| p[vp[v] as usize];
            let three_d = angle(pos(b) - pos(a), pos(c) - pos(a));
            let flat = |v: usize| uv2(f, v).extend(0.0);
            let in_uv = angle(flat(b) - flat(a), flat(c) - flat(a));
            worst = worst.max((three_d - in_uv).abs());
        }
    }
    worst
}

/// Per island: (uv bounding box min, max, uv area, 3D area).
fn island_measures(g: &Geometry, f: &Flattened) -> Vec<(Vec2, Vec2, f64, f64)> {
    let mut out = vec![(Vec2::MAX, Vec2::MIN, 0.0, 0.0); f.island_count];
    let p = g.positions();
    let vp = g.vertex_points();
    for prim in 0..g.num_prims() {
        let island = f.prim_island[prim];
        if island < 0 {
            continue;
        }
        let m = &mut out[island as usize];
        for v in g.prim_vertex_range(prim) {
            m.0 = m.0.min(uv2(f, v));
            m.1 = m.1.max(uv2(f, v));
        }
    }
    for t in fan_triangles(g) {
        let island = f.prim_island[g.topology().prim_of_vertex(t[0]) as usize] as usize;
        let (a, b, c) = (uv2(f, t[0]), uv2(f, t[1]), uv2(f, t[2]));
        out[island].2 += 0.5 * (b - a).perp_dot(c - a).abs() as f64;
        let pos = |v: usize| p[vp[v] as usize].as_dvec3();
        out[island].3 += 0.5
            * (pos(t[1]) - pos(t[0]))
                .cross(pos(t[2]) - pos(t[0]))
                .length();
    }
    out
}

#[test]
fn a_cut_cylinder_unrolls_into_one_rectangle_without_distortion() {
    let (g, seams) = cylinder(64, 16, 2.0);
    let f = flatten(&g, &seams, &FlattenOptions::default(), &never).unwrap();
    assert_eq!(f.island_count, 1);
    assert!(f.prim_island.iter().all(|&i| i == 0));
    let distortion = max_angle_distortion(&g, &f);
    println!("cut cylinder: max angle distortion {distortion:.3e} rad");
    assert!(distortion < 1e-3, "angle distortion {distortion} rad");
    // One rectangle: its uv area fills its bounding box, as wide as the
    // 64-gon's perimeter and as tall as the cylinder (2).
    let (lo, hi, area, _) = island_measures(&g, &f)[0];
    let size = hi - lo;
    assert!(
        area / (size.x as f64 * size.y as f64) > 0.999,
        "{area} in {size}"
    );
    let aspect = size.max_element() / size.min_element();
    let perimeter = 64.0 * 2.0 * (std::f32::consts::PI / 64.0).sin();
    assert!((aspect - perimeter / 2.0).abs() < 1e-4, "aspect {aspect}");
    // The seam points have one uv per side: the two sides are a whole
    // rectangle's length apart.
    let seam_point_uvs: Vec<Vec2> = (0..g.num_vertices())
        .filter(|&v| g.vertex_points()[v] == 0)
        .map(|v| uv2(&f, v))
        .collect();
    let spread = seam_point_uvs
        .iter()
        .map(|a| {
            seam_point_uvs
                .iter()
                .map(|b| a.distance(*b))
                .fold(0.0, f32::max)
        })
        .fold(0.0, f32::max);
    assert!(
        (spread - size.max_element()).abs() < 1e-4,
        "{seam_point_uvs:?}"
    );
    assert!(f.uv.iter().all(|t| t.z == 0.0));
    assert!(f.unconverged_islands == 0);
}

/// A mesh of separate islands of known sizes: unit, 2 x 1 and 0.5 x 0.5
/// grids, a hemisphere (cut by nothing: one disk) and a cube cut along
/// all its edges (six squares).
fn many_islands() -> (Geometry, Vec<[u32; 2]>) {
    let grids = [
        primitives::grid(Vec2::new(1.0, 1.0), 4, 4),
        primitives::grid(Vec2::new(2.0, 1.0), 8, 4),
        primitives::grid(Vec2::new(0.5, 0.5), 2, 2),
    ];
    let sphere = hemisphere(8);
    let mut cube = primitives::cube(1.0);
    ops::transform(
        &mut cube,
        geode_geo::glam::Mat4::from_translation(Vec3::new(5.0, 0.0, 0.0)),
    );
    let parts: Vec<&Geometry> = grids.iter().chain([&sphere, &cube]).collect();
    let g = ops::merge(&parts).unwrap();
    let offset = g.num_points() as u32 - cube.num_points() as u32;
    let seams = cube
        .topology()
        .edges()
        .iter()
        .map(|e| [e[0] + offset, e[1] + offset])
        .collect();
    (g, seams)
}

#[test]
fn packed_islands_stay_apart_inside_the_square_at_one_scale() {
    let (g, seams) = many_islands();
    let margin = 0.02;
    let options = FlattenOptions {
        pack: PackOptions {
            margin,
            rotate: true,
        },
        ..FlattenOptions::default()
    };
    let f = flatten(&g, &seams, &options, &never).unwrap();
    assert_eq!(f.island_count, 3 + 1 + 6);
    assert_eq!(f.margin, margin);
    let m = island_measures(&g, &f);
    for (i, a) in m.iter().enumerate() {
        assert!(
            a.0.min_element() >= margin as f32 - 1e-5,
            "island {i} at {:?}",
            a.0
        );
        assert!(
            a.1.max_element() <= 1.0 - margin as f32 + 1e-5,
            "island {i} to {:?}",
            a.1
        );
        for (j, b) in m.iter().enumerate().skip(i + 1) {
            let gap = (b.0 - a.1).max(a.0 - b.1).max_element();
            assert!(
                gap >= margin as f32 - 1e-5,
                "islands {i} and {j} {gap} apart"
            );
        }
    }
    // One scale: uv area over 3D area is the same for every island.
    let ratio = m[0].2 / m[0].3;
    for (i, a) in m.iter().enumerate() {
        assert!(
            (a.2 / a.3 / ratio - 1.0).abs() < 1e-3,
            "island {i}: {} vs {ratio}",
            a.2 / a.3
        );
    }
    assert!((ratio.sqrt() - f.scale).abs() / f.scale < 1e-3);
    // The layout is not wasteful: the islands cover a fair part of it.
    let covered: f64 = m.iter().map(|a| a.2).sum();
    println!(
        "10 islands packed: scale {:.4}, {covered:.3} of the square covered",
        f.scale
    );
    assert!(covered > 0.3, "islands cover {covered} of the square");
}

fn flatten_on(
    threads: usize,
    g: &Geometry,
    seams: &[[u32; 2]],
    (method, conformal): (LinearSolver, ConformalMethod),
) -> Flattened {
    let options = FlattenOptions {
        solver: SolverOptions {
            method,
            ..SolverOptions::default()
        },
        method: conformal,
        ..FlattenOptions::default()
    };
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| flatten(g, seams, &options, &never).unwrap())
}

/// Large enough for several parallel chunks in every reduction.
fn determinism_mesh() -> (Geometry, Vec<[u32; 2]>) {
    let (cyl, cyl_seams) = cylinder(96, 60, 3.0);
    let sphere = hemisphere(40);
    let g = ops::merge(&[&cyl, &sphere]).unwrap();
    (g, cyl_seams)
}

#[test]
fn the_same_bits_on_one_and_on_four_threads() {
    let (g, seams) = determinism_mesh();
    for method in [
        (LinearSolver::Cholesky, ConformalMethod::TwoPins),
        (LinearSolver::ConjugateGradient, ConformalMethod::TwoPins),
        (LinearSolver::Cholesky, ConformalMethod::Spectral),
    ] {
        let one = flatten_on(1, &g, &seams, method);
        let four = flatten_on(4, &g, &seams, method);
        let bits = |f: &Flattened| {
            f.uv.iter()
                .flat_map(|t| t.to_array().map(f32::to_bits))
                .collect::<Vec<_>>()
        };
        assert!(
            bits(&one) == bits(&four),
            "{method:?}: uv differ between thread counts"
        );
        assert_eq!(one.prim_island, four.prim_island);
        assert_eq!(one.iterations, four.iterations);
        assert_eq!(one.island_count, 2);
    }
}

#[test]
fn cancellation_stops_every_phase() {
    let (g, seams) = determinism_mesh();
    let always = || true;
    assert_eq!(
        flatten(&g, &seams, &FlattenOptions::default(), &always),
        Err(UvError::Cancelled)
    );
    // Cancelled after some polls: inside the islands' solves.
    for method in [
        (LinearSolver::Cholesky, ConformalMethod::TwoPins),
        (LinearSolver::ConjugateGradient, ConformalMethod::TwoPins),
        (LinearSolver::Cholesky, ConformalMethod::Spectral),
    ] {
        for after in [2, 4, 8] {
            let polls = AtomicUsize::new(0);
            let later = || polls.fetch_add(1, Ordering::Relaxed) >= after;
            let options = FlattenOptions {
                solver: SolverOptions {
                    method: method.0,
                    ..SolverOptions::default()
                },
                method: method.1,
                ..FlattenOptions::default()
            };
            assert_eq!(
                flatten(&g, &seams, &options, &later),
                Err(UvError::Cancelled)
            );
        }
    }
}

#[test]
fn degenerate_input_passes_without_panic() {
    let check = |g: &Geometry, seams: &[[u32; 2]]| {
        let f = flatten(g, seams, &FlattenOptions::default(), &never).unwrap();
        assert_eq!(f.uv.len(), g.num_vertices());
        assert_eq!(f.prim_island.len(), g.num_prims());
        for (v, t) in f.uv.iter().enumerate() {
            assert!(t.is_finite(), "vertex {v}: {t}");
            assert!(
                (0.0..=1.0).contains(&t.x) && (0.0..=1.0).contains(&t.y),
                "vertex {v}: {t}"
            );
        }
        f
    };
    // Empty, and points without primitives.
    let empty = check(&Geometry::new(), &[]);
    assert_eq!(empty.island_count, 0);
    let mut lonely = Geometry::new();
    lonely.add_points(&[Vec3::ZERO, Vec3::ONE]);
    check(&lonely, &[[0, 1], [7, 9]]);
    // One triangle; a zero-area triangle; all its points at one place.
    let one = Geometry::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]]).unwrap();
    assert_eq!(check(&one, &[]).island_count, 1);
    let flat =
        Geometry::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0], &[[0, 1, 2]]).unwrap();
    check(&flat, &[]);
    let point = Geometry::from_triangles(vec![Vec3::ONE; 3], &[[0, 1, 2]]).unwrap();
    check(&point, &[]);
    // A quad with a zero-area sliver hanging off an edge, a repeated point,
    // a fin of three triangles on one edge, a polyline and a lone point.
    let positions = vec![
        Vec3::ZERO,
        Vec3::X,
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::Y,
        Vec3::new(0.5, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(0.0, -1.0, 0.0),
        Vec3::splat(9.0),
    ];
    let g = Geometry::from_prims(
        positions,
        vec![0, 1, 2, 3, 0, 4, 1, 0, 1, 1, 3, 1, 0, 5, 1, 0, 6, 5, 6],
        &[4, 3, 3, 3, 3, 3],
        vec![
            PrimKind::Polygon,
            PrimKind::Polygon,
            PrimKind::Polygon,
            PrimKind::Polygon,
            PrimKind::Polygon,
            PrimKind::Polyline,
        ],
    )
    .unwrap();
    let f = check(&g, &[[0, 1], [1, 0]]);
    assert_eq!(f.prim_island[5], -1);
    // Seams on every edge of a mesh: each polygon its own island.
    let grid = primitives::grid(Vec2::ONE, 3, 3);
    let all = grid.topology().edges().to_vec();
    assert_eq!(check(&grid, &all).island_count, 9);
    // A closed sphere without seams is flattened (badly) without failing.
    check(
        &ops::triangulate(&primitives::uv_sphere(1.0, 12, 6), None),
        &[],
    );
    // A point that is not a number spoils only its own triangle.
    let nan = Geometry::from_triangles(
        vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::splat(f32::NAN)],
        &[[0, 1, 2], [1, 3, 2]],
    )
    .unwrap();
    check(&nan, &[]);
    // A margin outside [0, 0.5) is refused.
    let wide = FlattenOptions {
        pack: PackOptions {
            margin: 0.5,
            rotate: true,
        },
        ..FlattenOptions::default()
    };
    assert!(matches!(
        flatten(&one, &[], &wide, &never),
        Err(UvError::Invalid(_))
    ));
}

/// Per triangle (fanned): uv area over 3D area.
fn area_ratios(g: &Geometry, f: &Flattened) -> Vec<f64> {
    let p = g.positions();
    let vp = g.vertex_points();
    fan_triangles(g)
        .into_iter()
        .map(|t| {
            let (a, b, c) = (uv2(f, t[0]), uv2(f, t[1]), uv2(f, t[2]));
            let flat = 0.5 * (b - a).perp_dot(c - a) as f64;
            let pos = |v: usize| p[vp[v] as usize].as_dvec3();
            let solid = 0.5
                * (pos(t[1]) - pos(t[0]))
                    .cross(pos(t[2]) - pos(t[0]))
                    .length();
            flat / solid
        })
        .collect()
}

/// A torus of revolution cut along a meridian and a parallel is
/// conformally a rectangle: in coordinates `(u, integral of r / (R + r cos
/// v) dv)` the conformal factor is `R + r cos v`, so the uv-to-3D area
/// ratio runs from `1 / (R + r)^2` to `1 / (R - r)^2` (relative spread
/// `((R + r) / (R - r))^2`, 2.78 here), every triangle kept the right way
/// round. The spectral map comes near it; two pins let the strip curl.
#[test]
fn a_cut_torus_opens_spectrally_into_a_band_of_even_density() {
    let (cols, rows) = (48u32, 16u32);
    let g = primitives::torus(1.0, 0.25, cols, rows);
    // Point (i, j) is i * rows + j: the meridian i = 0 and the parallel j = 0.
    let mut seams: Vec<[u32; 2]> = (0..rows).map(|j| [j, (j + 1) % rows]).collect();
    seams.extend((0..cols).map(|i| [i * rows, ((i + 1) % cols) * rows]));
    let options = FlattenOptions {
        method: ConformalMethod::Spectral,
        ..FlattenOptions::default()
    };
    let f = flatten(&g, &seams, &options, &never).unwrap();
    assert_eq!(f.island_count, 1);
    let ratios = area_ratios(&g, &f);
    assert!(ratios.iter().all(|&r| r > 0.0), "a triangle flipped");
    let (lo, hi) = ratios
        .iter()
        .fold((f64::MAX, 0.0f64), |(lo, hi), &r| (lo.min(r), hi.max(r)));
    let expected = (1.25f64 / 0.75).powi(2);
    println!("cut torus, spectral: area ratio spread {:.3} (continuous {expected:.3}), angle distortion {:.3e}", hi / lo, max_angle_distortion(&g, &f));
    let spectral_spread = hi / lo;
    // The island's bounding box is filled: a rectangle, not a spiral.
    let (lo_uv, hi_uv, area, _) = island_measures(&g, &f)[0];
    let size = hi_uv - lo_uv;
    assert!(
        area / (size.x as f64 * size.y as f64) > 0.8,
        "{area} in {size}"
    );
    // Two pins on the same cut: the strip curls, its density varying far
    // more (what the spectral map is for).
    let pinned = flatten(&g, &seams, &FlattenOptions::default(), &never).unwrap();
    let ratios = area_ratios(&g, &pinned);
    let (lo, hi) = ratios.iter().fold((f64::MAX, 0.0f64), |(lo, hi), &r| {
        (lo.min(r.abs()), hi.max(r.abs()))
    });
    println!("cut torus, two pins: area ratio spread {:.3}", hi / lo);
    // Not the rectangle's own map (any conformal map of the strip is free
    // of energy; the spectral one bulges like a barrel, 5.2 here and 5.7
    // at four times the triangles), but within a small factor of it.
    assert!(spectral_spread < 2.5 * expected, "spread {spectral_spread}");
}

#[test]
fn the_spectral_map_of_a_cut_cylinder_is_as_exact_and_a_closed_island_falls_back() {
    let (g, seams) = cylinder(64, 16, 2.0);
    let options = FlattenOptions {
        method: ConformalMethod::Spectral,
        ..FlattenOptions::default()
    };
    let f = flatten(&g, &seams, &options, &never).unwrap();
    let distortion = max_angle_distortion(&g, &f);
    assert!(distortion < 1e-3, "angle distortion {distortion} rad");
    // A sphere without seams has no boundary: two pins, as before.
    let s = primitives::uv_sphere(1.0, 12, 8);
    let f = flatten(&s, &[], &options, &never).unwrap();
    let plain = flatten(&s, &[], &FlattenOptions::default(), &never).unwrap();
    assert_eq!(f.uv, plain.uv);
}
