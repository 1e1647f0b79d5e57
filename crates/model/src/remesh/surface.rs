//! The original surface the remesher projects onto: its triangles in a
//! closest-point hierarchy, its feature edges in a second one (segments as
//! degenerate triangles, which the closest-point query answers as
//! segments), and, in adaptive mode, the target length at each original
//! vertex. A vertex moves little between two projections, so a walk over
//! the original's adjacency from where it was last finds a point nearly
//! as close, which bounds the hierarchy's search to a few nodes.

use geode_geo::glam::Vec3;
use geode_geo::ops::{closest_on_triangle, TriangleBvh};

use super::mesh::{Mesh, Proj, Topo, NONE};

pub(super) struct Surface {
    pub pos: Vec<Vec3>,
    pub tris: Vec<[u32; 3]>,
    bvh: TriangleBvh,
    /// The original's adjacency, for the walk.
    topo: Topo,
    /// Feature edges: one segment each, and the original half-edge it is.
    features: Option<TriangleBvh>,
    feature_edges: Vec<u32>,
    /// Target length per original vertex (adaptive mode).
    pub sizes: Option<Vec<f32>>,
}

impl Surface {
    /// The surface of `m` as it is before remeshing, features as marked;
    /// `None` once `cancel` answers true.
    pub fn new(
        m: &Mesh,
        topo: Topo,
        sizes: Option<Vec<f32>>,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Option<Surface> {
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
        let features = match segments.is_empty() {
            true => None,
            false => Some(TriangleBvh::new_cancellable(&m.pos, &segments, cancel)?),
        };
        Some(Surface {
            bvh: TriangleBvh::new_cancellable(&m.pos, &m.faces, cancel)?,
            topo,
            pos: m.pos.clone(),
            tris: m.faces.clone(),
            features,
            feature_edges,
            sizes,
        })
    }

    fn corners(&self, tri: u32) -> [Vec3; 3] {
        self.tris[tri as usize].map(|v| self.pos[v as usize])
    }

    /// The closest point of the original triangles to `p`, `size` the
    /// target length there. A walk from `hint` (where `p` was last) finds
    /// a local closest point; within a tenth of `size` of `p` it is taken
    /// (at worst a near sheet's point, on the surface either way), else
    /// its distance bounds the hierarchy's search for the true one (a walk
    /// can settle far off on a creased or thin part).
    pub fn onto_surface(&self, p: Vec3, hint: Proj, size: f32) -> (Vec3, Proj) {
        let (q, near) = self.walk(p, hint.tri);
        let dist = (q - p).length();
        if dist <= 0.1 * size {
            return (q, near);
        }
        let bound = dist * (1.0 + 1e-5) + 1e-30;
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
            None => (q, near),
        }
    }

    /// Descends from triangle `start` to a local minimum of the distance
    /// to `p`: while the closest point is on an edge (or a corner), a
    /// triangle across it (or around it) strictly closer is taken. A
    /// point inside a triangle, or on an edge or corner no neighbour
    /// improves on, is where it settles.
    fn walk(&self, p: Vec3, start: u32) -> (Vec3, Proj) {
        const STEPS: usize = 24;
        const EDGE: f32 = 1e-6;
        let at = |t: u32| {
            let (q, u, v) = closest_on_triangle(&self.corners(t), p);
            (t, q, [1.0 - u - v, u, v], (q - p).length_squared())
        };
        let mut cur = at(start);
        for _ in 0..STEPS {
            let (t, q, w, d) = cur;
            let zero = w.map(|x| x <= EDGE);
            let best = match zero.iter().filter(|&&z| z).count() {
                0 => None,
                1 => {
                    // On the edge opposite the zero corner.
                    let i = zero.iter().position(|&z| z).expect("one zero");
                    let o = self.topo.opp[3 * t as usize + (i + 1) % 3];
                    (o != NONE).then(|| at(o / 3))
                }
                _ => {
                    let j = (0..3)
                        .max_by(|&a, &b| w[a].total_cmp(&w[b]))
                        .expect("three");
                    let v = self.tris[t as usize][j];
                    self.topo
                        .faces_of(v)
                        .iter()
                        .filter(|&&f| f != t)
                        .map(|&f| at(f))
                        .min_by(|a, b| a.3.total_cmp(&b.3).then(a.0.cmp(&b.0)))
                }
            };
            match best {
                Some(next) if next.3 < d => cur = next,
                _ => return (q, Proj { tri: t, w }),
            }
        }
        let (t, q, w, _) = cur;
        (q, Proj { tri: t, w })
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
