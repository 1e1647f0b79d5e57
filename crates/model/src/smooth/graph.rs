//! The edge graph smoothing walks: each point's neighbours across polygon
//! edges and polyline segments, and which polygon edges are open.
//!
//! Built here rather than read from the geometry's `Topology`, which also
//! builds half-edges, point-to-primitive rows and manifold data that
//! smoothing never reads (a million triangles: about 1 s there, a fraction
//! here). Every edge is a key `min << 32 | max`; polygon edges and polyline
//! segments are sorted apart, runs of equal polygon keys count the
//! polygons on an edge, and the merged unique keys fill each point's row in
//! ascending order, as `Topology::point_neighbours` orders them.

use geode_geo::{Geometry, PrimKind};
use rayon::prelude::*;

pub(super) struct EdgeGraph {
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
    /// Ends of polygon edges only one polygon uses, ascending, unique.
    pub boundary_points: Vec<u32>,
    /// Polygon edges not used by exactly two polygons.
    pub open_edges: usize,
}

fn key(a: u32, b: u32) -> u64 {
    u64::from(a.min(b)) << 32 | u64::from(a.max(b))
}

fn ends(k: u64) -> [u32; 2] {
    [(k >> 32) as u32, k as u32]
}

impl EdgeGraph {
    pub fn build(g: &Geometry) -> EdgeGraph {
        let (mut polygon, mut polyline) = (
            edge_keys(g, PrimKind::Polygon),
            edge_keys(g, PrimKind::Polyline),
        );
        polygon.par_sort_unstable();
        polyline.par_sort_unstable();
        polyline.dedup();
        let (mut unique, mut boundary_points, mut open_edges) = (Vec::new(), Vec::new(), 0);
        for run in polygon.chunk_by(|a, b| a == b) {
            if run.len() == 1 {
                boundary_points.extend(ends(run[0]));
            }
            if run.len() != 2 {
                open_edges += 1;
            }
            unique.push(run[0]);
        }
        boundary_points.par_sort_unstable();
        boundary_points.dedup();
        let unique = merge_unique(&unique, &polyline);
        let (offsets, neighbours) = rows(g.num_points(), &unique);
        EdgeGraph {
            offsets,
            neighbours,
            boundary_points,
            open_edges,
        }
    }

    pub fn neighbours(&self, p: usize) -> &[u32] {
        &self.neighbours[self.offsets[p] as usize..self.offsets[p + 1] as usize]
    }
}

/// The keys of every edge of primitives of `kind`, with repeats.
fn edge_keys(g: &Geometry, kind: PrimKind) -> Vec<u64> {
    let closed = kind == PrimKind::Polygon;
    (0..g.num_prims())
        .into_par_iter()
        .filter(|&k| g.prim_kind(k) == kind)
        .flat_map_iter(|k| {
            let pts = g.prim_points(k);
            let n = pts.len();
            let segments = if closed { n } else { n.saturating_sub(1) };
            (0..segments).map(move |i| key(pts[i], pts[(i + 1) % n]))
        })
        .filter(|&k| (k >> 32) as u32 != k as u32)
        .collect()
}

/// Two ascending unique key lists merged, still ascending and unique.
fn merge_unique(a: &[u64], b: &[u64]) -> Vec<u64> {
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() || j < b.len() {
        let next = match (a.get(i), b.get(j)) {
            (Some(&x), Some(&y)) if x == y => {
                (i, j) = (i + 1, j + 1);
                x
            }
            (Some(&x), Some(&y)) if x < y => {
                i += 1;
                x
            }
            (Some(&x), None) => {
                i += 1;
                x
            }
            (_, Some(&y)) => {
                j += 1;
                y
            }
            (None, None) => unreachable!(),
        };
        out.push(next);
    }
    out
}

/// Each point's neighbours in ascending order: edges run in ascending
/// `(min, max)` order, so a point first meets its smaller neighbours (as
/// the max, in ascending order) and then its larger ones.
fn rows(points: usize, edges: &[u64]) -> (Vec<u32>, Vec<u32>) {
    let mut offsets = vec![0u32; points + 1];
    for &k in edges {
        for p in ends(k) {
            offsets[p as usize + 1] += 1;
        }
    }
    for i in 0..points {
        offsets[i + 1] += offsets[i];
    }
    let mut fill = offsets.clone();
    let mut neighbours = vec![0u32; edges.len() * 2];
    for &k in edges {
        let [a, b] = ends(k);
        neighbours[fill[a as usize] as usize] = b;
        fill[a as usize] += 1;
        neighbours[fill[b as usize] as usize] = a;
        fill[b as usize] += 1;
    }
    (offsets, neighbours)
}

#[cfg(test)]
mod tests {
    use super::*;
    use geode_geo::glam::{Vec2, Vec3};
    use geode_geo::primitives;

    /// The same rows and boundary as the geometry's own topology, on a
    /// grid with a polyline over some of its points and one of its own.
    #[test]
    fn rows_and_boundary_agree_with_the_topology() {
        let mut g = primitives::grid(Vec2::splat(2.0), 5, 4);
        g.add_polyline(&[0, 7, 13, 2]).unwrap();
        let first = g.add_points(&[Vec3::X, Vec3::Y, Vec3::Z]);
        g.add_polyline(&[first, first + 1, first + 2]).unwrap();
        let graph = EdgeGraph::build(&g);
        let topology = g.topology();
        for p in 0..g.num_points() {
            assert_eq!(
                graph.neighbours(p),
                topology.point_neighbours(p),
                "point {p}"
            );
        }
        let mut boundary: Vec<u32> = topology
            .boundary_edges()
            .into_iter()
            .flat_map(|e| topology.edges()[e])
            .collect();
        boundary.sort_unstable();
        boundary.dedup();
        assert_eq!(graph.boundary_points, boundary);
        assert_eq!(graph.open_edges, topology.boundary_edges().len());
    }
}
