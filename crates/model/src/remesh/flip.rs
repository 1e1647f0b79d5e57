//! The flip phase: an edge is flipped when that brings its four vertices'
//! valences closer to their targets (6 inside, 4 on a border), summed in
//! squares, as Botsch and Kobbelt do. Feature and border edges never flip;
//! a flip that would fold the quad, join two already joined vertices, or
//! leave a vertex with fewer than three edges is refused.
//!
//! One sweep in half-edge order over the adjacency built at its start; a
//! flip marks its four vertices so every later candidate reads true
//! adjacency. Sweeps repeat (at most eight) until none flips; the last
//! adjacency, true of the mesh when nothing flipped, goes on to the
//! relaxation. Whether an edge should flip reads only its four vertices'
//! valences, places and joins, which only a flip marking one of them
//! changes: after the first sweep only edges with a marked vertex are
//! tested again.

use rayon::prelude::*;

use super::mesh::{next, prev, Mesh, Topo, NONE};
use crate::ModelError;

const PASSES: usize = 8;

pub(super) fn flip_edges(
    m: &mut Mesh,
    topo: &mut Topo,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<(), ModelError> {
    let mut dirty: Vec<bool> = Vec::new();
    for pass in 0..PASSES {
        topo.rebuild(m);
        let topo = &*topo;
        // Whether an edge should flip reads only its two faces, which a
        // flip earlier in the sweep rewrites only with vertices it marks:
        // so the tests run in parallel beforehand and the sweep skips the
        // marked.
        let mesh = &*m;
        let candidates: Vec<u32> = (0..3 * mesh.faces.len() as u32)
            .into_par_iter()
            .filter(|&h| {
                let o = topo.opp[h as usize];
                if o == NONE || o < h || mesh.is_feature(h) || mesh.is_feature(o) {
                    return false;
                }
                let (a, b) = (mesh.from(h), mesh.to(h));
                let (c, d) = (mesh.from(prev(h)), mesh.from(prev(o)));
                let marked = |v: u32| dirty[v as usize];
                let again = pass == 0 || marked(a) || marked(b) || marked(c) || marked(d);
                again
                    && c != d
                    && (better(topo, a, b, c, d) || opens_a_cap(mesh, topo, a, b, c, d))
                    && !topo.adjacent(mesh, c, d)
                    && !folds(mesh, a, b, c, d)
            })
            .collect();
        dirty.clear();
        dirty.resize(m.pos.len(), false);
        let mut done = 0usize;
        for (i, &h) in candidates.iter().enumerate() {
            if i % 8192 == 0 && cancel() {
                return Err(ModelError::Cancelled);
            }
            let o = topo.opp[h as usize];
            let (a, b) = (m.from(h), m.to(h));
            let (c, d) = (m.from(prev(h)), m.from(prev(o)));
            if [a, b, c, d].iter().any(|&v| dirty[v as usize]) {
                continue;
            }
            let (f, g) = ((h / 3) as usize, (o / 3) as usize);
            // Faces a b c and b a d become a d c and b c d; each keeps
            // the bits of its two outer edges.
            let bit = |e: u32| m.is_feature(e) as u8;
            let (bc, ca) = (bit(next(h)), bit(prev(h)));
            let (ad, db) = (bit(next(o)), bit(prev(o)));
            m.faces[f] = [a, d, c];
            m.mask[f] = ad | (ca << 2);
            m.faces[g] = [b, c, d];
            m.mask[g] = bc | (db << 2);
            for v in [a, b, c, d] {
                dirty[v as usize] = true;
            }
            done += 1;
        }
        if done == 0 {
            return Ok(());
        }
    }
    topo.rebuild(m);
    Ok(())
}

/// Whether flipping edge a b (opposite corners c, d) lowers the squared
/// deviation of the four valences from their targets.
fn better(topo: &Topo, a: u32, b: u32, c: u32, d: u32) -> bool {
    let target = |v: u32| if topo.border[v as usize] { 4 } else { 6 };
    let val = |v: u32| topo.valence[v as usize] as i32;
    let least = |v: u32| if topo.border[v as usize] { 2 } else { 3 };
    if val(a) - 1 < least(a) || val(b) - 1 < least(b) {
        return false;
    }
    let dev = |v: u32, delta: i32| {
        let e = val(v) + delta - target(v);
        e * e
    };
    let before = dev(a, 0) + dev(b, 0) + dev(c, 0) + dev(d, 0);
    let after = dev(a, -1) + dev(b, -1) + dev(c, 1) + dev(d, 1);
    after < before
}

/// Whether edge a b faces an angle so wide (at c or d) that its faces are
/// near-degenerate caps, and flipping it widens the faces' smallest
/// angle: the valence rule cannot mend a cap between fixed corners.
fn opens_a_cap(m: &Mesh, topo: &Topo, a: u32, b: u32, c: u32, d: u32) -> bool {
    let least = |v: u32| if topo.border[v as usize] { 2 } else { 3 };
    if topo.valence[a as usize] as i32 - 1 < least(a)
        || topo.valence[b as usize] as i32 - 1 < least(b)
    {
        return false;
    }
    let p = |v: u32| m.pos[v as usize];
    // Wider than 150° (cos² > 3/4 with a negative cos), without roots:
    // anything narrower is left to the valence rule.
    let wide = |x: u32, y: u32, z: u32| {
        let (u, v) = (p(y) - p(x), p(z) - p(x));
        let dot = u.dot(v);
        dot < 0.0 && dot * dot > 0.75 * u.length_squared() * v.length_squared()
    };
    if !wide(c, a, b) && !wide(d, a, b) {
        return false;
    }
    let angle = |x: u32, y: u32, z: u32| (p(y) - p(x)).angle_between(p(z) - p(x));
    let min3 = |x: u32, y: u32, z: u32| angle(x, y, z).min(angle(y, z, x)).min(angle(z, x, y));
    min3(a, d, c).min(min3(b, c, d)) > min3(a, b, c).min(min3(b, a, d))
}

/// Whether the flipped faces would turn against the old ones.
fn folds(m: &Mesh, a: u32, b: u32, c: u32, d: u32) -> bool {
    let p = |v: u32| m.pos[v as usize];
    let normal = |x: u32, y: u32, z: u32| (p(y) - p(x)).cross(p(z) - p(x));
    let old = normal(a, b, c) + normal(b, a, d);
    normal(a, d, c).dot(old) <= 0.0 || normal(b, c, d).dot(old) <= 0.0
}
