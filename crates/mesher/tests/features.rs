//! Sharp features at any orientation: boxes and wedges turned by seeded
//! random rotations, checked against the exact surface (every vertex on it)
//! and the exact corners (each reproduced by a vertex).

mod common;

use common::Rng;
use geode_frep::shapes::block;
use geode_frep::Field;
use geode_mesher::{polygonise, MeshOptions};

use common::mesh;
use common::{apply, box_surface_distance, transpose};

#[test]
fn rotated_boxes_keep_every_vertex_on_the_surface_and_every_corner() {
    let mut rng = Rng(0x6e0de);
    let depth = 6;
    let half_box = 1.0;
    let cell = 2.0 * half_box / (1u64 << depth) as f64;
    let mut worst_vertex = 0.0f64;
    let mut worst_corner = 0.0f64;
    for case in 0..12 {
        let r = rng.rotation();
        let h = [
            0.25 + 0.25 * rng.next(),
            0.25 + 0.25 * rng.next(),
            0.25 + 0.25 * rng.next(),
        ];
        let c = [
            0.05 * (rng.next() - 0.5),
            0.05 * (rng.next() - 0.5),
            0.05 * (rng.next() - 0.5),
        ];
        // A point p samples the box's frame at R^T (p - c).
        let rt = transpose(&r);
        let o = apply(&rt, c).map(|x| -x);
        let f = block([0.0; 3], h).affine_inverse(rt, o);
        let g = mesh(&f, half_box, depth);
        let report = g.topology().manifold_report(&g);
        assert!(report.is_closed_manifold(), "case {case}: {report:?}");
        let to_box = |p: [f64; 3]| apply(&rt, std::array::from_fn(|k| p[k] - c[k]));
        for p in g.positions() {
            let q = to_box([p.x as f64, p.y as f64, p.z as f64]);
            let d = box_surface_distance(q, h);
            if d / cell > 0.05 {
                eprintln!("case {case} vertex {q:?} of {h:?}: {} at {p:?}", d / cell);
            }
            worst_vertex = worst_vertex.max(d / cell);
        }
        for s in 0..8 {
            let local = [
                if s & 1 == 0 { -h[0] } else { h[0] },
                if s & 2 == 0 { -h[1] } else { h[1] },
                if s & 4 == 0 { -h[2] } else { h[2] },
            ];
            let turned = apply(&r, local);
            let corner: [f64; 3] = std::array::from_fn(|k| turned[k] + c[k]);
            let nearest = common::nearest_vertex(&g, corner);
            if nearest / cell > 0.02 {
                eprintln!("case {case} corner {corner:?} missed by {}", nearest / cell);
            }
            worst_corner = worst_corner.max(nearest / cell);
        }
    }
    common::assert_sharp(worst_vertex, worst_corner);
}

/// Solves the 3x3 system `rows x = rhs` (Cramer's rule); None when singular.
fn solve3(rows: [[f64; 3]; 3], rhs: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(rows);
    if d.abs() < 1e-9 {
        return None;
    }
    Some(std::array::from_fn(|k| {
        let mut m = rows;
        for (row, r) in m.iter_mut().zip(rhs) {
            row[k] = r;
        }
        det(m) / d
    }))
}

/// Boxes with four corners cut off (faces meeting at 125 degrees as well as
/// 90), turned by random rotations. Cuts are deep enough that corners stay
/// several cells apart: one vertex per cell cannot keep two corners that
/// share a cell, at any orientation.
#[test]
fn cut_boxes_keep_their_faces_and_corners() {
    let mut rng = Rng(0x9017);
    let depth = 6;
    let cell = 2.0 / (1u64 << depth) as f64;
    let (mut worst_vertex, mut worst_corner, mut corners_seen) = (0.0f64, 0.0f64, 0);
    for case in 0..8 {
        let r = rng.rotation();
        let s3 = 1.0 / 3f64.sqrt();
        let h = [
            0.4 + 0.1 * rng.next(),
            0.4 + 0.1 * rng.next(),
            0.4 + 0.1 * rng.next(),
        ];
        let mut planes: Vec<([f64; 3], f64)> = Vec::new();
        for (axis, sign) in (0..3).flat_map(|a| [(a, 1.0), (a, -1.0)]) {
            let mut n = [0.0; 3];
            n[axis] = sign;
            planes.push((apply(&r, n), h[axis]));
        }
        for corner in [
            [1.0, 1.0, 1.0],
            [-1.0, 1.0, -1.0],
            [1.0, -1.0, -1.0],
            [-1.0, -1.0, 1.0],
        ] {
            let n = corner.map(|c: f64| c * s3);
            let reach = (h[0] + h[1] + h[2]) * s3;
            planes.push((apply(&r, n), reach - 0.12 - 0.08 * rng.next()));
        }
        let (x, y, z) = (Field::x(), Field::y(), Field::z());
        let f = planes
            .iter()
            .map(|(n, d)| *d - (&x * n[0] + &y * n[1] + &z * n[2]))
            .reduce(|a, b| a.min(b))
            .unwrap()
            .min(geode_frep::shapes::sphere([0.0; 3], 0.95));
        let g = mesh(&f, 1.0, depth);
        let report = g.topology().manifold_report(&g);
        assert!(report.is_closed_manifold(), "case {case}: {report:?}");
        // The exact solid: inside every half-space (the bounding ball clips
        // only where the planes leave the polytope open).
        let inside_margin = |p: [f64; 3]| {
            planes
                .iter()
                .map(|(n, d)| d - (n[0] * p[0] + n[1] * p[1] + n[2] * p[2]))
                .fold(f64::INFINITY, f64::min)
                .min(0.95 - (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt())
        };
        for p in g.positions() {
            let d = inside_margin([p.x as f64, p.y as f64, p.z as f64]).abs();
            if d / cell > 0.01 {
                eprintln!("case {case} vertex {p:?} off by {}", d / cell);
            }
            worst_vertex = worst_vertex.max(d / cell);
        }
        for i in 0..planes.len() {
            for j in i + 1..planes.len() {
                for k in j + 1..planes.len() {
                    let rows = [planes[i].0, planes[j].0, planes[k].0];
                    let Some(c) = solve3(rows, [planes[i].1, planes[j].1, planes[k].1]) else {
                        continue;
                    };
                    // A corner of the polytope, away from the clipping ball.
                    if inside_margin(c) < -1e-9 || c.iter().map(|v| v * v).sum::<f64>() > 0.8 {
                        continue;
                    }
                    corners_seen += 1;
                    let nearest = common::nearest_vertex(&g, c);
                    if nearest / cell > 0.02 {
                        eprintln!("case {case} corner {c:?} missed by {}", nearest / cell);
                    }
                    worst_corner = worst_corner.max(nearest / cell);
                }
            }
        }
    }
    assert!(corners_seen >= 8 * 16, "{corners_seen} corners");
    common::assert_sharp(worst_vertex, worst_corner);
}

/// The seed's screw thread: a sawtooth helix of pitch 0.25 whose crest, at
/// radius 0.42, is where the turn's fraction is one half.
fn thread() -> Field {
    let (x, y, z) = (Field::x(), Field::y(), Field::z());
    let turns = z.atan2(x.clone()) / std::f64::consts::TAU + y.clone() / 0.25;
    let radius = (x.square() + z.square()).sqrt();
    let thread = 0.42 - radius - 0.3 * (turns.modulo(1.0) - 0.5).abs();
    thread.min(geode_frep::shapes::cylinder([0.0; 3], 1.0, 0.8))
}

/// Distance from `p` to the crest helix (r = 0.42, fraction of a turn 1/2),
/// measured across the unrolled cylinder.
fn crest_distance(p: [f64; 3]) -> f64 {
    let r = (p[0] * p[0] + p[2] * p[2]).sqrt();
    let turns = p[2].atan2(p[0]) / std::f64::consts::TAU + p[1] / 0.25;
    let off = turns - turns.floor() - 0.5;
    let slope = 0.25 / (std::f64::consts::TAU * 0.42);
    let across = 0.25 * off.abs() / (1.0 + slope * slope).sqrt();
    ((r - 0.42).powi(2) + across.powi(2)).sqrt()
}

#[test]
fn the_screw_crest_is_meshed_on_the_exact_crest() {
    let (lo, hi, depth) = ([-0.6, -0.9, -0.6], [0.6, 0.9, 0.6], 7);
    let opts = MeshOptions::new(lo, hi, depth);
    let g = polygonise(&thread(), &opts, &|| false, &|_| {}).unwrap().0;
    let report = g.topology().manifold_report(&g);
    assert!(report.is_closed_manifold(), "{report:?}");
    let h = 1.8 / (1u64 << depth) as f64;
    let origin = lo.map(|x| x - h);
    let cell_of = |p: [f64; 3]| -> [i64; 3] {
        std::array::from_fn(|a| ((p[a] - origin[a]) / h).floor() as i64)
    };
    let mut by_cell: std::collections::HashMap<[i64; 3], Vec<[f64; 3]>> = Default::default();
    for p in g.positions() {
        let p = [p.x as f64, p.y as f64, p.z as f64];
        by_cell.entry(cell_of(p)).or_default().push(p);
    }
    // Walk the crest helix away from the shaft's ends; each cell it passes
    // through holds a vertex on it.
    let (mut worst, mut cells, mut grazed) = (0.0f64, std::collections::BTreeSet::new(), 0);
    for step in 0..20_000 {
        let y = -0.6 + 1.2 * step as f64 / 20_000.0;
        // turns = theta / tau + y / 0.25 = k + 1/2 for the crest.
        let t = y / 0.25;
        let theta = (0.5 - (t - t.floor())) * std::f64::consts::TAU;
        let s = [0.42 * theta.cos(), y, 0.42 * theta.sin()];
        let c = cell_of(s);
        let distance_to_cell_face = (0..3)
            .map(|a| {
                let f = (s[a] - origin[a]) / h;
                (f - f.floor()).min(f.ceil() - f)
            })
            .fold(f64::INFINITY, f64::min);
        if distance_to_cell_face < 0.05 || !cells.insert(c) {
            continue;
        }
        let Some(vertices) = by_cell.get(&c) else {
            // The crest only grazes this cell: no grid corner of it is inside.
            grazed += 1;
            continue;
        };
        let best = vertices
            .iter()
            .map(|&p| crest_distance(p) / h)
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(best);
        if best > 0.01 {
            eprintln!(
                "crest cell {c:?} best {best:.3} at {s:?} verts {}",
                vertices.len()
            );
        }
    }
    eprintln!(
        "{} crest cells ({grazed} grazed), worst {worst:.4} cells",
        cells.len()
    );
    assert!(cells.len() > 200);
    assert!(
        worst <= 0.01,
        "a crest cell's vertex lies {worst} cells off the crest"
    );
}

/// The mesh's triangles, for closest points.
fn triangle_bvh(g: &geode_geo::Geometry) -> geode_geo::ops::TriangleBvh {
    let tris: Vec<[u32; 3]> = (0..g.num_prims())
        .map(|p| {
            let v = g.prim_points(p);
            [v[0], v[1], v[2]]
        })
        .collect();
    geode_geo::ops::TriangleBvh::new(g.positions(), &tris)
}

/// The screw's crest (r = 0.42, half a turn) and root (r = 0.27, whole
/// turns) helices sampled densely away from the shaft's ends: the fraction
/// of samples within `within` cells of the meshed surface (the triangles,
/// not only the vertices: a zig-zag across a crease leaves the crease
/// between its vertices).
fn helix_coverage(g: &geode_geo::Geometry, h: f64, within: f64) -> [f64; 2] {
    use geode_geo::glam::Vec3;
    let bvh = triangle_bvh(g);
    [(0.42, 0.5), (0.27, 0.0)].map(|(radius, fraction)| {
        let n = 20_000;
        let near = (0..n)
            .filter(|&step| {
                let y = -0.6 + 1.2 * step as f64 / n as f64;
                let t = y / 0.25;
                let theta = (fraction - (t - t.floor())) * std::f64::consts::TAU;
                let s = Vec3::new(
                    (radius * theta.cos()) as f32,
                    y as f32,
                    (radius * theta.sin()) as f32,
                );
                let d = bvh.closest(s, f32::INFINITY).unwrap().dist2.sqrt() as f64;
                d <= within * h
            })
            .count();
        near as f64 / n as f64
    })
}

#[test]
fn the_screw_crest_and_root_lie_on_the_mesh() {
    let (lo, hi, depth) = ([-0.6, -0.9, -0.6], [0.6, 0.9, 0.6], 7);
    let g = polygonise(
        &thread(),
        &MeshOptions::new(lo, hi, depth),
        &|| false,
        &|_| {},
    )
    .unwrap()
    .0;
    let h = 1.8 / (1u64 << depth) as f64;
    let mut at = Vec::new();
    for within in [0.05, 0.1, 0.25] {
        let [crest, root] = helix_coverage(&g, h, within);
        eprintln!("within {within} cell: crest {crest:.3}, root {root:.3}");
        at.push((crest, root));
    }
    // Depth 7: 100% of either helix within 0.05 cell. The crest pokes
    // into cells whose corners are all outside; the edges it crosses twice
    // (double.rs) give those cells vertices on it, and creases are
    // straightened (crease.rs). Before: 81% (63% without straightening).
    assert!(at[0].0 >= 0.99 && at[0].1 >= 0.99, "{at:?}");
    assert!(at[2].0 >= 0.995 && at[2].1 >= 0.995, "{at:?}");
}

/// Points of `curve` (a closed parametric curve, t in 0..1) within
/// `within` cells of the mesh's triangles, as a fraction, and the worst.
fn curve_coverage(
    g: &geode_geo::Geometry,
    h: f64,
    within: f64,
    curve: impl Fn(f64) -> [f64; 3],
) -> (f64, f64) {
    use geode_geo::glam::Vec3;
    let bvh = triangle_bvh(g);
    let n = 5000;
    let d: Vec<f64> = (0..n)
        .map(|i| {
            let p = curve(i as f64 / n as f64);
            let s = Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32);
            bvh.closest(s, f32::INFINITY).unwrap().dist2.sqrt() as f64 / h
        })
        .collect();
    let near = d.iter().filter(|&&x| x <= within).count();
    (
        near as f64 / n as f64,
        d.iter().copied().fold(0.0, f64::max),
    )
}

/// The circle where a sphere meets a cylinder it caps, and a cone's rim,
/// each turned by 12 seeded random rotations: sampled along the crease,
/// against the mesh, every sample within 0.05 cell (issue 37).
#[test]
fn curved_creases_of_capped_cylinders_and_cones_at_any_turn() {
    use geode_frep::shapes::{cone, cylinder, sphere};
    let mut rng = Rng(0xc0ffee);
    let depth = 7;
    let (lo, hi) = ([-1.0; 3], [1.0; 3]);
    let h = 2.0 / (1u64 << depth) as f64;
    // Cylinder r 0.5 along y (half height 0.6) under a sphere r 0.7 at
    // (0, 0.6, 0): they cross at y = 0.6 - sqrt(0.49 - 0.25). A cone with
    // its apex up, radius 0.5 and height 0.9: its rim at y = -0.45.
    let capped = cylinder([0.0; 3], 0.5, 0.6).max(sphere([0.0, 0.6, 0.0], 0.7));
    let crease_y = 0.6 - (0.49f64 - 0.25).sqrt();
    let rimmed = cone([0.0, 0.45, 0.0], 0.5, 0.9);
    let mut worst_seen = [0.0f64; 2];
    for case in 0..24 {
        let (shape, y, name) = if case % 2 == 0 {
            (&capped, crease_y, "capped cylinder")
        } else {
            (&rimmed, -0.45, "cone")
        };
        let r = rng.rotation();
        let f = shape.affine_inverse(transpose(&r), [0.0; 3]);
        let g = polygonise(&f, &MeshOptions::new(lo, hi, depth), &|| false, &|_| {})
            .unwrap()
            .0;
        let circle = |t: f64| {
            let a = t * std::f64::consts::TAU;
            apply(&r, [0.5 * a.cos(), y, 0.5 * a.sin()])
        };
        let (near, worst) = curve_coverage(&g, h, 0.05, circle);
        // Crease vertices that stand just beside their cell never share a
        // point with a neighbour's (a welding reader would fuse them).
        let mut seen = std::collections::HashSet::new();
        for p in g.positions() {
            assert!(
                seen.insert(p.to_array().map(f32::to_bits)),
                "{name} {case}: duplicate vertex {p}"
            );
        }
        // Before the crease's point beside a cell was taken where its line
        // passes the cell (not where it passes the planes' mass point) and
        // crease points just off a curved face were taken onto it, the
        // first cone here missed 0.8% of its rim by up to 0.53 cell (and 9
        // of 12 other turns tried missed 0.5-2% by up to 0.5 cell).
        assert!(
            near == 1.0 && worst < 0.05,
            "{name} {case}: {near} of the crease within 0.05 cell, worst {worst} cell"
        );
        let k = case % 2;
        worst_seen[k] = worst_seen[k].max(worst);
    }
    eprintln!(
        "worst crease sample: capped cylinders {:.3} cell, cones {:.3} cell",
        worst_seen[0], worst_seen[1]
    );
}
