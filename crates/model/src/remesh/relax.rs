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

use super::mesh::{Mesh, Proj, Topo};
use super::surface::Surface;

pub(super) fn relax(m: &mut Mesh, topo: &Topo) {
    let mesh = &*m;
    let moved: Vec<Vec3> = (0..mesh.pos.len() as u32)
        .into_par_iter()
        .map(|v| match topo.feature[v as usize] {
            _ if mesh.fixed[v as usize] => mesh.pos[v as usize],
            0 => tangential(mesh, topo, v),
            2 => along_feature(mesh, topo, v),
            _ => mesh.pos[v as usize],
        })
        .collect();
    m.pos = moved;
}

/// The centroid of `v`'s neighbours, less its offset along the normal.
fn tangential(m: &Mesh, topo: &Topo, v: u32) -> Vec3 {
    let p = m.pos[v as usize];
    let mut sum = Vec3::ZERO;
    let mut normal = Vec3::ZERO;
    let faces = topo.faces_of(v);
    if faces.is_empty() {
        return p;
    }
    for &f in faces {
        let t = m.faces[f as usize];
        let q = t.map(|x| m.pos[x as usize]);
        normal += (q[1] - q[0]).cross(q[2] - q[0]);
        // Inside, each neighbour is in two faces: half from each.
        for (k, &x) in t.iter().enumerate() {
            if x != v {
                sum += 0.5 * q[k];
            }
        }
    }
    let c = sum / faces.len() as f32;
    let n = normal.normalize_or_zero();
    let d = c - p;
    p + d - n * n.dot(d)
}

/// The middle of `v`'s two feature neighbours.
fn along_feature(m: &Mesh, topo: &Topo, v: u32) -> Vec3 {
    match topo.feature_ends(m, v) {
        Some([a, b]) => 0.5 * (m.pos[a as usize] + m.pos[b as usize]),
        None => m.pos[v as usize],
    }
}

/// Every vertex back onto the original (corners stay), its place there
/// and its target length updated.
pub(super) fn project(m: &mut Mesh, topo: &Topo, s: &Surface) {
    let mesh = &*m;
    let placed: Vec<(Vec3, Proj)> = (0..mesh.pos.len())
        .into_par_iter()
        .map(|v| {
            let (p, proj) = (mesh.pos[v], mesh.proj[v]);
            match topo.feature[v] {
                _ if mesh.fixed[v] => (p, proj),
                0 => s.onto_surface(p, proj, mesh.size[v]),
                2 => s.onto_features(p, mesh.size[v]),
                _ => (p, proj),
            }
        })
        .collect();
    for (v, (p, proj)) in placed.into_iter().enumerate() {
        m.pos[v] = p;
        m.proj[v] = proj;
    }
    if let Some(sizes) = &s.sizes {
        let tris = &s.tris;
        m.size.par_iter_mut().zip(&m.proj).for_each(|(size, proj)| {
            let t = tris[proj.tri as usize];
            *size = (0..3).map(|k| proj.w[k] * sizes[t[k] as usize]).sum();
        });
    }
}
