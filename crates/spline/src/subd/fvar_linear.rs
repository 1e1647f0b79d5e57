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

use super::fvar::{blocks, continuous_edges, edge_corners, FVarChannel};
use super::level::Level;
use super::refine::{child_slot, Plan};
use super::scheme::{self, Term};

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
    let d = ch.dim;
    let num_values = ch.values.len() / d.max(1);
    let nf = p.faces.len();
    let continuous = continuous_edges(ch, p);
    let alone = (!all_linear).then(|| alone_values(ch, p, &continuous));
    // Edge values: one where continuous, else one per side.
    let face_base = num_values;
    let mut edge_base = Vec::with_capacity(p.edge_verts.len() + 1);
    let mut n = face_base + nf;
    for (e, &cont) in continuous.iter().enumerate() {
        edge_base.push(n as u32);
        n += if cont {
            1
        } else {
            p.edge_faces.row(e).len().max(1)
        };
    }
    edge_base.push(n as u32);
    let value = |corner: usize| {
        let x = ch.corner_value[corner] as usize * d;
        &ch.values[x..x + d]
    };
    let mut values = vec![0.0f64; n * d];
    let (value_part, rest) = values.split_at_mut(face_base * d);
    let (face_part, edge_part) = rest.split_at_mut(nf * d);
    face_part
        .par_chunks_mut(d)
        .enumerate()
        .with_min_len(GRAIN)
        .for_each(|(f, out)| {
            let corners = p.faces.offsets[f] as usize..p.faces.offsets[f + 1] as usize;
            let w = 1.0 / corners.len() as f64;
            for (k, out) in out.iter_mut().enumerate() {
                *out = corners.clone().map(|c| value(c)[k] * w).sum();
            }
        });
    let face_value = |f: u32| &face_part[f as usize * d..(f as usize + 1) * d];
    edge_values(
        ch,
        p,
        plan,
        &continuous,
        &edge_base,
        all_linear,
        &face_value,
        edge_part,
    );
    value_part
        .par_chunks_mut(d)
        .enumerate()
        .with_min_len(GRAIN)
        .for_each(|(x, out)| {
            let own = &ch.values[x * d..(x + 1) * d];
            match alone.as_ref().and_then(|a| a[x]) {
                Some(v) => vertex_rule(ch, p, c, plan, v, own, &face_value, out),
                None => out.copy_from_slice(own),
            }
        });
    let corner_value = child_corners(p, &continuous, &edge_base, ch, face_base as u32);
    debug_assert_eq!(corner_value.len(), c.faces.items.len());
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

/// The vertex rule of `v` (whose one value is `own`) over its neighbours'
/// values, as the span rules apply it inside a region.
#[allow(clippy::too_many_arguments)]
fn vertex_rule<'a>(
    ch: &FVarChannel,
    p: &Level,
    c: &Level,
    plan: &Plan,
    v: u32,
    own: &[f64],
    face_value: &impl Fn(u32) -> &'a [f64],
    out: &mut [f64],
) {
    let d = ch.dim;
    let (edges, faces) = (
        p.vertex_edges.row(v as usize),
        p.vertex_faces.row(v as usize),
    );
    // The value at the far end of edge e (continuous: the same from either face).
    let far = |e: u32| {
        let f = p.edge_faces.row(e as usize)[0];
        let (a, b) = edge_corners(p, f, e);
        let other = if p.faces.items[a] == v { b } else { a };
        let x = ch.corner_value[other] as usize * d;
        &ch.values[x..x + d]
    };
    out.iter_mut().for_each(|x| *x = 0.0);
    let mut emit = |t: Term, w: f64| {
        let x: &[f64] = match t {
            Term::Vertex => own,
            Term::EdgeEnd(k) => far(edges[k]),
            Term::FacePoint(k) => face_value(faces[k]),
            Term::Opposite(_) => return,
        };
        (0..d).for_each(|k| out[k] += w * x[k]);
    };
    let parent_sharp = |k: usize| super::level::is_sharp(p.edge_sharpness[edges[k] as usize]);
    let child_sharp = |k: usize| {
        let e = edges[k];
        let half = 2 * e + u32::from(p.edge_verts[e as usize][0] != v);
        super::level::is_sharp(c.edge_sharpness[half as usize])
    };
    let rules = (
        plan.parent_rule[v as usize],
        plan.child_rule[v as usize],
        plan.vertex_weight[v as usize] as f64,
    );
    scheme::blended_vertex_point(
        false,
        rules,
        edges.len(),
        faces.len(),
        parent_sharp,
        child_sharp,
        &mut emit,
    );
}

/// Each edge's child values: the edge rule where continuous (unless
/// everything is linear), else the midpoint of each side's ends.
#[allow(clippy::too_many_arguments)]
fn edge_values<'a>(
    ch: &FVarChannel,
    p: &Level,
    plan: &Plan,
    continuous: &[bool],
    edge_base: &[u32],
    all_linear: bool,
    face_value: &(impl Fn(u32) -> &'a [f64] + Sync),
    edge_part: &mut [f64],
) {
    let d = ch.dim;
    let start = edge_base[0] as usize;
    let at = |e: usize| (edge_base[e] as usize - start) * d;
    let value = |corner: usize| {
        let x = ch.corner_value[corner] as usize * d;
        &ch.values[x..x + d]
    };
    blocks(edge_part, continuous.len(), at).for_each(|(edges, block)| {
        let base = at(edges.start);
        for e in edges {
            let out = &mut block[at(e) - base..at(e + 1) - base];
            let faces = p.edge_faces.row(e);
            let ends = |f: u32| {
                let (a, b) = edge_corners(p, f, e as u32);
                (value(a), value(b))
            };
            if continuous[e] && !all_linear {
                let (xa, xb) = ends(faces[0]);
                let (end_w, face_w) = scheme::edge_point(plan.edge_weight[e] as f64, faces.len());
                for k in 0..d {
                    out[k] = end_w * (xa[k] + xb[k])
                        + faces
                            .iter()
                            .map(|&f| face_w * face_value(f)[k])
                            .sum::<f64>();
                }
            } else {
                for (&f, o) in faces.iter().zip(out.chunks_mut(d)) {
                    let (xa, xb) = ends(f);
                    for k in 0..d {
                        o[k] = 0.5 * (xa[k] + xb[k]);
                    }
                }
            }
        }
    });
}

/// The child corners' values: a quad per parent corner (the corner's
/// value's child, its next edge's value on this face's side, the face's
/// value, its previous edge's), placed as the child topology places them.
fn child_corners(
    p: &Level,
    continuous: &[bool],
    edge_base: &[u32],
    ch: &FVarChannel,
    face_base: u32,
) -> Vec<u32> {
    let mut corner_value = vec![0u32; 4 * p.faces.items.len()];
    let at = |f: usize| 4 * p.faces.offsets[f] as usize;
    blocks(&mut corner_value, p.faces.len(), at).for_each(|(faces, block)| {
        let base = at(faces.start);
        for f in faces {
            let run = &mut block[at(f) - base..at(f + 1) - base];
            let (start, end) = (p.faces.offsets[f] as usize, p.faces.offsets[f + 1] as usize);
            let side = |e: u32| {
                let base = edge_base[e as usize];
                if continuous[e as usize] {
                    base
                } else {
                    let faces = p.edge_faces.row(e as usize);
                    base + faces.iter().position(|&x| x == f as u32).unwrap_or(0) as u32
                }
            };
            for (corner, quad) in (start..end).zip(run.chunks_mut(4)) {
                let prev = if corner == start { end - 1 } else { corner - 1 };
                let items = [
                    ch.corner_value[corner],
                    side(p.face_edges[corner]),
                    face_base + f as u32,
                    side(p.face_edges[prev]),
                ];
                for (i, item) in items.into_iter().enumerate() {
                    quad[child_slot(end - start, corner - start, i)] = item;
                }
            }
        }
    });
    corner_value
}
