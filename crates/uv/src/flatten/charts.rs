//! Cutting a polygon mesh into islands and uv vertices ("wedges").
//!
//! Two polygons are joined across an edge when the edge is shared by
//! exactly these two polygons, they traverse it in opposite directions
//! (consistent orientation), it has two distinct points, and it is not a
//! seam. Every other edge is a cut: the mesh's own boundary, seams,
//! non-manifold edges (three polygons or more) and edges between
//! inconsistently oriented polygons.
//!
//! An island is a class of polygons joined through edges. A wedge is a
//! class of polygon vertices (corners) of one point joined across the
//! edges at that point: a point inside an island has one wedge, a point
//! on a seam one per side (which is why uv is a vertex attribute). Both
//! are found with union-find over the edges in order, then numbered by
//! first appearance, so they do not depend on the thread count.

use geode_geo::{Geometry, PrimKind, Topology};

/// Marks vertices and primitives that belong to no island.
pub(super) const NONE: u32 = u32::MAX;

/// Islands and wedges of a geometry's polygons.
#[derive(Clone, Debug, Default)]
pub(super) struct Charts {
    /// The wedge of each vertex (NONE for vertices of other primitives).
    pub vertex_wedge: Vec<u32>,
    /// The point of each wedge.
    pub wedge_point: Vec<u32>,
    /// The island of each wedge.
    pub wedge_island: Vec<u32>,
    /// The island of each primitive (NONE for primitives not polygons).
    pub prim_island: Vec<u32>,
    pub islands: usize,
}

/// The islands and wedges of `g`'s polygons, cut along `seams` (point
/// pairs, either order; pairs that are no edge of `g` are ignored).
pub(super) fn build_charts(g: &Geometry, seams: &[[u32; 2]]) -> Charts {
    let topology = g.topology();
    let is_seam = seam_edges(&topology, seams);
    let mut corners = UnionFind::new(g.num_vertices());
    let mut prims = UnionFind::new(g.num_prims());
    for (edge, &seam) in is_seam.iter().enumerate() {
        if seam {
            continue;
        }
        if let Some([h1, h2]) = joined_half_edges(g, &topology, edge) {
            // h1 runs a -> b, h2 runs b -> a: the corners at a are h1 and
            // next(h2), those at b are next(h1) and h2.
            corners.union(h1, next_vertex(g, &topology, h2));
            corners.union(next_vertex(g, &topology, h1), h2);
            prims.union(
                topology.prim_of_vertex(h1 as usize),
                topology.prim_of_vertex(h2 as usize),
            );
        }
    }
    number_classes(g, &mut corners, &mut prims)
}

/// Whether each topology edge is one of the seams.
fn seam_edges(topology: &Topology, seams: &[[u32; 2]]) -> Vec<bool> {
    let mut is_seam = vec![false; topology.edges().len()];
    for &[a, b] in seams {
        if let Some(e) = topology.find_edge(a, b) {
            is_seam[e] = true;
        }
    }
    is_seam
}

/// The two polygon half-edges (vertex numbers) of an edge that joins two
/// polygons, or None when the edge is a cut (see the module doc).
fn joined_half_edges(g: &Geometry, topology: &Topology, edge: usize) -> Option<[u32; 2]> {
    let mut half_edges = topology.edge_half_edges(edge);
    let (h1, h2) = (half_edges.next()?.0, half_edges.next()?.0);
    if half_edges.next().is_some() {
        return None;
    }
    let (p1, p2) = (
        topology.prim_of_vertex(h1 as usize),
        topology.prim_of_vertex(h2 as usize),
    );
    let polygons = g.prim_kind(p1 as usize) == PrimKind::Polygon
        && g.prim_kind(p2 as usize) == PrimKind::Polygon;
    let points = g.vertex_points();
    let (a1, b1) = (
        points[h1 as usize],
        points[next_vertex(g, topology, h1) as usize],
    );
    let (a2, b2) = (
        points[h2 as usize],
        points[next_vertex(g, topology, h2) as usize],
    );
    let opposite = a1 == b2 && b1 == a2 && a1 != b1;
    (polygons && p1 != p2 && opposite).then_some([h1, h2])
}

/// The vertex after `v` around its primitive.
fn next_vertex(g: &Geometry, topology: &Topology, v: u32) -> u32 {
    let range = g.prim_vertex_range(topology.prim_of_vertex(v as usize) as usize);
    let next = v as usize + 1;
    (if next == range.end { range.start } else { next }) as u32
}

/// Numbers wedges and islands by first appearance (vertex order, prim
/// order) over the polygons.
fn number_classes(g: &Geometry, corners: &mut UnionFind, prims: &mut UnionFind) -> Charts {
    let mut charts = Charts {
        vertex_wedge: vec![NONE; g.num_vertices()],
        prim_island: vec![NONE; g.num_prims()],
        ..Charts::default()
    };
    let mut island_of_root = vec![NONE; g.num_prims()];
    let mut wedge_of_root = vec![NONE; g.num_vertices()];
    let points = g.vertex_points();
    for prim in 0..g.num_prims() {
        if g.prim_kind(prim) != PrimKind::Polygon {
            continue;
        }
        let root = prims.find(prim as u32) as usize;
        if island_of_root[root] == NONE {
            island_of_root[root] = charts.islands as u32;
            charts.islands += 1;
        }
        let island = island_of_root[root];
        charts.prim_island[prim] = island;
        for v in g.prim_vertex_range(prim) {
            let root = corners.find(v as u32) as usize;
            if wedge_of_root[root] == NONE {
                wedge_of_root[root] = charts.wedge_point.len() as u32;
                charts.wedge_point.push(points[v]);
                charts.wedge_island.push(island);
            }
            charts.vertex_wedge[v] = wedge_of_root[root];
        }
    }
    charts
}

/// Disjoint sets over `0..n` with path halving.
struct UnionFind {
    parent: Vec<u32>,
}

impl UnionFind {
    fn new(n: usize) -> UnionFind {
        UnionFind {
            parent: (0..n as u32).collect(),
        }
    }

    fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let grandparent = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = grandparent;
            x = grandparent;
        }
        x
    }

    /// Joins the sets of `a` and `b`; the smaller root stays the root.
    fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            let (keep, join) = (ra.min(rb), ra.max(rb));
            self.parent[join as usize] = keep;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geode_geo::glam::{Vec2, Vec3};
    use geode_geo::primitives;

    #[test]
    fn a_grid_is_one_island_with_a_wedge_per_point() {
        let g = primitives::grid(Vec2::ONE, 3, 2);
        let c = build_charts(&g, &[]);
        assert_eq!(c.islands, 1);
        assert_eq!(c.wedge_point.len(), g.num_points());
    }

    #[test]
    fn a_seam_across_a_grid_makes_two_islands() {
        // Two quads side by side sharing the edge 1-4.
        let positions = (0..6)
            .map(|i| Vec3::new((i % 3) as f32, (i / 3) as f32, 0.0))
            .collect();
        let g = Geometry::from_polygons(positions, vec![0, 1, 4, 3, 1, 2, 5, 4], &[4, 4]).unwrap();
        assert_eq!(build_charts(&g, &[]).islands, 1);
        let c = build_charts(&g, &[[4, 1]]);
        assert_eq!(c.islands, 2);
        assert_eq!(c.prim_island, vec![0, 1]);
        assert_eq!(c.wedge_point.len(), 8);
    }

    #[test]
    fn a_cut_tube_is_one_island_with_doubled_seam_points() {
        let g = primitives::tube(1.0, 2.0, 8, 3, false);
        // The tube's seam column: points j * 8.
        let seams: Vec<[u32; 2]> = (0..3).map(|j| [j * 8, (j + 1) * 8]).collect();
        let c = build_charts(&g, &seams);
        assert_eq!(c.islands, 1);
        assert_eq!(c.wedge_point.len(), g.num_points() + 4);
    }

    #[test]
    fn polylines_and_non_manifold_edges() {
        // Three triangles on the edge 0-1 (a fin), and a polyline.
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, -Vec3::Y, Vec3::ONE];
        let g = Geometry::from_prims(
            positions,
            vec![0, 1, 2, 1, 0, 3, 1, 0, 4, 4, 5],
            &[3, 3, 3, 2],
            vec![
                PrimKind::Polygon,
                PrimKind::Polygon,
                PrimKind::Polygon,
                PrimKind::Polyline,
            ],
        )
        .unwrap();
        let c = build_charts(&g, &[]);
        assert_eq!(c.islands, 3);
        assert_eq!(c.prim_island[3], NONE);
        assert_eq!(&c.vertex_wedge[9..], &[NONE, NONE]);
    }
}
