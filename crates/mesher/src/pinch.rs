//! Vertex splitting for the dual-contouring mesher: where one cell
//! component's sheet touches an ambiguous cell face twice (a tube thinner
//! than a cell), its single vertex is shared by two sheets and the dual
//! edge to the neighbour lies in four triangles. Splitting each such vertex
//! into its edge-connected fans (as manifold dual contouring does) and
//! moving each copy onto the surface on its own side makes the mesh a
//! closed manifold again.

use std::collections::{HashMap, HashSet};

use geode_geo::glam::Vec3;

use geode_frep::eval::{GradEval, PointEval};
use geode_frep::tape::Tape;

/// The cell lattice the vertices were placed in: copies stay in their cell.
pub(crate) struct Cells {
    pub origin: [f64; 3],
    pub h: f64,
}

/// Splits each vertex of `candidates` (ascending, deduplicated, each with
/// the index of its brick's tape in `tapes`) whose link is not a simple
/// cycle; then the neighbours of split vertices whose link splitting broke
/// (the other end of a dual edge that lay in four triangles: its brick
/// from `brick_of`), for a few rounds. Returns how many vertices were added.
pub(crate) fn split_pinched_vertices(
    positions: &mut Vec<Vec3>,
    normals: &mut Vec<Vec3>,
    triangles: &mut [[u32; 3]],
    (candidates, brick_of): (&[(u32, u32)], BrickOf),
    tapes: &[&Tape],
    cells: &Cells,
) -> usize {
    let before = positions.len();
    let mut seen: HashSet<u32> = candidates.iter().map(|c| c.0).collect();
    let mut round = candidates.to_vec();
    for _ in 0..ROUNDS {
        let split = split_round(positions, normals, triangles, &round, tapes, cells);
        if split.is_empty() {
            break;
        }
        let split: HashSet<u32> = split.into_iter().collect();
        let mut next: Vec<(u32, u32)> = Vec::new();
        for tri in triangles.iter() {
            if tri.iter().any(|v| split.contains(v)) {
                for &v in tri {
                    if (v as usize) < before && seen.insert(v) {
                        next.push((v, brick_of(v)));
                    }
                }
            }
        }
        next.sort_unstable();
        round = next;
    }
    positions.len() - before
}

/// The brick (its tape's index) a vertex was made in.
pub(crate) type BrickOf<'a> = &'a dyn Fn(u32) -> u32;

/// Rounds of splitting: each reaches the neighbours the last one broke.
const ROUNDS: usize = 4;

/// One round of [`split_pinched_vertices`]; returns the vertices split
/// (each original and its copies).
fn split_round(
    positions: &mut Vec<Vec3>,
    normals: &mut Vec<Vec3>,
    triangles: &mut [[u32; 3]],
    candidates: &[(u32, u32)],
    tapes: &[&Tape],
    cells: &Cells,
) -> Vec<u32> {
    let mut split = Vec::new();
    if candidates.is_empty() {
        return split;
    }
    let mut incident: HashMap<u32, Vec<u32>> =
        candidates.iter().map(|&(v, _)| (v, Vec::new())).collect();
    for (t, tri) in triangles.iter().enumerate() {
        for v in tri {
            if let Some(list) = incident.get_mut(v) {
                list.push(t as u32);
            }
        }
    }
    for &(v, brick) in candidates {
        let tris = &incident[&v];
        let fans = fans_around(v, tris, triangles);
        if fans.len() < 2 {
            continue;
        }
        // The brick's tape: simplified for its region, which holds the
        // vertex's cell and so every copy.
        let tape = tapes[brick as usize];
        let (mut point, mut grad) = (PointEval::new(tape), GradEval::new(tape));
        let origin = positions[v as usize];
        let mut placed: Vec<Vec3> = Vec::with_capacity(fans.len());
        for (k, fan) in fans.iter().enumerate() {
            let id = if k == 0 {
                v
            } else {
                positions.push(origin);
                normals.push(normals[v as usize]);
                (positions.len() - 1) as u32
            };
            split.push(id);
            for &t in fan {
                for c in triangles[t as usize].iter_mut() {
                    if *c == v {
                        *c = id;
                    }
                }
            }
            let (mut p, n) = place_copy(
                origin, fan, triangles, positions, &mut point, &mut grad, cells,
            );
            if placed.iter().any(|q| q.distance(p) < 1e-3 * cells.h as f32) {
                // Projected onto one spot: keep the copy on its fan's side.
                p = p.lerp(fan_centre(fan, triangles, positions), 0.25);
            }
            placed.push(p);
            positions[id as usize] = p;
            normals[id as usize] = n;
        }
    }
    split
}

/// Incident triangles of `v` grouped so that each group's link (the ring of
/// opposite edges) is one simple cycle: the link of a pinched vertex is a
/// closed walk through some neighbour more than once, and cutting the walk
/// at every repeat leaves simple cycles, one per copy. Every edge of the
/// mesh then lies in exactly two triangles, whatever the neighbours do.
/// A link that is not a closed walk (an open surface) is left as one group.
fn fans_around(v: u32, tris: &[u32], triangles: &[[u32; 3]]) -> Vec<Vec<u32>> {
    // Link edges a -> b, one per triangle, in triangle order.
    let mut out: HashMap<u32, Vec<(u32, u32)>> = HashMap::new();
    let mut balance: HashMap<u32, i32> = HashMap::new();
    for &t in tris {
        let tri = triangles[t as usize];
        let Some(i) = tri.iter().position(|&c| c == v) else {
            continue;
        };
        let (a, b) = (tri[(i + 1) % 3], tri[(i + 2) % 3]);
        out.entry(a).or_default().push((b, t));
        *balance.entry(a).or_default() += 1;
        *balance.entry(b).or_default() -= 1;
    }
    if balance.values().any(|&d| d != 0) {
        return vec![tris.to_vec()];
    }
    for list in out.values_mut() {
        list.reverse(); // popped from the back: lowest triangle first
    }
    let mut starts: Vec<(u32, u32)> = out
        .iter()
        .flat_map(|(&a, l)| l.iter().map(move |&(_, t)| (t, a)))
        .collect();
    starts.sort_unstable();
    let mut groups = Vec::new();
    for (first, a) in starts {
        if !out[&a].iter().any(|&(_, t)| t == first) {
            continue;
        }
        // Walk from `a`, cutting a cycle off whenever a vertex repeats.
        let mut path: Vec<(u32, u32)> = Vec::new(); // (vertex, triangle leaving it)
        let mut cur = a;
        while let Some((b, t)) = out.get_mut(&cur).and_then(|l| l.pop()) {
            path.push((cur, t));
            cur = b;
            if let Some(k) = path.iter().position(|&(x, _)| x == cur) {
                groups.push(path.drain(k..).map(|(_, t)| t).collect::<Vec<u32>>());
                if path.is_empty() {
                    break;
                }
            }
        }
    }
    groups
}

/// A copy's position: the centre of its fan pulled back onto the surface by
/// Newton steps along the gradient, kept in the original vertex's cell.
fn place_copy(
    origin: Vec3,
    fan: &[u32],
    triangles: &[[u32; 3]],
    positions: &[Vec3],
    point: &mut PointEval,
    grad: &mut GradEval,
    cells: &Cells,
) -> (Vec3, Vec3) {
    let o = origin.as_dvec3().to_array();
    let cell: [f64; 3] = std::array::from_fn(|k| ((o[k] - cells.origin[k]) / cells.h).floor());
    let margin = 1e-4 * cells.h;
    let lo: [f64; 3] = std::array::from_fn(|k| cells.origin[k] + cell[k] * cells.h + margin);
    let hi: [f64; 3] = std::array::from_fn(|k| lo[k] + cells.h - 2.0 * margin);
    let clamp = |x: [f64; 3]| -> [f64; 3] { std::array::from_fn(|k| x[k].clamp(lo[k], hi[k])) };
    let centre = fan_centre(fan, triangles, positions).as_dvec3().to_array();
    // Halfway from the shared vertex towards its fan: far enough to part
    // the two sheets, near enough to keep a sharp feature the QEF found.
    let mut x = clamp(std::array::from_fn(|k| 0.5 * (o[k] + centre[k])));
    for _ in 0..4 {
        let f = point.eval(x);
        let g = grad.eval(x).d;
        let gg = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
        if !(gg > 0.0 && gg.is_finite() && f.is_finite()) || f.abs() < 1e-12 {
            break;
        }
        x = clamp(std::array::from_fn(|k| x[k] - f * g[k] / gg));
    }
    let g = grad.eval(x).d;
    let len = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
    let normal = if len > 0.0 && len.is_finite() {
        Vec3::new(
            (-g[0] / len) as f32,
            (-g[1] / len) as f32,
            (-g[2] / len) as f32,
        )
    } else {
        Vec3::Y
    };
    (Vec3::new(x[0] as f32, x[1] as f32, x[2] as f32), normal)
}

fn fan_centre(fan: &[u32], triangles: &[[u32; 3]], positions: &[Vec3]) -> Vec3 {
    let sum: Vec3 = fan
        .iter()
        .flat_map(|&t| triangles[t as usize])
        .map(|c| positions[c as usize])
        .sum();
    sum / (3 * fan.len()) as f32
}
