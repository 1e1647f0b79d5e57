//! Reduction within a distance bound, against surfaces with exact distances:
//! a finely cut cube (flat faces must collapse to few triangles, corners and
//! edges kept), a cube-sphere (every sample within the bound), manifoldness,
//! thread independence and cancellation.

use std::collections::HashSet;

use geode_geo::glam::Vec3;
use geode_geo::ops::{self, compact_vertices, reduce_triangles, ReduceOptions};
use geode_geo::primitives;

/// The surface of [-1, 1]^3 cut into n x n squares a face, two triangles
/// each, outward, vertices shared.
fn cut_cube(n: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let g = ops::triangulate(&primitives::box_mesh(Vec3::splat(2.0), [n; 3]), None);
    let tris = (0..g.num_prims())
        .map(|p| {
            let pts = g.prim_points(p);
            [pts[0], pts[1], pts[2]]
        })
        .collect();
    (g.positions().to_vec(), tris)
}

fn box_distance(p: Vec3) -> f32 {
    let q = p.abs() - Vec3::ONE;
    q.max(Vec3::ZERO).length() + q.max_element().min(0.0)
}

/// Every directed edge's opposite appears exactly once: closed, manifold
/// edges, consistently wound.
fn assert_closed(tris: &[[u32; 3]]) {
    let mut edges = HashSet::new();
    for t in tris {
        for i in 0..3 {
            assert!(
                edges.insert((t[i], t[(i + 1) % 3])),
                "edge {:?} twice",
                (t[i], t[(i + 1) % 3])
            );
        }
    }
    for &(a, b) in &edges {
        assert!(edges.contains(&(b, a)), "edge ({a}, {b}) has no twin");
    }
}

fn reduce(
    positions: &[Vec3],
    tris: &[[u32; 3]],
    tolerance: f64,
    distance: fn(Vec3) -> f32,
) -> Vec<[u32; 3]> {
    let measure = |points: &[Vec3], out: &mut [f32]| {
        for (p, o) in points.iter().zip(out) {
            *o = distance(*p);
        }
    };
    let r = reduce_triangles(
        positions,
        tris,
        &ReduceOptions::new(tolerance),
        &measure,
        &|| false,
    )
    .expect("not cancelled");
    r.triangles
}

#[test]
fn a_cut_cube_collapses_to_its_faces_keeping_every_corner() {
    let (positions, tris) = cut_cube(24);
    let reduced = reduce(&positions, &tris, 1e-4, box_distance);
    assert_closed(&reduced);
    assert!(
        reduced.len() <= 16,
        "{} of {} triangles left",
        reduced.len(),
        tris.len()
    );
    let used: HashSet<u32> = reduced.iter().flatten().copied().collect();
    for corner in 0..8 {
        let c = Vec3::new(
            if corner & 1 == 0 { -1.0 } else { 1.0 },
            if corner & 2 == 0 { -1.0 } else { 1.0 },
            if corner & 4 == 0 { -1.0 } else { 1.0 },
        );
        assert!(
            used.iter().any(|&v| positions[v as usize] == c),
            "corner {c} collapsed away"
        );
    }
    // Area and volume unchanged: nothing moved off the faces.
    let volume: f32 = reduced
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            a.dot(b.cross(c)) / 6.0
        })
        .sum();
    assert!((volume - 8.0).abs() < 1e-3, "volume {volume}");
}

/// `f` run on a pool of `threads` threads.
fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

fn sphere_distance(p: Vec3) -> f32 {
    p.length() - 1.0
}

#[test]
fn a_sphere_reduces_within_the_bound_at_every_sample() {
    let (mut positions, tris) = cut_cube(40);
    for p in &mut positions {
        *p = p.normalize();
    }
    let before = tris.len();
    for tolerance in [0.002, 0.01] {
        let reduced = reduce(&positions, &tris, tolerance, sphere_distance);
        assert_closed(&reduced);
        assert!(
            reduced.len() < before / 3,
            "{tolerance}: {} of {before}",
            reduced.len()
        );
        // Independent samples: 10 barycentric points a triangle.
        let mut worst = 0.0f32;
        for t in &reduced {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            for (u, v) in [
                (0.33, 0.33),
                (0.5, 0.5),
                (0.5, 0.0),
                (0.0, 0.5),
                (0.25, 0.25),
                (0.6, 0.2),
            ] {
                worst = worst.max(sphere_distance(a + (b - a) * u + (c - a) * v).abs());
            }
        }
        // Midpoints and centroids are measured; other points of a triangle
        // of a convex surface lie no deeper than its centroid by more than
        // a small fraction.
        assert!(
            worst as f64 <= tolerance * 1.2,
            "{tolerance}: worst {worst}"
        );
        // Fewer triangles at the looser bound.
        if tolerance == 0.01 {
            assert!(reduced.len() < before / 12, "{}", reduced.len());
        }
    }
}

#[test]
fn the_result_does_not_depend_on_threads() {
    let (mut positions, tris) = cut_cube(30);
    for p in &mut positions {
        *p = p.normalize() * (1.0 + 0.1 * (3.0 * p.x).sin());
    }
    let runs: Vec<Vec<[u32; 3]>> = [1, 2, 4]
        .iter()
        .map(|&threads| {
            on_threads(threads, || {
                reduce(&positions, &tris, 0.01, |p| p.length() - 1.0)
            })
        })
        .collect();
    assert_eq!(runs[0], runs[1]);
    assert_eq!(runs[0], runs[2]);
}

#[test]
fn a_tetrahedron_stays_a_tetrahedron() {
    let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
    let tris = vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    let reduced = reduce(&positions, &tris, 10.0, |_| 0.0);
    assert_eq!(reduced.len(), 4);
    assert_closed(&reduced);
}

#[test]
fn a_zero_bound_changes_nothing_curved_and_compaction_renumbers() {
    let (mut positions, tris) = cut_cube(8);
    for p in &mut positions {
        *p = p.normalize();
    }
    let mut reduced = reduce(&positions, &tris, 0.0, sphere_distance);
    assert_eq!(reduced.len(), tris.len());
    let kept = compact_vertices(positions.len(), &mut reduced);
    assert_eq!(kept.len(), positions.len());
    assert_eq!(reduced, tris);
}

#[test]
fn cancelling_stops_the_reduction() {
    let (positions, tris) = cut_cube(20);
    let measure = |_: &[Vec3], out: &mut [f32]| out.fill(0.0);
    let r = reduce_triangles(
        &positions,
        &tris,
        &ReduceOptions::new(0.1),
        &measure,
        &|| true,
    );
    assert!(r.is_err());
}

/// A sphere triangulated irregularly (every third edge of a cut cube's
/// flipped, seeded), large enough to be reduced in parts: the parts' cut
/// runs between vertices of every valence, and the result stays closed and
/// manifold, far smaller, and the same on one thread as on two.
#[test]
fn an_irregular_mesh_reduced_in_parts_stays_closed() {
    let (mut positions, mut tris) = cut_cube(20);
    for p in &mut positions {
        *p = p.normalize();
    }
    flip_every_third_edge(&mut tris, 0x5eed);
    assert_closed(&tris);
    let runs: Vec<Vec<[u32; 3]>> = [1, 2]
        .iter()
        .map(|&threads| on_threads(threads, || reduce(&positions, &tris, 0.01, sphere_distance)))
        .collect();
    assert_closed(&runs[0]);
    assert!(runs[0].len() * 4 < tris.len(), "{}", runs[0].len());
    assert_eq!(runs[0], runs[1]);
}

/// Flips about every third interior edge (seeded), where the other
/// diagonal is not an edge already and no triangle takes two flips.
fn flip_every_third_edge(tris: &mut [[u32; 3]], mut seed: u64) {
    use std::collections::HashMap;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    let mut half: HashMap<(u32, u32), (usize, u32)> = HashMap::new();
    for (t, tri) in tris.iter().enumerate() {
        for i in 0..3 {
            half.insert((tri[i], tri[(i + 1) % 3]), (t, tri[(i + 2) % 3]));
        }
    }
    let mut edges: Vec<(u32, u32)> = half.keys().copied().filter(|(a, b)| a < b).collect();
    edges.sort_unstable();
    let mut used = vec![false; tris.len()];
    for (a, b) in edges {
        if next() % 3 != 0 {
            continue;
        }
        let (Some(&(t1, c)), Some(&(t2, d))) = (half.get(&(a, b)), half.get(&(b, a))) else {
            continue;
        };
        if used[t1] || used[t2] || c == d || half.contains_key(&(c, d)) {
            continue;
        }
        used[t1] = true;
        used[t2] = true;
        tris[t1] = [a, d, c];
        tris[t2] = [d, b, c];
        half.remove(&(a, b));
        half.remove(&(b, a));
        half.insert((c, d), (t2, b));
        half.insert((d, c), (t1, a));
    }
}
