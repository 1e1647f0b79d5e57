//! Triangle-mesh reduction by half-edge collapses within a distance bound:
//! quadric errors order the collapses, a caller-supplied measure of distance
//! to the true surface (an FRep's field, for instance) accepts them. A
//! vertex only ever moves onto a neighbour, so every kept vertex keeps its
//! exact position and attributes; collapses that would break a closed
//! manifold (the link condition), flip or fold a triangle are never made.
//!
//! The passes themselves are in `collapse`. (Reducing a large mesh block by
//! block in parallel first was tried: no faster on the bear's 150k
//! triangles, so it is not done.)

use glam::Vec3;

/// How far a reduction may go.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReduceOptions {
    /// The largest distance, in model units, from the reduced surface to the
    /// true one at the points the measure is asked about.
    pub tolerance: f64,
    /// A collapse may turn no triangle further than this (cosine of the
    /// angle between its normal before and after).
    pub min_normal_cos: f32,
}

impl ReduceOptions {
    pub fn new(tolerance: f64) -> ReduceOptions {
        ReduceOptions {
            tolerance,
            min_normal_cos: 0.2,
        }
    }
}

/// The reduced triangles (over the input's vertex indices; vertices no
/// triangle uses any more are gone) and what it took.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Reduced {
    pub triangles: Vec<[u32; 3]>,
    pub collapses: usize,
}

/// Distances to the true surface: fills `out[i]` for `points[i]` (sign ignored).
pub type Deviation<'a> = &'a (dyn Fn(&[Vec3], &mut [f32]) + Sync);

/// Renumbers `triangles` over the vertices they still use, in their old
/// order; returns, for each new vertex, its old index.
pub fn compact_vertices(vertices: usize, triangles: &mut [[u32; 3]]) -> Vec<u32> {
    let (new_index, kept) = renumber_used(vertices, triangles.iter().flatten().copied());
    for t in triangles.iter_mut() {
        *t = t.map(|v| new_index[v as usize]);
    }
    kept
}

/// New indices for the vertices `used` names (each once, in their old
/// order; `u32::MAX` for the others) and, for each new vertex, its old
/// index.
pub fn renumber_used(vertices: usize, used: impl IntoIterator<Item = u32>) -> (Vec<u32>, Vec<u32>) {
    let mut new_index = vec![u32::MAX; vertices];
    for v in used {
        new_index[v as usize] = 0;
    }
    let mut kept = Vec::new();
    for (old, slot) in new_index.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = kept.len() as u32;
            kept.push(old as u32);
        }
    }
    (new_index, kept)
}
