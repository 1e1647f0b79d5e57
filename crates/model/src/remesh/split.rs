//! The split phase: every edge longer than 4/3 of its target length gets
//! its midpoint, and each face is cut by the pattern of its split edges
//! (one: two triangles; two: three, the quad cut along its shorter
//! diagonal; three: four). Both faces of an edge see the same midpoint,
//! so the mesh stays conforming; passes repeat until no edge is long.
//! Midpoints are numbered in half-edge order, so the result does not
//! depend on threads.

use geode_geo::glam::Vec3;
use rayon::prelude::*;

use super::mesh::{Mesh, Topo, NONE};
use crate::ModelError;

/// Passes at most (each halves the longest edges).
const MAX_PASSES: usize = 24;

pub(super) fn split_long_edges(
    m: &mut Mesh,
    topo: &mut Topo,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<(), ModelError> {
    for _ in 0..MAX_PASSES {
        if cancel() {
            return Err(ModelError::Cancelled);
        }
        let mesh = &*m;
        let long: Vec<bool> = (0..3 * mesh.faces.len() as u32)
            .into_par_iter()
            .map(|h| {
                let (a, b) = (mesh.from(h), mesh.to(h));
                let len = (mesh.pos[a as usize] - mesh.pos[b as usize]).length();
                len > 4.0 / 3.0 * mesh.edge_size(a, b)
            })
            .collect();
        if !long.iter().any(|&l| l) {
            return Ok(());
        }
        topo.rebuild(m);
        let mids = midpoints(m, topo, &long);
        cut_faces(m, &mids);
    }
    Ok(())
}

/// The midpoint vertex of each long half-edge (NONE elsewhere), the
/// vertices appended to `m`. The lower half-edge of a pair owns it.
fn midpoints(m: &mut Mesh, topo: &Topo, long: &[bool]) -> Vec<u32> {
    let mut mids = vec![NONE; long.len()];
    let mut n = m.pos.len() as u32;
    for h in 0..long.len() {
        let o = topo.opp[h];
        if long[h] && (o == NONE || (h as u32) < o) {
            mids[h] = n;
            n += 1;
            let (a, b) = (m.from(h as u32) as usize, m.to(h as u32) as usize);
            m.pos.push(0.5 * (m.pos[a] + m.pos[b]));
            m.size.push(0.5 * (m.size[a] + m.size[b]));
            // A guess the projection starts from.
            m.proj.push(m.proj[a]);
            m.fixed.push(false);
        }
    }
    for h in 0..long.len() {
        let o = topo.opp[h];
        if long[h] && o != NONE && o < h as u32 {
            mids[h] = mids[o as usize];
        }
    }
    mids
}

/// Replaces each face by its pattern's pieces.
fn cut_faces(m: &mut Mesh, mids: &[u32]) {
    let mut faces = Vec::with_capacity(m.faces.len() * 2);
    let mut mask = Vec::with_capacity(m.faces.len() * 2);
    let pos = &m.pos;
    for (f, (&t, &bits)) in m.faces.iter().zip(&m.mask).enumerate() {
        let mid = [mids[3 * f], mids[3 * f + 1], mids[3 * f + 2]];
        let split = mid.iter().filter(|&&x| x != NONE).count();
        let bit = |k: usize| (bits >> (k % 3)) & 1;
        let mut push = |c: [u32; 3], b: [u8; 3]| {
            faces.push(c);
            mask.push(b[0] | (b[1] << 1) | (b[2] << 2));
        };
        match split {
            0 => push(t, [bit(0), bit(1), bit(2)]),
            1 => {
                let k = (0..3).find(|&k| mid[k] != NONE).expect("one split");
                let (a, b, c, x) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3], mid[k]);
                push([a, x, c], [bit(k), 0, bit(k + 2)]);
                push([x, b, c], [bit(k), bit(k + 1), 0]);
            }
            2 => {
                // Rotate so edge 2 (c to a) is the one not split.
                let k = ((0..3).find(|&k| mid[k] == NONE).expect("one whole") + 1) % 3;
                let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
                let (x, y) = (mid[k], mid[(k + 1) % 3]);
                push([x, b, y], [bit(k), bit(k + 1), 0]);
                let p = |v: u32| pos[v as usize];
                if dist2(p(a), p(y)) <= dist2(p(x), p(c)) {
                    push([a, x, y], [bit(k), 0, 0]);
                    push([a, y, c], [0, bit(k + 1), bit(k + 2)]);
                } else {
                    push([a, x, c], [bit(k), 0, bit(k + 2)]);
                    push([x, y, c], [0, bit(k + 1), 0]);
                }
            }
            _ => {
                let (x, y, z) = (mid[0], mid[1], mid[2]);
                push([t[0], x, z], [bit(0), 0, bit(2)]);
                push([x, t[1], y], [bit(0), bit(1), 0]);
                push([z, y, t[2]], [0, bit(1), bit(2)]);
                push([x, y, z], [0, 0, 0]);
            }
        }
    }
    m.faces = faces;
    m.mask = mask;
}

fn dist2(a: Vec3, b: Vec3) -> f32 {
    (a - b).length_squared()
}
