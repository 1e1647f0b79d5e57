//! The collapse phase: edges shorter than 4/5 of their target length are
//! collapsed, one endpoint merged into the other (which does not move),
//! when the link condition holds (the mesh keeps its topology), no edge of
//! the result is longer than 4/3 of its target, no face turns over, and
//! features allow it: a vertex on a feature line only slides along it, a
//! corner never goes.
//!
//! Candidates are taken shortest first (ties by half-edge) in one
//! sequential sweep; a collapse marks every vertex of the faces it touched
//! so the adjacency built at the start of the pass stays true for every
//! later candidate (which must touch none of them). Passes repeat on a
//! rebuilt adjacency until none collapses.
//!
//! A candidate refused in one pass whose ends nothing marked is refused
//! again in the next (collapses move no vertex, and every test reads only
//! what a collapse around its ends would mark), so later passes test only
//! the edges at a marked vertex: on a UV sphere's million triangles, where
//! most short edges wait on their neighbours, that is a few thousand of
//! a million per pass.

use rayon::prelude::*;

use super::mesh::{next, prev, Mesh, Topo, NONE};
use crate::ModelError;

const MAX_PASSES: usize = 12;

pub(super) fn collapse_short_edges(
    m: &mut Mesh,
    topo: &mut Topo,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<(), ModelError> {
    let mut scratch = Scratch::default();
    // Per vertex: whether the last pass marked it (all, before the first).
    let mut changed: Vec<bool> = Vec::new();
    for pass in 0..MAX_PASSES {
        scratch.stamp.clear();
        scratch.stamp.resize(m.pos.len(), 0);
        scratch.epoch = 0;
        if cancel() {
            return Err(ModelError::Cancelled);
        }
        // Most passes at convergence find nothing: no adjacency then.
        let any = (0..3 * m.faces.len() as u32).into_par_iter().any(|h| {
            let (a, b) = (m.from(h), m.to(h));
            (m.pos[a as usize] - m.pos[b as usize]).length() < 0.8 * m.edge_size(a, b)
        });
        if !any {
            return Ok(());
        }
        topo.rebuild(m);
        let (mesh, topo) = (&*m, &*topo);
        let mut short: Vec<(f32, u32)> = (0..3 * mesh.faces.len() as u32)
            .into_par_iter()
            .filter_map(|h| {
                let o = topo.opp[h as usize];
                if o != NONE && o < h {
                    return None;
                }
                let (a, b) = (mesh.from(h), mesh.to(h));
                if pass > 0 && !changed[a as usize] && !changed[b as usize] {
                    return None;
                }
                let len = (mesh.pos[a as usize] - mesh.pos[b as usize]).length();
                (len < 0.8 * mesh.edge_size(a, b)).then_some((len, h))
            })
            .collect();
        if short.is_empty() {
            return Ok(());
        }
        short.par_sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        let mut dirty = vec![false; m.pos.len()];
        let mut dead = vec![false; m.faces.len()];
        let mut done = 0usize;
        for (i, &(_, h)) in short.iter().enumerate() {
            if i % 4096 == 0 && cancel() {
                return Err(ModelError::Cancelled);
            }
            let (a, b) = (m.from(h), m.to(h));
            if dirty[a as usize] || dirty[b as usize] {
                continue;
            }
            // Both ways allowed, the vertex of lower valence goes: tried
            // first, the other way only when it may not (a pole's
            // thousand-face ring is rarely gathered).
            let (first, second) = if topo.valence[a as usize] < topo.valence[b as usize] {
                ((a, b), (b, a))
            } else {
                ((b, a), (a, b))
            };
            let (gone, kept) = if allowed(m, topo, h, first.0, first.1, &mut scratch) {
                first
            } else if allowed(m, topo, h, second.0, second.1, &mut scratch) {
                second
            } else {
                continue;
            };
            apply(m, topo, gone, kept, &mut dead, &mut dirty);
            done += 1;
        }
        if done == 0 {
            return Ok(());
        }
        let map = m.compact(&dead);
        changed.clear();
        changed.resize(m.pos.len(), false);
        for (v, &to) in map.iter().enumerate() {
            if to != NONE {
                changed[to as usize] = dirty[v];
            }
        }
    }
    Ok(())
}

/// Reused by every candidate: no allocation per collapse. A vertex is in
/// the current ring when its stamp is the current epoch, so a ring is
/// gathered and tested in time linear in its size (a UV sphere's pole
/// has a thousand neighbours).
#[derive(Default)]
struct Scratch {
    stamp: Vec<u32>,
    epoch: u32,
}

/// Whether edge `a b` is shorter than a tenth of its target.
fn tiny(m: &Mesh, a: u32, b: u32) -> bool {
    (m.pos[a as usize] - m.pos[b as usize]).length() < TINY * m.edge_size(a, b)
}

/// Below this fraction of the target an edge between two feature lines
/// collapses though it is on neither.
const TINY: f32 = 0.1;

/// Whether `gone` may merge into `kept` along half-edge `h` (either way
/// round between them).
fn allowed(m: &Mesh, topo: &Topo, h: u32, gone: u32, kept: u32, s: &mut Scratch) -> bool {
    let on_feature = m.is_feature(h);
    if m.fixed[gone as usize] {
        return false;
    }
    match topo.feature[gone as usize] {
        0 => {}
        2 if on_feature && topo.feature[kept as usize] > 0 => {}
        // Two feature lines closer than a tenth of the target (creases
        // meeting at a sliver of the input, a line folding back past a
        // corner) cannot both be drawn with edges of the target's length:
        // left apart, they pinched triangles to no area on the OpenSubdiv
        // car. A line point that near another line's point joins it.
        2 if tiny(m, gone, kept) => {}
        _ => return false,
    }
    let o = topo.opp[h as usize];
    let c = m.from(prev(h));
    let d = if o == NONE { NONE } else { m.from(prev(o)) };
    // A corner of three edges would be left with two (a fold).
    let thin = |v: u32| v != NONE && !topo.border[v as usize] && topo.valence[v as usize] <= 3;
    if thin(c) || thin(d) {
        return false;
    }
    // No edge of the result too long, no face around `gone` turned over:
    // checked before the link condition, as they fail early and cheaply.
    let pk = m.pos[kept as usize];
    for &f in topo.faces_of(gone) {
        let t = m.faces[f as usize];
        for &x in &t {
            if x != gone
                && x != kept
                && (m.pos[x as usize] - pk).length() > 4.0 / 3.0 * m.edge_size(kept, x)
            {
                return false;
            }
        }
        if t.contains(&kept) {
            continue;
        }
        let p = t.map(|v| m.pos[v as usize]);
        let q = t.map(|v| if v == gone { pk } else { m.pos[v as usize] });
        let before = (p[1] - p[0]).cross(p[2] - p[0]);
        let after = (q[1] - q[0]).cross(q[2] - q[0]);
        if before.dot(after) <= 0.0 {
            return false;
        }
    }
    // Link condition: the common neighbours are the edge's opposite
    // corners (c and d are always common; any other is a pinch). Each of
    // `gone`'s neighbours is tested from the smaller of its ring and
    // `kept`'s, so a pole's ring is not walked per neighbour.
    s.epoch += 1;
    let ring = s.epoch;
    let mut common = 0;
    for &f in topo.faces_of(gone) {
        for &x in &m.faces[f as usize] {
            if x == gone || x == kept || s.stamp[x as usize] == ring {
                continue;
            }
            s.stamp[x as usize] = ring;
            let joined = if topo.faces_of(x).len() <= topo.faces_of(kept).len() {
                topo.adjacent(m, x, kept)
            } else {
                topo.adjacent(m, kept, x)
            };
            common += joined as u32;
        }
    }
    common == if d == NONE { 1 } else { 2 }
}

/// Merges `gone` into `kept`: the two faces of their edge die (their
/// other edges fuse, feature bits joined), the rest of `gone`'s faces
/// take `kept`.
fn apply(m: &mut Mesh, topo: &Topo, gone: u32, kept: u32, dead: &mut [bool], dirty: &mut [bool]) {
    for &f in topo.faces_of(gone).iter().chain(topo.faces_of(kept)) {
        for &v in &m.faces[f as usize] {
            dirty[v as usize] = true;
        }
    }
    for &f in topo.faces_of(gone) {
        let t = m.faces[f as usize];
        if t.contains(&kept) {
            dead[f as usize] = true;
            // The two edges other than gone-kept become one.
            let k = t
                .iter()
                .position(|&v| v != gone && v != kept)
                .expect("a third corner");
            let h1 = 3 * f + k as u32;
            let h0 = prev(h1);
            debug_assert_eq!(next(h0), h1);
            let (o0, o1) = (topo.opp[h0 as usize], topo.opp[h1 as usize]);
            let any = [h0, h1, o0, o1]
                .iter()
                .any(|&h| h != NONE && m.is_feature(h));
            if any {
                for o in [o0, o1] {
                    if o != NONE {
                        m.set_feature(o);
                    }
                }
            }
        } else {
            let k = t.iter().position(|&v| v == gone).expect("a face of gone");
            m.faces[f as usize][k] = kept;
        }
    }
}
