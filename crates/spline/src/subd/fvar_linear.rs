//! Face-varying values where every region boundary is linear (OpenSubdiv's
//! `LINEAR_BOUNDARIES`, geode's default, and `LINEAR_ALL`): a value on a
//! seam or the mesh's boundary keeps its place, so none needs the spans
//! the smooth options track (`fvar.rs`). A value alone at its vertex, with
//! every edge there continuous, refines by the vertex's own rule over its
//! neighbours' values (under `LINEAR_ALL` it keeps its place too); a
//! continuous edge by the edge rule, any other to the midpoint of each
//! side. The same results as the span rules, in a few passes over the
//! mesh's own topology. Child values are numbered as the parent's: each
//! parent value's child, then a value per face, then the edges' (one, or
//! one per side).

use rayon::prelude::*;

use super::fvar::FVarChannel;
use super::fvar_step::Step;
use super::level::Level;
use super::refine::Plan;

/// Items per parallel task: enough to amortise the scheduling.
const GRAIN: usize = 1024;

/// The channel on the child level `c` of `p` under linear boundaries
/// (`all_linear`: every value and edge linear, OpenSubdiv's `LINEAR_ALL`).
pub(crate) fn refine_linear(
    ch: &FVarChannel,
    p: &Level,
    c: &Level,
    plan: &Plan,
    all_linear: bool,
) -> FVarChannel {
    let step = Step { ch, p, c, plan };
    let d = ch.dim;
    let continuous = step.continuous_edges();
    let alone = (!all_linear).then(|| alone_values(ch, p, &continuous));
    let layout = step.layout(&continuous, ch.values.len() / d.max(1));
    let mut values = vec![0.0f64; layout.len() * d];
    let (value_part, face_values) =
        step.faces_and_edges(&continuous, &layout, all_linear, &mut values);
    value_part
        .par_chunks_mut(d)
        .enumerate()
        .with_min_len(GRAIN)
        .for_each(|(x, out)| {
            let own = &ch.values[x * d..(x + 1) * d];
            match alone.as_ref().and_then(|a| a[x]) {
                Some(v) => step.vertex_rule(v, own, face_values, false, out),
                None => out.copy_from_slice(own),
            }
        });
    // A parent value's child is numbered as the value.
    let corner_value = step.corners(&continuous, &layout, |corner| ch.corner_value[corner]);
    FVarChannel {
        dim: d,
        values,
        corner_value,
    }
}

/// For each value, its vertex where it is the vertex's only value and every
/// edge there is continuous (the vertex's rule applies), else None (it
/// keeps its place).
fn alone_values(ch: &FVarChannel, p: &Level, continuous: &[bool]) -> Vec<Option<u32>> {
    let mut alone = vec![None; ch.values.len() / ch.dim.max(1)];
    let owners: Vec<Option<(u32, u32)>> = (0..p.num_vertices)
        .into_par_iter()
        .with_min_len(GRAIN)
        .map(|v| {
            let edges = p.vertex_edges.row(v);
            if edges.is_empty() || !edges.iter().all(|&e| continuous[e as usize]) {
                return None;
            }
            let mut corners = p.vertex_faces.row(v).iter().flat_map(|&f| {
                let r =
                    p.faces.offsets[f as usize] as usize..p.faces.offsets[f as usize + 1] as usize;
                r.filter(move |&c| p.faces.items[c] == v as u32)
            });
            let first = ch.corner_value[corners.next()?];
            corners
                .all(|c| ch.corner_value[c] == first)
                .then_some((first, v as u32))
        })
        .collect();
    for (value, v) in owners.into_iter().flatten() {
        alone[value as usize] = Some(v);
    }
    alone
}
