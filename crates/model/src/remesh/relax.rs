//! Tangential relaxation and projection. Each free vertex moves to its
//! neighbours' centroid within its tangent plane (Botsch and Kobbelt's
//! uniform Laplacian with the normal part removed; area weights, as the
//! PMP library uses, gave a wider spread of edge lengths here), a vertex on a feature
//! line to the middle of its two feature neighbours, corners stay. Then
//! every vertex goes back onto the original: free ones to the closest
//! point of the original triangles, feature-line ones to the closest
//! point of the original feature edges. Both phases read the old
//! positions and write new ones per vertex, so they run in parallel and
//! give the same bytes on any number of threads.

use geode_geo::glam::Vec3;
use rayon::prelude::*;

use super::mesh::{next, Mesh, Topo};
use super::surface::Surface;

/// Every vertex relaxed; `scratch` takes the old positions (kept from
/// call to call: no fresh memory per round).
pub(super) fn relax(m: &mut Mesh, topo: &Topo, scratch: &mut Vec<Vec3>) {
    scratch.resize(m.pos.len(), Vec3::ZERO);
    let mesh = &*m;
    scratch.par_iter_mut().enumerate().for_each(|(v, out)| {
        let v = v as u32;
        *out = match topo.feature[v as usize] {
            _ if mesh.fixed[v as usize] => mesh.pos[v as usize],
            0 => tangential(mesh, topo, v),
            2 => along_feature(mesh, topo, v),
            _ => mesh.pos[v as usize],
        }
    });
    std::mem::swap(&mut m.pos, scratch);
}

/// Which vertices a projection moves.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Onto {
    All,
    Features,
}

/// The centroid of `v`'s neighbours, less its offset along the normal.
fn tangential(m: &Mesh, topo: &Topo, v: u32) -> Vec3 {
    let p = m.pos[v as usize];
    let mut sum = Vec3::ZERO;
    let mut normal = Vec3::ZERO;
    let around = topo.leaving(v);
    if around.is_empty() {
        return p;
    }
    for l in around {
        let (a, b) = (m.pos[l.to as usize], m.pos[l.third as usize]);
        normal += (a - p).cross(b - p);
        // Inside, each neighbour is in two faces: half from each.
        sum += 0.5 * (a + b);
    }
    let c = sum / around.len() as f32;
    let n = normal.normalize_or_zero();
    let d = c - p;
    p + d - n * n.dot(d)
}

/// The middle of `v`'s two feature neighbours, unless they and `v` are
/// the corners of a face whose three edges are all on feature lines (a
/// scan's noise makes such small crease triangles): there the middle is
/// on the face's third edge, and the face would lose its area.
fn along_feature(m: &Mesh, topo: &Topo, v: u32) -> Vec3 {
    let closes_a_crease_triangle = |a: u32, b: u32| {
        topo.leaving(v).iter().any(|l| {
            (l.to == a && l.third == b || l.to == b && l.third == a) && m.is_feature(next(l.edge))
        })
    };
    match topo.feature_ends(m, v) {
        Some([a, b]) if !closes_a_crease_triangle(a, b) => {
            0.5 * (m.pos[a as usize] + m.pos[b as usize])
        }
        _ => m.pos[v as usize],
    }
}

/// Vertices back onto the original (corners stay), their places there
/// and target lengths updated. Each reads and writes only its own, so in
/// place.
/// A cancel leaves the vertices not yet visited where they were (the
/// caller answers it next: a projection of a million vertices takes longer
/// than a cancel may wait).
pub(super) fn project(
    m: &mut Mesh,
    topo: &Topo,
    s: &Surface,
    which: Onto,
    cancel: &(dyn Fn() -> bool + Sync),
) {
    let (fixed, size) = (&m.fixed, &m.size);
    let stopped = std::sync::atomic::AtomicBool::new(false);
    let stop = |v: usize| {
        use std::sync::atomic::Ordering::Relaxed;
        if v.is_multiple_of(1024) && cancel() {
            stopped.store(true, Relaxed);
        }
        stopped.load(Relaxed)
    };
    m.pos
        .par_iter_mut()
        .zip(m.proj.par_iter_mut())
        .enumerate()
        .for_each(|(v, (p, proj))| {
            let (to, at) = match topo.feature[v] {
                _ if fixed[v] || stop(v) => return,
                0 if which == Onto::All => s.onto_surface(*p, *proj, size[v]),
                2 => s.onto_features(*p, size[v]),
                _ => return,
            };
            *p = to;
            *proj = at;
        });
    if let Some(sizes) = &s.sizes {
        let tris = &s.tris;
        m.size.par_iter_mut().zip(&m.proj).for_each(|(size, proj)| {
            let t = tris[proj.tri as usize];
            *size = (0..3).map(|k| proj.w[k] * sizes[t[k] as usize]).sum();
        });
    }
}
