//! Attribute blur (Houdini's Attribute Blur): each pass moves every value
//! toward the mean of its neighbours' by `step` (Laplacian smoothing), or
//! alternates a shrinking and an inflating pass (Taubin's λ|μ smoothing,
//! which keeps the mean level: "volume preserving"). Neighbours are the
//! points an edge joins, the primitives an edge joins, or the points within
//! a radius (k-d tree, at most a given count). Pinned elements keep their
//! values. Passes are Jacobi steps over a copy: the result does not depend
//! on the order elements are visited, nor on the thread count.

use geode_geo::glam::Vec3;
use geode_geo::{Attribute, Geometry, Group};
use rayon::prelude::*;

use crate::error::unless_cancelled;
use crate::kdtree::KdTree;
use crate::relation::Rows;
use crate::AttribError;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Laplacian,
    VolumePreserving,
}

/// Taubin's pass-band: μ is chosen so 1/λ + 1/μ = 0.1.
const PASS_BAND: f32 = 0.1;

/// Elements per cancellation poll.
const CHUNK: usize = 1 << 14;

/// Points joined by an edge of a polygon or polyline.
pub fn point_neighbours(g: &Geometry) -> Rows {
    let topo = g.topology();
    let mut offsets = vec![0u32];
    let mut entries = Vec::new();
    for p in 0..g.num_points() {
        entries.extend_from_slice(topo.point_neighbours(p));
        offsets.push(entries.len() as u32);
    }
    Rows { offsets, entries }
}

/// Primitives sharing an edge, each once.
pub fn prim_neighbours(g: &Geometry) -> Rows {
    let topo = g.topology();
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for e in 0..topo.edges().len() {
        let prims: Vec<u32> = topo
            .edge_half_edges(e)
            .map(|h| topo.prim_of(h) as u32)
            .collect();
        for (i, &a) in prims.iter().enumerate() {
            for &b in &prims[i + 1..] {
                if a != b {
                    pairs.push((a, b));
                    pairs.push((b, a));
                }
            }
        }
    }
    pairs.par_sort_unstable();
    pairs.dedup();
    let mut offsets = vec![0u32; g.num_prims() + 1];
    for &(a, _) in &pairs {
        offsets[a as usize + 1] += 1;
    }
    for i in 0..g.num_prims() {
        offsets[i + 1] += offsets[i];
    }
    Rows {
        offsets,
        entries: pairs.into_iter().map(|(_, b)| b).collect(),
    }
}

/// Points within `radius` of each point (itself excluded), the nearest
/// `max` of them.
pub fn proximity_neighbours(
    positions: &[Vec3],
    radius: f32,
    max: usize,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Rows, AttribError> {
    let tree = KdTree::new_cancellable(positions, cancel).ok_or(AttribError::Cancelled)?;
    let rows: Vec<Result<Vec<Vec<u32>>, AttribError>> = positions
        .par_chunks(CHUNK)
        .enumerate()
        .map(|(c, chunk)| {
            unless_cancelled(cancel)?;
            let mut found = Vec::new();
            Ok(chunk
                .iter()
                .enumerate()
                .map(|(j, &q)| {
                    let me = (c * CHUNK + j) as u32;
                    tree.k_nearest(q, max.saturating_add(1), radius, &mut found);
                    found
                        .iter()
                        .map(|n| n.index)
                        .filter(|&i| i != me)
                        .take(max)
                        .collect()
                })
                .collect())
        })
        .collect();
    let mut out = Rows {
        offsets: vec![0],
        entries: Vec::new(),
    };
    for chunk in rows {
        for row in chunk? {
            out.entries.extend(row);
            out.offsets.push(out.entries.len() as u32);
        }
    }
    Ok(out)
}

/// `attr` (floats or vectors) blurred `iterations` times over `neighbours`.
pub fn blur(
    attr: &Attribute,
    neighbours: &Rows,
    iterations: usize,
    step: f32,
    mode: Mode,
    pinned: Option<&Group>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Attribute, AttribError> {
    let Some((values, w)) = attr.data().as_floats() else {
        return Err(AttribError::Invalid(format!(
            "a {} attribute cannot be blurred: blur floats and vectors",
            attr.attrib_type()
        )));
    };
    if neighbours.len() * w != values.len() {
        return Err(AttribError::Invalid(
            "the attribute and the neighbours are of different classes".into(),
        ));
    }
    let mu = step / (PASS_BAND * step - 1.0);
    let mut now = values.to_vec();
    let mut next = now.clone();
    for pass in 0..iterations {
        let factor = match (mode, pass % 2) {
            (Mode::VolumePreserving, 1) => mu,
            _ => step,
        };
        next.par_chunks_mut(CHUNK * w)
            .enumerate()
            .try_for_each(|(c, out)| {
                unless_cancelled(cancel)?;
                for (j, o) in out.chunks_mut(w).enumerate() {
                    let i = c * CHUNK + j;
                    let row = neighbours.row(i);
                    if row.is_empty() || pinned.is_some_and(|g| g.contains(i)) {
                        o.copy_from_slice(&now[i * w..(i + 1) * w]);
                        continue;
                    }
                    for (k, x) in o.iter_mut().enumerate() {
                        let own = now[i * w + k];
                        let mean = row.iter().map(|&n| now[n as usize * w + k]).sum::<f32>()
                            / row.len() as f32;
                        *x = own + factor * (mean - own);
                    }
                }
                Ok::<(), AttribError>(())
            })?;
        std::mem::swap(&mut now, &mut next);
    }
    let mut out = attr.clone();
    let (dst, _) = out.floats_mut().expect("a float column");
    dst.copy_from_slice(&now);
    Ok(out)
}
