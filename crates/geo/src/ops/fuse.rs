//! Fuse points closer than a distance (spatial hashing + union-find, not O(n^2)).

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::geometry::{Geometry, PrimKind};

/// What a fuse did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FuseStats {
    pub points_removed: usize,
    pub degenerate_prims_removed: usize,
}

type Cell = (i32, i32, i32);

fn cell_of(p: Vec3, inv: f32) -> Cell {
    let c = (p * inv).floor();
    (c.x as i32, c.y as i32, c.z as i32)
}

fn find(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let gp = parent[parent[i as usize] as usize];
        parent[i as usize] = gp;
        i = gp;
    }
    i
}

/// Merges every pair of points within `distance` of each other (transitively),
/// keeping the lowest-numbered point of each cluster with its attributes and
/// moving it to the cluster's average position. Vertices are redirected;
/// consecutive repeated points in a primitive are collapsed and primitives left
/// with too few points are removed. Deterministic for any thread count.
pub fn fuse_points(g: &mut Geometry, distance: f32) -> FuseStats {
    let n = g.num_points();
    if n == 0 {
        return FuseStats::default();
    }
    let pos = g.positions();
    let d = distance.max(0.0);
    // A zero distance fuses identical positions only; any cell size works then.
    let inv = if d > 0.0 { 1.0 / d } else { 1.0 };
    let mut keyed: Vec<(Cell, u32)> = pos
        .par_iter()
        .enumerate()
        .map(|(i, &p)| (cell_of(p, inv), i as u32))
        .collect();
    keyed.par_sort_unstable();
    let d2 = d * d;
    let pairs: Vec<(u32, u32)> = keyed
        .par_iter()
        .flat_map_iter(|&(c, i)| {
            let p = pos[i as usize];
            let mut out = Vec::new();
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let nc = (c.0 + dx, c.1 + dy, c.2 + dz);
                        let start = keyed.partition_point(|e| e.0 < nc);
                        for &(kc, j) in &keyed[start..] {
                            if kc != nc {
                                break;
                            }
                            if j > i && (pos[j as usize] - p).length_squared() <= d2 {
                                out.push((i, j));
                            }
                        }
                    }
                }
            }
            out
        })
        .collect();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    for (a, b) in pairs {
        let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
        if ra != rb {
            // The lowest index is the root: the survivor is independent of order.
            let (lo, hi) = (ra.min(rb), ra.max(rb));
            parent[hi as usize] = lo;
        }
    }
    let roots: Vec<u32> = (0..n as u32).map(|i| find(&mut parent, i)).collect();
    if roots.iter().enumerate().all(|(i, &r)| r == i as u32) {
        return FuseStats::default();
    }
    let mut sum = vec![DVec3::ZERO; n];
    let mut count = vec![0u32; n];
    for (i, &r) in roots.iter().enumerate() {
        sum[r as usize] += pos[i].as_dvec3();
        count[r as usize] += 1;
    }
    let averaged: Vec<(usize, Vec3)> = (0..n)
        .filter(|&i| count[i] > 1)
        .map(|i| (i, (sum[i] / count[i] as f64).as_vec3()))
        .collect();
    {
        let p = g.positions_mut();
        for (i, a) in averaged {
            p[i] = a;
        }
    }
    for v in g.vertex_point.make_mut().iter_mut() {
        *v = roots[*v as usize];
    }
    let degenerate = collapse_repeated_points(g);
    let before = g.num_points();
    super::compact_points(g);
    g.invalidate_topology();
    FuseStats {
        points_removed: before - g.num_points(),
        degenerate_prims_removed: degenerate,
    }
}

/// Drops vertices that repeat the previous vertex's point (cyclically for
/// polygons) and primitives left too small; returns how many were removed.
fn collapse_repeated_points(g: &mut Geometry) -> usize {
    let mut keep_vertices: Vec<u32> = Vec::with_capacity(g.num_vertices());
    let mut keep_prim = vec![true; g.num_prims()];
    let mut new_counts = Vec::with_capacity(g.num_prims());
    for (prim, keep) in keep_prim.iter_mut().enumerate() {
        let r = g.prim_vertex_range(prim);
        let kind = g.prim_kinds[prim];
        let start = keep_vertices.len();
        if let PrimKind::Patch(_) = kind {
            // A control grid keeps every vertex, repeated points included.
            keep_vertices.extend(r.map(|v| v as u32));
            new_counts.push((keep_vertices.len() - start) as u32);
            continue;
        }
        for v in r.clone() {
            let p = g.vertex_point[v];
            if let Some(&last) = keep_vertices[start..].last() {
                if g.vertex_point[last as usize] == p {
                    continue;
                }
            }
            keep_vertices.push(v as u32);
        }
        if kind == PrimKind::Polygon && keep_vertices.len() - start > 1 {
            let first = g.vertex_point[keep_vertices[start] as usize];
            let last = g.vertex_point[*keep_vertices.last().unwrap() as usize];
            if first == last {
                keep_vertices.pop();
            }
        }
        let min = match kind {
            PrimKind::Polygon => 3,
            PrimKind::Polyline => 2,
            PrimKind::Packed(_) => 1,
            PrimKind::Patch(_) => 0,
        };
        if keep_vertices.len() - start < min {
            keep_vertices.truncate(start);
            *keep = false;
        }
        new_counts.push((keep_vertices.len() - start) as u32);
    }
    if keep_vertices.len() == g.num_vertices() {
        return 0;
    }
    g.vertex_point = keep_vertices
        .iter()
        .map(|&v| g.vertex_point[v as usize])
        .collect();
    g.vertices = g.vertices.gather(&keep_vertices);
    let mut acc = 0u32;
    g.prim_offsets = std::iter::once(0)
        .chain(new_counts.iter().map(|&c| {
            acc += c;
            acc
        }))
        .collect();
    let removed = keep_prim.iter().filter(|k| !**k).count();
    if removed > 0 {
        let drop = crate::Group::from_flags(keep_prim.iter().map(|k| !k));
        super::delete_prims(g, &drop, false);
    }
    removed
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives::cube;

    #[test]
    fn fuses_split_cube_back_to_closed() {
        // Six separate quads (24 points) fuse into a closed cube with 8 points.
        let c = cube(1.0);
        let mut positions = Vec::new();
        let mut faces = Vec::new();
        for prim in 0..c.num_prims() {
            for &p in c.prim_points(prim) {
                faces.push(positions.len() as u32);
                positions.push(c.positions()[p as usize] + Vec3::splat(1e-5 * prim as f32));
            }
        }
        let mut g = Geometry::from_polygons(positions, faces, &[4; 6]).unwrap();
        assert_eq!(g.topology().boundary_edges().len(), 24);
        let stats = fuse_points(&mut g, 1e-3);
        assert_eq!(stats.points_removed, 16);
        assert_eq!(g.num_points(), 8);
        assert!(g.topology().manifold_report(&g).is_closed_manifold());
    }

    #[test]
    fn collapsing_an_edge_removes_degenerates() {
        let mut g = Geometry::from_triangles(
            vec![Vec3::ZERO, Vec3::X, Vec3::new(0.0, 1e-4, 0.0), Vec3::Y],
            &[[0, 1, 2], [0, 1, 3]],
        )
        .unwrap();
        let s = fuse_points(&mut g, 1e-3);
        assert_eq!(s.degenerate_prims_removed, 1);
        assert_eq!(g.num_prims(), 1);
        assert_eq!(g.num_points(), 3);
        assert_eq!(g.positions()[0], Vec3::new(0.0, 0.5e-4, 0.0));
    }

    #[test]
    fn far_points_untouched_and_chains_are_transitive() {
        let mut g = Geometry::new();
        g.add_points(&[Vec3::ZERO, Vec3::X * 0.9, Vec3::X * 1.8, Vec3::X * 10.0]);
        g.add_polyline(&[0, 1, 2, 3]).unwrap();
        fuse_points(&mut g, 1.0);
        assert_eq!(g.num_points(), 2);
        assert_eq!(g.positions()[1], Vec3::X * 10.0);
    }
}
