//! Refinement toward a tolerance: where a triangle of the dual-contoured
//! mesh strays further than the tolerance from the surface (its centroid or
//! an edge's midpoint, measured with the field), the edge is split at its
//! midpoint moved onto the surface (by Newton steps along the gradient, or
//! to the nearest crossing along the ends' mean normal where that is
//! nearer), and the triangles around it are cut to match. Every triangle
//! cut by one, two or three of its edges is replaced by two, three or four,
//! so neighbours always agree and the mesh stays closed and manifold.

use geode_geo::glam::Vec3;
use rayon::prelude::*;

use crate::flip::flip_edges;
use crate::surface::{
    distance_estimate, field_distances, grads_at, ray_feet, walk_to_surface, Mesh, RegionTapes,
};
use geode_frep::eval::Grad;

/// Rounds of flipping or splitting: each split halves the edges it cuts, so
/// a deviation of a cell falls below 1/100 of a cell within six on a smooth
/// surface; flips (a round each) come first.
const ROUNDS: usize = 8;

/// What refinement did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Refinement {
    pub splits: usize,
    /// The largest deviation measured after the last round.
    pub deviation: f64,
}

/// How many times its triangles refinement may leave a mesh.
const GROWTH: usize = 4;

/// The mesh and the splits made before a round, to undo it.
type Snapshot = (Vec<Vec3>, Vec<Vec3>, Vec<[u32; 3]>, usize);

/// Splits edges until every centroid and edge midpoint is within
/// `tolerance` of the surface, the rounds run out, or a round stops helping
/// (the field's surface differs from any refinement of the mesh there: a
/// feature thinner than a cell, or a field whose first-order distance reads
/// high); a round that made the worst deviation larger is undone. `None`
/// when cancelled.
pub(crate) fn refine(
    tapes: &RegionTapes,
    (positions, normals, triangles): Mesh,
    tolerance: f64,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Option<Refinement> {
    // Vertices the QEF put further than the tolerance off the surface (a
    // clamped corner, a rounded tip) move onto it first (a no-op where
    // they already were).
    onto_surface(tapes, positions, normals, triangles, tolerance);
    let mut done = Refinement::default();
    let mut before: Option<Snapshot> = None;
    let start = triangles.len().max(1);
    let mut last = (f64::INFINITY, usize::MAX);
    let mut measured = Measured::default();
    for round in 0..=ROUNDS {
        if cancel() {
            return None;
        }
        let (split, worst) = edges_to_split(tapes, positions, triangles, tolerance, &mut measured);
        let helped = worst < last.0 || split.len() < last.1;
        if worst > last.0 {
            if let Some((p, n, t, splits)) = before.take() {
                (*positions, *normals, *triangles) = (p, n, t);
                done.splits = splits;
            }
            break;
        }
        done.deviation = worst;
        // Each split adds up to three triangles: refinement may at most
        // grow the mesh fourfold (a tolerance finer than the depth can
        // follow would otherwise split without end).
        let grows_too_much = triangles.len() + 3 * split.len() > GROWTH * start;
        if split.is_empty() || round == ROUNDS || !helped || grows_too_much {
            break;
        }
        last = (worst, split.len());
        before = Some((
            positions.clone(),
            normals.clone(),
            triangles.clone(),
            done.splits,
        ));
        if !flip_edges(tapes, positions, triangles, &split).is_empty() {
            // Measure again before splitting what flips left.
            continue;
        }
        let first = positions.len() as u32;
        let (points, point_normals) = on_surface(tapes, (positions, normals), &split, tolerance);
        positions.extend(points);
        normals.extend(point_normals);
        *triangles = cut(triangles, &split, first);
        done.splits += split.len();
    }
    Some(done)
}

/// Distances measured in earlier rounds, by edge and by triangle (sorted
/// keys): refinement never moves a vertex, only adds them, so an edge or a
/// triangle that is still there needs no second measure.
#[derive(Default)]
struct Measured {
    edges: Vec<([u32; 2], f32)>,
    triangles: Vec<([u32; 3], f32)>,
}

/// The field distance of each key's sample (`keys` sorted): from `known`
/// (sorted) where it was measured, else measured now.
fn distances<K: Ord + Copy + Sync>(
    tapes: &RegionTapes,
    keys: &[K],
    known: &[(K, f32)],
    sample: impl Fn(&K) -> Vec3 + Sync,
) -> Vec<f32> {
    let mut out = vec![0.0f32; keys.len()];
    let mut missing = Vec::new();
    let mut j = 0;
    for (i, k) in keys.iter().enumerate() {
        while j < known.len() && known[j].0 < *k {
            j += 1;
        }
        match known.get(j) {
            Some((key, d)) if key == k => out[i] = *d,
            _ => missing.push(i),
        }
    }
    let points: Vec<Vec3> = missing.par_iter().map(|&i| sample(&keys[i])).collect();
    let mut found = vec![0.0f32; points.len()];
    field_distances(tapes, &points, &mut found);
    for (i, d) in missing.into_iter().zip(found) {
        out[i] = d;
    }
    out
}

/// The edges (lower index first, sorted) whose midpoint strays beyond the
/// tolerance, and the longest edge of each triangle whose centroid does
/// while none of its edges does; with the largest deviation seen. Every
/// edge and triangle is measured (once: see `Measured`): the tolerance is a
/// guarantee, and no test on the ends' normals bounds how far the surface
/// bends between them (a gyroid shell's edge whose ends' tangent planes
/// hold its chord to 0.9 of the tolerance strayed 1.08 of it).
fn edges_to_split(
    tapes: &RegionTapes,
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    tolerance: f64,
    measured: &mut Measured,
) -> (Vec<[u32; 2]>, f64) {
    let p = |v: u32| positions[v as usize];
    // Each edge once: from the triangle where it runs upwards.
    let mut edges: Vec<[u32; 2]> = triangles
        .par_iter()
        .flat_map_iter(|t| (0..3).map(move |i| [t[i], t[(i + 1) % 3]]))
        .filter(|e| e[0] < e[1])
        .collect();
    edges.par_sort_unstable();
    // Triangles by their corners in ascending order (a centroid does not
    // depend on their order).
    let mut sorted: Vec<[u32; 3]> = triangles
        .par_iter()
        .map(|t| {
            let mut t = *t;
            t.sort_unstable();
            t
        })
        .collect();
    sorted.par_sort_unstable();
    let at_edges = distances(tapes, &edges, &measured.edges, |e| {
        0.5 * (p(e[0]) + p(e[1]))
    });
    let at_centroids = distances(tapes, &sorted, &measured.triangles, |t| {
        (p(t[0]) + p(t[1]) + p(t[2])) / 3.0
    });
    measured.edges = edges
        .iter()
        .copied()
        .zip(at_edges.iter().copied())
        .collect();
    measured.triangles = sorted
        .iter()
        .copied()
        .zip(at_centroids.iter().copied())
        .collect();
    let worst = at_edges
        .iter()
        .chain(&at_centroids)
        .fold(0.0, |w, &d| f64::max(w, d.into()));
    let mut split: Vec<[u32; 2]> = edges
        .iter()
        .zip(&at_edges)
        .filter(|(_, d)| f64::from(**d) > tolerance)
        .map(|(e, _)| *e)
        .collect();
    let mut longest: Vec<[u32; 2]> = sorted
        .iter()
        .zip(&at_centroids)
        .filter(|(_, d)| f64::from(**d) > tolerance)
        .filter_map(|(t, _)| {
            let sides = [0, 1, 2].map(|i| {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                [a.min(b), a.max(b)]
            });
            if sides.iter().any(|e| split.binary_search(e).is_ok()) {
                return None;
            }
            sides.into_iter().max_by(|x, y| {
                let len = |e: &[u32; 2]| (p(e[0]) - p(e[1])).length_squared();
                len(x).total_cmp(&len(y)).then(y.cmp(x))
            })
        })
        .collect();
    split.append(&mut longest);
    split.sort_unstable();
    split.dedup();
    (split, worst)
}

/// Moves each vertex further than `tolerance` from the surface onto it
/// (within half its shortest edge).
pub(crate) fn onto_surface(
    tapes: &RegionTapes,
    positions: &mut [Vec3],
    normals: &mut [Vec3],
    triangles: &[[u32; 3]],
    tolerance: f64,
) {
    let at_vertices = grads_at(tapes, positions);
    let far: Vec<u32> = at_vertices
        .iter()
        .enumerate()
        .filter(|(_, g)| distance_estimate(g).abs() as f64 > tolerance)
        .map(|(v, _)| v as u32)
        .collect();
    if far.is_empty() {
        return;
    }
    let mut reach = vec![f32::MAX; far.len()];
    for t in triangles {
        for i in 0..3 {
            if let Ok(k) = far.binary_search(&t[i]) {
                let (a, b) = (t[i] as usize, t[(i + 1) % 3] as usize);
                let (c, d) = (t[(i + 2) % 3] as usize, t[i] as usize);
                let shortest = (positions[a] - positions[b])
                    .length()
                    .min((positions[c] - positions[d]).length());
                reach[k] = reach[k].min(0.5 * shortest);
            }
        }
    }
    let starts: Vec<Vec3> = far.iter().map(|&v| positions[v as usize]).collect();
    let at_starts: Vec<Grad> = far.iter().map(|&v| at_vertices[v as usize]).collect();
    let (points, at_points) = project(tapes, (&starts, &at_starts), &reach);
    for (k, &v) in far.iter().enumerate() {
        positions[v as usize] = points[k];
        normals[v as usize] = outward(&at_points[k]).unwrap_or(Vec3::Y);
    }
}

/// Where each split edge's new vertex goes: its midpoint moved onto the
/// surface (within the edge's length: across a right-angled crease the
/// surface lies half of it away) by the walk along the gradient or along
/// the ends' mean normal, whichever lands nearer, or, where the ends'
/// tangent planes meet in a line (the edge crosses a crease), the point of
/// that line nearest the midpoint when it lies on the surface. With
/// normals.
fn on_surface(
    tapes: &RegionTapes,
    (positions, normals): (&[Vec3], &[Vec3]),
    split: &[[u32; 2]],
    tolerance: f64,
) -> (Vec<Vec3>, Vec<Vec3>) {
    let p = |v: u32| positions[v as usize];
    let mids: Vec<Vec3> = split.iter().map(|e| 0.5 * (p(e[0]) + p(e[1]))).collect();
    let reach: Vec<f32> = split.iter().map(|e| (p(e[0]) - p(e[1])).length()).collect();
    let at_mids = grads_at(tapes, &mids);
    let (mut points, mut at_points) = project(tapes, (&mids, &at_mids), &reach);
    // The walk follows the gradient, which can lead to a farther surface
    // than the one across the edge: the nearest crossing along the ends'
    // mean normal wins when it is nearer.
    let across: Vec<Vec3> = split
        .iter()
        .map(|e| (normals[e[0] as usize] + normals[e[1] as usize]).normalize_or(Vec3::Z))
        .collect();
    let rays = ray_feet(tapes, (&mids, &at_mids), &across, &reach);
    for (i, ray) in rays.into_iter().enumerate() {
        let Some((foot, at_foot)) = ray else { continue };
        let walked = (distance_estimate(&at_points[i]).abs() as f64) <= 1e-3 * tolerance;
        if !walked || foot.distance(mids[i]) < points[i].distance(mids[i]) {
            (points[i], at_points[i]) = (foot, at_foot);
        }
    }
    let creases: Vec<Vec3> = split
        .iter()
        .zip(&mids)
        .map(|(e, m)| {
            crease_point(
                *m,
                [p(e[0]), p(e[1])],
                [normals[e[0] as usize], normals[e[1] as usize]],
            )
        })
        .collect();
    let at_creases = grads_at(tapes, &creases);
    for i in 0..split.len() {
        let near = creases[i].distance(mids[i]) <= reach[i];
        let on_crease = distance_estimate(&at_creases[i]).abs();
        // On the surface (to a thousandth of the tolerance), the crease
        // point wins: it keeps the crease the edge cuts.
        let on_surface = (on_crease as f64) <= 1e-3 * tolerance;
        if near && (on_surface || on_crease < distance_estimate(&at_points[i]).abs()) {
            points[i] = creases[i];
            at_points[i] = at_creases[i];
        }
    }
    let point_normals = at_points
        .iter()
        .map(|g| outward(g).unwrap_or(Vec3::Y))
        .collect();
    (points, point_normals)
}

/// The point nearest `m` on both planes through `ends` with `normals`
/// (`m` itself when the planes are near parallel).
fn crease_point(m: Vec3, ends: [Vec3; 2], normals: [Vec3; 2]) -> Vec3 {
    let [a, b] = ends.map(|x| x.as_dvec3());
    let [na, nb] = normals.map(|x| x.as_dvec3());
    let m64 = m.as_dvec3();
    // x = m + s na + t nb with na.(x - a) = 0 and nb.(x - b) = 0.
    let (aa, ab, bb) = (na.dot(na), na.dot(nb), nb.dot(nb));
    let det = aa * bb - ab * ab;
    if det < 1e-4 * aa * bb {
        return m;
    }
    let (ra, rb) = (na.dot(a - m64), nb.dot(b - m64));
    let s = (ra * bb - rb * ab) / det;
    let t = (rb * aa - ra * ab) / det;
    (m64 + na * s + nb * t).as_vec3()
}

/// Points moved to where their walk meets the surface, when that is within
/// `reach` of them (else they stay), with the value and gradient there.
fn project(
    tapes: &RegionTapes,
    (starts, at_starts): (&[Vec3], &[Grad]),
    reach: &[f32],
) -> (Vec<Vec3>, Vec<Grad>) {
    let (feet, at_feet) = walk_to_surface(tapes, starts, at_starts);
    (0..starts.len())
        .map(|i| {
            if starts[i].distance(feet[i]) <= reach[i] {
                (feet[i], at_feet[i])
            } else {
                (starts[i], at_starts[i])
            }
        })
        .unzip()
}

/// The outward unit normal a gradient gives (`f >= 0` inside), if any.
fn outward(g: &Grad) -> Option<Vec3> {
    let n = -geode_geo::glam::DVec3::from_array(g.d)
        .normalize_or_zero()
        .as_vec3();
    (n != Vec3::ZERO).then_some(n)
}

/// The triangles with the split edges cut: new vertex `first + i` on
/// `split[i]`. Orientation is kept.
fn cut(triangles: &[[u32; 3]], split: &[[u32; 2]], first: u32) -> Vec<[u32; 3]> {
    let mid = |a: u32, b: u32| {
        split
            .binary_search(&[a.min(b), a.max(b)])
            .ok()
            .map(|i| first + i as u32)
    };
    let mut out = Vec::with_capacity(triangles.len() + 3 * split.len());
    for &t in triangles {
        let m = [0, 1, 2].map(|i| mid(t[i], t[(i + 1) % 3]));
        match m.iter().filter(|x| x.is_some()).count() {
            0 => out.push(t),
            1 => {
                // Rotate so the cut edge runs from corner 0 to corner 1.
                let i = m.iter().position(|x| x.is_some()).unwrap_or(0);
                let (a, b, c) = (t[i], t[(i + 1) % 3], t[(i + 2) % 3]);
                let ab = m[i].unwrap_or(a);
                out.push([a, ab, c]);
                out.push([ab, b, c]);
            }
            2 => {
                // Rotate so the uncut edge runs from corner 2 to corner 0.
                let i = m.iter().position(|x| x.is_none()).unwrap_or(0);
                let (c, a, b) = (t[i], t[(i + 1) % 3], t[(i + 2) % 3]);
                // Cut: a-b at ab, b-c at bc.
                let ab = m[(i + 1) % 3].unwrap_or(a);
                let bc = m[(i + 2) % 3].unwrap_or(b);
                out.push([ab, b, bc]);
                // The quad c, a, ab, bc, fanned from c.
                out.push([c, a, ab]);
                out.push([c, ab, bc]);
            }
            _ => {
                let [ab, bc, ca] = m.map(|x| x.unwrap_or(0));
                let [a, b, c] = t;
                out.push([a, ab, ca]);
                out.push([ab, b, bc]);
                out.push([ca, bc, c]);
                out.push([ab, bc, ca]);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    /// An octahedron: closed, 6 vertices, 12 edges.
    fn octahedron() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let p = vec![Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
        let t = vec![
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ];
        (p, t)
    }

    fn area(p: &[Vec3], t: &[[u32; 3]]) -> f32 {
        t.iter()
            .map(|t| {
                0.5 * (p[t[1] as usize] - p[t[0] as usize])
                    .cross(p[t[2] as usize] - p[t[0] as usize])
                    .length()
            })
            .sum()
    }

    #[test]
    fn cutting_any_set_of_edges_keeps_the_mesh_closed_and_its_area() {
        let (p, t) = octahedron();
        let mut all: Vec<[u32; 2]> = t
            .iter()
            .flat_map(|t| (0..3).map(move |i| [t[i], t[(i + 1) % 3]]))
            .filter(|e| e[0] < e[1])
            .collect();
        all.sort_unstable();
        assert_eq!(all.len(), 12);
        for mask in [1u32, 3, 5, 0b111, 0b1010_1010_1010, 0xfff, 0b1001_0110_0011] {
            let split: Vec<[u32; 2]> = (0..12)
                .filter(|i| mask >> i & 1 == 1)
                .map(|i| all[i])
                .collect();
            let mut q = p.clone();
            q.extend(
                split
                    .iter()
                    .map(|e| 0.5 * (p[e[0] as usize] + p[e[1] as usize])),
            );
            let cut = cut(&t, &split, p.len() as u32);
            let mut edges = HashSet::new();
            for tri in &cut {
                for i in 0..3 {
                    assert!(
                        edges.insert((tri[i], tri[(i + 1) % 3])),
                        "mask {mask:b}: edge twice"
                    );
                }
            }
            for &(a, b) in &edges {
                assert!(edges.contains(&(b, a)), "mask {mask:b}: ({a}, {b}) open");
            }
            assert!(
                (area(&q, &cut) - area(&p, &t)).abs() < 1e-5,
                "mask {mask:b}"
            );
        }
    }
}
