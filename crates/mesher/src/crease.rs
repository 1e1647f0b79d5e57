//! Creases straightened: where dual contouring's quads are split across a
//! curved sharp edge (a thread's crest, where a cylinder meets a sphere),
//! the mesh zig-zags between vertices on the crease and vertices on its
//! flanks, and the edges that cut across the crease stray from the
//! surface. Such an edge is flipped to the other diagonal of its two
//! triangles when that one (and both new triangles) lie closer to the
//! surface, measured with the field; crease vertices then join along the
//! crease. Only edges between faces meeting at an angle are candidates (a
//! smooth region's edges are never measured), and each round measures
//! only the edges the last round changed.

use geode_geo::glam::Vec3;
use rayon::prelude::*;

use crate::flip::flip_edges;
use crate::surface::{field_distances, RegionTapes};

/// Faces meeting at more than this angle (cosine of 20 degrees) make
/// their shared edge a candidate.
const CREASE_COS: f32 = 0.94;
/// An edge whose midpoint strays more than this (in cells) is flipped
/// where flipping brings it closer.
const STRAY_CELLS: f64 = 0.05;
/// Rounds of flips: each takes a zig-zag one step along.
const ROUNDS: usize = 8;

/// Flips edges across creases (see the module doc); returns how many.
pub(crate) fn straighten_creases(
    tapes: &RegionTapes,
    positions: &[Vec3],
    triangles: &mut [[u32; 3]],
    cell: f64,
    cancel: &(dyn Fn() -> bool + Sync),
) -> usize {
    let mut flipped = 0;
    let mut watch: Option<Vec<bool>> = None;
    for _ in 0..ROUNDS {
        if cancel() {
            break;
        }
        let candidates = creased_edges(positions, triangles, watch.as_deref());
        if candidates.is_empty() {
            break;
        }
        let mids: Vec<Vec3> = candidates
            .iter()
            .map(|e| 0.5 * (positions[e[0] as usize] + positions[e[1] as usize]))
            .collect();
        let mut d = vec![0.0f32; mids.len()];
        field_distances(tapes, &mids, &mut d);
        let far: Vec<[u32; 2]> = candidates
            .iter()
            .zip(&d)
            .filter(|(_, d)| **d as f64 > STRAY_CELLS * cell)
            .map(|(e, _)| *e)
            .collect();
        let changed = flip_edges(tapes, positions, triangles, &far);
        if changed.is_empty() {
            break;
        }
        flipped += changed.len() / 2;
        // Next round: the corners of the triangles this one changed.
        let mut near = vec![false; positions.len()];
        for t in changed {
            triangles[t].iter().for_each(|&v| near[v as usize] = true);
        }
        watch = Some(near);
    }
    flipped
}

/// Interior edges (lower index first, sorted) whose two faces meet at an
/// angle; with `watch`, only edges with both ends watched.
fn creased_edges(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    watch: Option<&[bool]>,
) -> Vec<[u32; 2]> {
    let watched = |v: u32| watch.is_none_or(|w| w[v as usize]);
    let p = |v: u32| positions[v as usize];
    let mut half: Vec<([u32; 2], Vec3)> = triangles
        .par_iter()
        .with_min_len(4096)
        .filter(|t| t.iter().any(|&v| watched(v)))
        .flat_map_iter(|t| {
            let n = (p(t[1]) - p(t[0]))
                .cross(p(t[2]) - p(t[0]))
                .normalize_or_zero();
            (0..3).filter_map(move |i| {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                (watched(a) && watched(b)).then_some(([a.min(b), a.max(b)], n))
            })
        })
        .collect();
    // Equal keys in any order give the same edges: the test is symmetric.
    half.par_sort_unstable_by_key(|h| h.0);
    let mut edges: Vec<[u32; 2]> = half
        .windows(2)
        .filter(|w| w[0].0 == w[1].0 && w[0].1.dot(w[1].1) < CREASE_COS)
        .map(|w| w[0].0)
        .collect();
    edges.dedup();
    edges
}
