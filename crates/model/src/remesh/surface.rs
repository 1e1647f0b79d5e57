//! The original surface the remesher projects onto: its triangles in a
//! closest-point hierarchy, its feature edges in a second one (segments as
//! degenerate triangles, which the closest-point query answers as
//! segments), and, in adaptive mode, the target length at each original
//! vertex.

use geode_geo::glam::Vec3;
use geode_geo::ops::{closest_on_triangle, TriangleBvh};

use super::mesh::{Mesh, Proj, Topo, NONE};

pub(super) struct Surface {
    pub pos: Vec<Vec3>,
    pub tris: Vec<[u32; 3]>,
    bvh: TriangleBvh,
    /// Feature edges: one segment each, and the original half-edge it is.
    features: Option<TriangleBvh>,
    feature_edges: Vec<u32>,
    /// Target length per original vertex (adaptive mode).
    pub sizes: Option<Vec<f32>>,
}

impl Surface {
    /// The surface of `m` as it is before remeshing, features as marked.
    pub fn new(m: &Mesh, topo: &Topo, sizes: Option<Vec<f32>>) -> Surface {
        let mut segments = Vec::new();
        let mut feature_edges = Vec::new();
        for h in 0..3 * m.faces.len() as u32 {
            let o = topo.opp[h as usize];
            if m.is_feature(h) && (o == NONE || h < o) {
                let (a, b) = (m.from(h), m.to(h));
                segments.push([a, b, b]);
                feature_edges.push(h);
            }
        }
        let features = (!segments.is_empty()).then(|| TriangleBvh::new(&m.pos, &segments));
        Surface {
            bvh: TriangleBvh::new(&m.pos, &m.faces),
            pos: m.pos.clone(),
            tris: m.faces.clone(),
            features,
            feature_edges,
            sizes,
        }
    }

    fn corners(&self, tri: u32) -> [Vec3; 3] {
        self.tris[tri as usize].map(|v| self.pos[v as usize])
    }

    /// The closest point of the original triangles to `p`; `hint` (where
    /// `p` was last) bounds the search, so most queries visit little.
    pub fn onto_surface(&self, p: Vec3, hint: Proj) -> (Vec3, Proj) {
        let (q, _, _) = closest_on_triangle(&self.corners(hint.tri), p);
        let bound = (q - p).length() * (1.0 + 1e-5) + 1e-30;
        let hit = self
            .bvh
            .closest(p, bound)
            .or_else(|| self.bvh.closest(p, f32::INFINITY));
        match hit {
            Some(c) => (
                c.point,
                Proj {
                    tri: c.triangle,
                    w: [1.0 - c.u - c.v, c.u, c.v],
                },
            ),
            None => (p, hint),
        }
    }

    /// The closest point of the original feature edges to `p`, searched
    /// first within a few target lengths.
    pub fn onto_features(&self, p: Vec3, size: f32) -> (Vec3, Proj) {
        let tree = self
            .features
            .as_ref()
            .expect("a feature vertex has features");
        let hit = tree
            .closest(p, 4.0 * size)
            .or_else(|| tree.closest(p, f32::INFINITY))
            .expect("at least one feature segment");
        let h = self.feature_edges[hit.triangle as usize];
        let (tri, k) = (h / 3, (h % 3) as usize);
        // The segment's weight of its end is u + v (corners 1 and 2 are
        // both the end).
        let t = hit.u + hit.v;
        let mut w = [0.0f32; 3];
        w[k] = 1.0 - t;
        w[(k + 1) % 3] = t;
        (hit.point, Proj { tri, w })
    }

    /// The weights of `p`'s closest point on original triangle `tri`.
    pub fn weights_on(&self, tri: u32, p: Vec3) -> ([f32; 3], f32) {
        let (q, u, v) = closest_on_triangle(&self.corners(tri), p);
        ([1.0 - u - v, u, v], (q - p).length_squared())
    }
}
