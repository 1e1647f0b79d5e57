//! Connectivity built on demand: edges, adjacency, half-edges, boundaries, manifoldness.

use rayon::prelude::*;

use crate::geometry::{Geometry, PrimKind};

const NONE: u32 = u32::MAX;

/// A half-edge is identified with the polygon vertex it starts from: it runs
/// from that vertex's point to the next vertex's point of the same polygon.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct HalfEdge(pub u32);

/// Compressed rows: row `i` is `items[offsets[i]..offsets[i+1]]`.
#[derive(Clone, Debug, Default)]
pub struct Csr {
    offsets: Vec<u32>,
    items: Vec<u32>,
}

impl Csr {
    fn from_pairs(rows: usize, mut pairs: Vec<(u32, u32)>) -> Csr {
        pairs.par_sort_unstable();
        pairs.dedup();
        let mut offsets = vec![0u32; rows + 1];
        for &(r, _) in &pairs {
            offsets[r as usize + 1] += 1;
        }
        for i in 0..rows {
            offsets[i + 1] += offsets[i];
        }
        Csr {
            offsets,
            items: pairs.into_iter().map(|(_, x)| x).collect(),
        }
    }

    pub fn row(&self, i: usize) -> &[u32] {
        &self.items[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    pub fn rows(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }
}

/// What is wrong, if anything, with a surface's manifoldness.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ManifoldReport {
    /// Edges used by exactly one polygon.
    pub boundary_edges: usize,
    /// Edges used by more than two polygons.
    pub non_manifold_edges: usize,
    /// Edges shared by two polygons that traverse it in the same direction.
    pub inconsistent_edges: usize,
    /// Points whose polygons form more than one fan (bow-tie vertices).
    pub non_manifold_points: usize,
    /// Polygons with a repeated point or fewer than three distinct points.
    pub degenerate_polygons: usize,
}

impl ManifoldReport {
    /// Every edge shared by exactly two consistently oriented polygons.
    pub fn is_closed_manifold(&self) -> bool {
        *self == ManifoldReport::default()
    }
}

/// Topology of a geometry's polygons and polylines.
#[derive(Clone, Debug)]
pub struct Topology {
    /// Unique undirected edges `(a, b)` with `a < b`, sorted.
    edges: Vec<[u32; 2]>,
    /// Polygon half-edges of each edge.
    edge_half_edges: Csr,
    /// Edge of each vertex's half-edge (or segment for polylines); NONE for
    /// the last vertex of a polyline and for packed primitives.
    vertex_edge: Vec<u32>,
    vertex_prim: Vec<u32>,
    point_prims: Csr,
    point_points: Csr,
    /// Polygon half-edges leaving each point.
    point_half_edges: Csr,
    is_polygon_vertex: Vec<bool>,
}

impl Topology {
    pub(crate) fn build(g: &Geometry) -> Topology {
        let nv = g.num_vertices();
        let np = g.num_points();
        let vp = g.vertex_points();
        let mut vertex_prim = vec![0u32; nv];
        let mut is_polygon_vertex = vec![false; nv];
        // (edge key, vertex) for every segment.
        let mut keyed: Vec<(u64, u32)> = Vec::with_capacity(nv);
        for prim in 0..g.num_prims() {
            let r = g.prim_vertex_range(prim);
            for v in r.clone() {
                vertex_prim[v] = prim as u32;
            }
            let closed = match g.prim_kind(prim) {
                PrimKind::Polygon => true,
                PrimKind::Polyline => false,
                PrimKind::Packed(_) | PrimKind::Patch(_) => continue,
            };
            let n = r.len();
            let segs = if closed { n } else { n.saturating_sub(1) };
            for k in 0..segs {
                let v = r.start + k;
                let w = r.start + (k + 1) % n;
                let (a, b) = (vp[v], vp[w]);
                let key = (a.min(b) as u64) << 32 | a.max(b) as u64;
                keyed.push((key, v as u32));
                is_polygon_vertex[v] = closed;
            }
        }
        keyed.par_sort_unstable();
        let mut edges: Vec<[u32; 2]> = Vec::new();
        let mut vertex_edge = vec![NONE; nv];
        let mut edge_he_pairs: Vec<(u32, u32)> = Vec::new();
        for &(key, v) in &keyed {
            let e = [(key >> 32) as u32, key as u32];
            if edges.last() != Some(&e) {
                edges.push(e);
            }
            let ei = (edges.len() - 1) as u32;
            vertex_edge[v as usize] = ei;
            if is_polygon_vertex[v as usize] {
                edge_he_pairs.push((ei, v));
            }
        }
        let edge_half_edges = Csr::from_pairs(edges.len(), edge_he_pairs);

        let point_prims = Csr::from_pairs(np, (0..nv).map(|v| (vp[v], vertex_prim[v])).collect());
        let point_points = Csr::from_pairs(
            np,
            edges.iter().flat_map(|&[a, b]| [(a, b), (b, a)]).collect(),
        );
        let point_half_edges = Csr::from_pairs(
            np,
            (0..nv)
                .filter(|&v| is_polygon_vertex[v])
                .map(|v| (vp[v], v as u32))
                .collect(),
        );
        Topology {
            edges,
            edge_half_edges,
            vertex_edge,
            vertex_prim,
            point_prims,
            point_points,
            point_half_edges,
            is_polygon_vertex,
        }
    }

    /// Unique undirected edges `(a, b)`, `a < b`, of polygons and polylines.
    pub fn edges(&self) -> &[[u32; 2]] {
        &self.edges
    }

    /// Index of the edge `{a, b}`, if it exists.
    pub fn find_edge(&self, a: u32, b: u32) -> Option<usize> {
        self.edges.binary_search(&[a.min(b), a.max(b)]).ok()
    }

    /// Polygon half-edges lying on edge `e`.
    pub fn edge_half_edges(&self, e: usize) -> impl Iterator<Item = HalfEdge> + '_ {
        self.edge_half_edges.row(e).iter().map(|&v| HalfEdge(v))
    }

    pub fn prim_of_vertex(&self, v: usize) -> u32 {
        self.vertex_prim[v]
    }

    /// Primitives using point `p`.
    pub fn point_prims(&self, p: usize) -> &[u32] {
        self.point_prims.row(p)
    }

    /// Points joined to `p` by an edge.
    pub fn point_neighbours(&self, p: usize) -> &[u32] {
        self.point_points.row(p)
    }

    /// Polygon half-edges leaving point `p`.
    pub fn point_half_edges(&self, p: usize) -> impl Iterator<Item = HalfEdge> + '_ {
        self.point_half_edges.row(p).iter().map(|&v| HalfEdge(v))
    }

    /// The half-edge of polygon vertex `v` (None for polylines and packed).
    pub fn half_edge_of_vertex(&self, v: usize) -> Option<HalfEdge> {
        self.is_polygon_vertex
            .get(v)
            .copied()
            .unwrap_or(false)
            .then_some(HalfEdge(v as u32))
    }

    pub fn edge_of(&self, h: HalfEdge) -> usize {
        self.vertex_edge[h.0 as usize] as usize
    }

    pub fn prim_of(&self, h: HalfEdge) -> usize {
        self.vertex_prim[h.0 as usize] as usize
    }

    /// The next half-edge around the same polygon.
    pub fn next(&self, g: &Geometry, h: HalfEdge) -> HalfEdge {
        let r = g.prim_vertex_range(self.prim_of(h));
        let v = h.0 as usize + 1;
        HalfEdge(if v == r.end { r.start } else { v } as u32)
    }

    /// The previous half-edge around the same polygon.
    pub fn prev(&self, g: &Geometry, h: HalfEdge) -> HalfEdge {
        let r = g.prim_vertex_range(self.prim_of(h));
        let v = h.0 as usize;
        HalfEdge(if v == r.start { r.end - 1 } else { v - 1 } as u32)
    }

    pub fn origin(&self, g: &Geometry, h: HalfEdge) -> u32 {
        g.vertex_points()[h.0 as usize]
    }

    pub fn destination(&self, g: &Geometry, h: HalfEdge) -> u32 {
        g.vertex_points()[self.next(g, h).0 as usize]
    }

    /// The opposite half-edge on a manifold edge: None on boundary and
    /// non-manifold edges.
    pub fn twin(&self, h: HalfEdge) -> Option<HalfEdge> {
        let hs = self.edge_half_edges.row(self.edge_of(h));
        match hs {
            [a, b] if *a == h.0 => Some(HalfEdge(*b)),
            [a, b] if *b == h.0 => Some(HalfEdge(*a)),
            _ => None,
        }
    }

    /// Edges used by exactly one polygon.
    pub fn boundary_edges(&self) -> Vec<usize> {
        (0..self.edges.len())
            .filter(|&e| self.edge_half_edges.row(e).len() == 1)
            .collect()
    }

    /// Counts of everything that stops the polygons forming a closed,
    /// consistently oriented 2-manifold.
    pub fn manifold_report(&self, g: &Geometry) -> ManifoldReport {
        let mut r = ManifoldReport::default();
        let vp = g.vertex_points();
        for e in 0..self.edges.len() {
            let hs = self.edge_half_edges.row(e);
            match hs.len() {
                0 => {}
                1 => r.boundary_edges += 1,
                2 => {
                    if vp[hs[0] as usize] == vp[hs[1] as usize] {
                        r.inconsistent_edges += 1;
                    }
                }
                _ => r.non_manifold_edges += 1,
            }
        }
        for prim in 0..g.num_prims() {
            if g.prim_kind(prim) != PrimKind::Polygon {
                continue;
            }
            let pts = g.prim_points(prim);
            let mut sorted = pts.to_vec();
            sorted.sort_unstable();
            sorted.dedup();
            if sorted.len() != pts.len() || sorted.len() < 3 {
                r.degenerate_polygons += 1;
            }
        }
        r.non_manifold_points = (0..g.num_points())
            .into_par_iter()
            .filter(|&p| self.fan_count(g, p) > 1)
            .count();
        r
    }

    /// Number of separate fans of polygons around point `p` (1 on a manifold).
    pub fn fan_count(&self, g: &Geometry, p: usize) -> usize {
        let out: &[u32] = self.point_half_edges.row(p);
        if out.len() <= 1 {
            return out.len();
        }
        // Union outgoing half-edges that are adjacent across an edge: the
        // half-edge entering p before `h` in its polygon is `prev(h)`; its twin
        // leaves p in the neighbouring polygon.
        let mut parent: Vec<usize> = (0..out.len()).collect();
        fn find(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        // Each edge's half-edges leaving p are joined once, to the first of
        // them, and every polygon entering p across that edge to it: linear
        // in the polygons around p even where thousands share an edge.
        let mut first_leaving: std::collections::HashMap<usize, Option<usize>> =
            std::collections::HashMap::new();
        for (i, &h) in out.iter().enumerate() {
            let incoming = self.prev(g, HalfEdge(h));
            let edge = self.edge_of(incoming);
            let first = *first_leaving.entry(edge).or_insert_with(|| {
                let mut leaving = self
                    .edge_half_edges(edge)
                    .filter(|&o| o != incoming)
                    .filter_map(|o| out.binary_search(&o.0).ok());
                let first = leaving.next();
                if let Some(f) = first {
                    for j in leaving {
                        let (a, b) = (find(&mut parent, j), find(&mut parent, f));
                        parent[a] = b;
                    }
                }
                first
            });
            if let Some(f) = first {
                let (a, b) = (find(&mut parent, i), find(&mut parent, f));
                parent[a] = b;
            }
        }
        (0..out.len())
            .filter(|&i| find(&mut parent, i) == i)
            .count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives::cube;

    /// Thousands of polygons on one edge (a file of one face repeated) are
    /// counted in linear time: each copy is a fan of its own around each
    /// corner, as before, without pairing every copy with every other.
    #[test]
    fn fans_around_a_shared_edge_are_counted_linearly() {
        let copies = 20_000;
        let g = Geometry::from_polygons(
            vec![glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::Y],
            (0..copies).flat_map(|_| [0, 1, 2]).collect(),
            &vec![3; copies],
        )
        .unwrap();
        let t = g.topology();
        assert_eq!(t.fan_count(&g, 0), copies);
        let r = t.manifold_report(&g);
        assert_eq!((r.non_manifold_edges, r.non_manifold_points), (3, 3));
    }

    #[test]
    fn cube_is_closed_manifold() {
        let g = cube(1.0);
        let t = g.topology();
        assert_eq!(t.edges().len(), 12);
        assert!(t.boundary_edges().is_empty());
        assert!(t.manifold_report(&g).is_closed_manifold());
        for p in 0..8 {
            assert_eq!(t.point_neighbours(p).len(), 3);
            assert_eq!(t.point_prims(p).len(), 3);
            assert_eq!(t.fan_count(&g, p), 1);
        }
        // Walking next four times returns to the start; twin of twin is self.
        for v in 0..g.num_vertices() {
            let h = t.half_edge_of_vertex(v).unwrap();
            let mut k = h;
            for _ in 0..4 {
                k = t.next(&g, k);
            }
            assert_eq!(k, h);
            let tw = t.twin(h).unwrap();
            assert_eq!(t.twin(tw), Some(h));
            assert_eq!(t.origin(&g, tw), t.destination(&g, h));
            assert_eq!(t.prev(&g, t.next(&g, h)), h);
        }
    }

    #[test]
    fn open_and_bad_surfaces_are_reported() {
        let mut g = cube(1.0);
        crate::ops::delete_prims(&mut g, &crate::Group::from_members(6, [0]), true);
        let r = g.topology().manifold_report(&g);
        assert_eq!(r.boundary_edges, 4);
        assert!(!r.is_closed_manifold());

        // Flip one face of a cube: four inconsistent edges.
        let mut h = cube(1.0);
        crate::ops::reverse_prims(&mut h, Some(&crate::Group::from_members(6, [2])));
        assert_eq!(h.topology().manifold_report(&h).inconsistent_edges, 4);

        // Two triangles sharing only a point: a bow-tie vertex.
        let bow = Geometry::from_triangles(
            vec![
                glam::Vec3::ZERO,
                glam::Vec3::X,
                glam::Vec3::Y,
                -glam::Vec3::X,
                -glam::Vec3::Y,
            ],
            &[[0, 1, 2], [0, 3, 4]],
        )
        .unwrap();
        let t = bow.topology();
        assert_eq!(t.fan_count(&bow, 0), 2);
        assert_eq!(t.manifold_report(&bow).non_manifold_points, 1);

        // Three triangles on one edge.
        let fin = Geometry::from_triangles(
            vec![
                glam::Vec3::ZERO,
                glam::Vec3::X,
                glam::Vec3::Y,
                glam::Vec3::Z,
                -glam::Vec3::Y,
            ],
            &[[0, 1, 2], [1, 0, 3], [0, 1, 4]],
        )
        .unwrap();
        assert_eq!(fin.topology().manifold_report(&fin).non_manifold_edges, 1);
    }

    #[test]
    fn polylines_have_edges_but_no_half_edges() {
        let mut g = Geometry::new();
        g.add_points(&[glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::Y]);
        g.add_polyline(&[0, 1, 2]).unwrap();
        let t = g.topology();
        assert_eq!(t.edges(), &[[0, 1], [1, 2]]);
        assert!(t.half_edge_of_vertex(0).is_none());
        assert_eq!(t.point_neighbours(1), &[0, 2]);
        assert!(t.manifold_report(&g).is_closed_manifold());
    }
}
