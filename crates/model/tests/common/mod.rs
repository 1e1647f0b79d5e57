//! Shared by the modelling kernel's tests: the Python oracles (trimesh,
//! manifold3d, scipy from PyPI, which tools/test.sh installs into
//! tools/.venv and names in GEODE_PYTHON) and mesh measures.
#![allow(dead_code)]

use geode_geo::Geometry;

pub mod meshes;

mod oracle;
pub use oracle::*;

/// The signed volume a closed mesh's polygons enclose (divergence theorem
/// over fans).
pub fn volume(g: &Geometry) -> f64 {
    let p = g.positions();
    let mut v = 0.0;
    for k in 0..g.num_prims() {
        let q = g.prim_points(k);
        for j in 1..q.len().saturating_sub(1) {
            let (a, b, c) = (
                p[q[0] as usize].as_dvec3(),
                p[q[j] as usize].as_dvec3(),
                p[q[j + 1] as usize].as_dvec3(),
            );
            v += a.dot(b.cross(c)) / 6.0;
        }
    }
    v
}

/// Euler characteristic V - E + F of a polygon mesh (edges counted
/// undirected), and whether every edge has exactly two faces.
pub fn euler_and_closed(g: &Geometry) -> (i64, bool) {
    let mut edges = std::collections::HashMap::new();
    for k in 0..g.num_prims() {
        let q = g.prim_points(k);
        for j in 0..q.len() {
            let (a, b) = (q[j], q[(j + 1) % q.len()]);
            *edges.entry((a.min(b), a.max(b))).or_insert(0u32) += 1;
        }
    }
    let used: std::collections::HashSet<u32> = (0..g.num_prims())
        .flat_map(|k| g.prim_points(k).to_vec())
        .collect();
    let closed = edges.values().all(|&n| n == 2);
    (
        used.len() as i64 - edges.len() as i64 + g.num_prims() as i64,
        closed,
    )
}
