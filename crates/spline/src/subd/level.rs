//! One level of a subdivision mesh: faces as vertex and edge rings, edges
//! with their faces and sharpness, vertices with their edges, faces and
//! sharpness; built from faces at the base (edges found by sorting) and
//! directly by refinement after that.

use rayon::prelude::*;

/// OpenSubdiv's infinite sharpness: never decremented.
pub const INFINITE: f32 = 10.0;

pub fn is_sharp(s: f32) -> bool {
    s > 0.0
}

pub fn decrement(s: f32) -> f32 {
    if s >= INFINITE {
        INFINITE
    } else if s > 1.0 {
        s - 1.0
    } else {
        0.0
    }
}

/// Compressed rows: the items of row `i` are `items[offsets[i]..offsets[i + 1]]`.
#[derive(Clone, Debug, Default)]
pub struct Rows {
    pub offsets: Vec<u32>,
    pub items: Vec<u32>,
}

impl Rows {
    pub fn row(&self, i: usize) -> &[u32] {
        &self.items[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Rows for `n` keys from the (key, item) pairs `pairs` emits (called
    /// twice: to count, then to fill), items in emission order.
    pub fn group_by(n: usize, pairs: impl Fn(&mut dyn FnMut(u32, u32))) -> Rows {
        let mut offsets = vec![0u32; n + 1];
        pairs(&mut |k, _| offsets[k as usize + 1] += 1);
        for i in 0..n {
            offsets[i + 1] += offsets[i];
        }
        let mut items = vec![0u32; offsets[n] as usize];
        // Fill through the offsets shifted by one, then restore them.
        pairs(&mut |k, v| {
            let slot = &mut offsets[k as usize];
            items[*slot as usize] = v;
            *slot += 1;
        });
        for i in (1..=n).rev() {
            offsets[i] = offsets[i - 1];
        }
        offsets[0] = 0;
        Rows { offsets, items }
    }
}

/// One level of a subdivision hierarchy. Its topology is the crate's own:
/// outside it a level is only counted.
#[derive(Clone, Debug, Default)]
pub struct Level {
    pub(crate) num_vertices: usize,
    /// Face corners: vertices, and the edge from each corner to the next.
    pub(crate) faces: Rows,
    pub(crate) face_edges: Vec<u32>,
    pub(crate) hole: Vec<bool>,
    pub(crate) edge_verts: Vec<[u32; 2]>,
    pub(crate) edge_sharpness: Vec<f32>,
    pub(crate) vertex_sharpness: Vec<f32>,
    /// Derived adjacency.
    pub(crate) edge_faces: Rows,
    pub(crate) vertex_edges: Rows,
    pub(crate) vertex_faces: Rows,
}

impl Level {
    pub fn num_vertices(&self) -> usize {
        self.num_vertices
    }

    pub fn num_faces(&self) -> usize {
        self.faces.len()
    }
    /// The base level from faces; edges are numbered in order of their
    /// first (face, corner) and get sharpness from `crease(face, corner)`
    /// (the largest of their corners').
    pub fn from_faces(num_vertices: usize, faces: Rows, crease: impl Fn(usize) -> f32) -> Level {
        let n = faces.items.len();
        let mut keyed: Vec<(u32, u32, u32)> = Vec::with_capacity(n);
        for f in 0..faces.len() {
            let r = faces.row(f);
            let base = faces.offsets[f] as usize;
            for k in 0..r.len() {
                let (a, b) = (r[k], r[(k + 1) % r.len()]);
                if a == b {
                    // A degenerate edge belongs to its face alone (as in
                    // OpenSubdiv): keyed apart from every other.
                    keyed.push((a, u32::MAX - (base + k) as u32, (base + k) as u32));
                } else {
                    keyed.push((a.min(b), a.max(b), (base + k) as u32));
                }
            }
        }
        keyed.par_sort_unstable();
        let mut face_edges = vec![0u32; n];
        let mut edge_verts: Vec<[u32; 2]> = Vec::new();
        let mut edge_sharpness: Vec<f32> = Vec::new();
        let mut first_corner: Vec<u32> = Vec::new();
        let mut i = 0;
        while i < keyed.len() {
            let mut j = i;
            let mut s = 0.0f32;
            let mut first = u32::MAX;
            while j < keyed.len() && keyed[j].0 == keyed[i].0 && keyed[j].1 == keyed[i].1 {
                s = s.max(crease(keyed[j].2 as usize));
                first = first.min(keyed[j].2);
                j += 1;
            }
            let e = edge_verts.len() as u32;
            for item in &keyed[i..j] {
                face_edges[item.2 as usize] = e;
            }
            let (a, b) = (keyed[i].0, keyed[i].1);
            edge_verts.push([a, if b > u32::MAX - n as u32 { a } else { b }]);
            edge_sharpness.push(s);
            first_corner.push(first);
            i = j;
        }
        // Renumber edges by first appearance so numbering follows the faces.
        let mut order: Vec<u32> = (0..edge_verts.len() as u32).collect();
        order.sort_unstable_by_key(|&e| first_corner[e as usize]);
        let mut rank = vec![0u32; order.len()];
        for (r, &e) in order.iter().enumerate() {
            rank[e as usize] = r as u32;
        }
        let edge_verts = order.iter().map(|&e| edge_verts[e as usize]).collect();
        let edge_sharpness = order.iter().map(|&e| edge_sharpness[e as usize]).collect();
        for fe in face_edges.iter_mut() {
            *fe = rank[*fe as usize];
        }
        let hole = vec![false; faces.len()];
        let mut level = Level {
            num_vertices,
            faces,
            face_edges,
            hole,
            edge_verts,
            edge_sharpness,
            vertex_sharpness: vec![0.0; num_vertices],
            ..Level::default()
        };
        level.derive();
        level
    }

    /// Builds the adjacency rows from faces and edges.
    pub fn derive(&mut self) {
        let faces = &self.faces;
        let nf = faces.len();
        let corners = |f: usize| faces.offsets[f] as usize..faces.offsets[f + 1] as usize;
        // Edge faces, vertex faces and vertex edges are independent: build
        // them side by side.
        let (edge_faces, (vertex_faces, vertex_edges)) = rayon::join(
            || {
                Rows::group_by(self.edge_verts.len(), |emit| {
                    for f in 0..nf {
                        for c in corners(f) {
                            emit(self.face_edges[c], f as u32);
                        }
                    }
                })
            },
            || {
                rayon::join(
                    || {
                        Rows::group_by(self.num_vertices, |emit| {
                            for f in 0..nf {
                                for c in corners(f) {
                                    emit(faces.items[c], f as u32);
                                }
                            }
                        })
                    },
                    || {
                        Rows::group_by(self.num_vertices, |emit| {
                            for (e, v) in self.edge_verts.iter().enumerate() {
                                emit(v[0], e as u32);
                                if v[1] != v[0] {
                                    emit(v[1], e as u32);
                                }
                            }
                        })
                    },
                )
            },
        );
        self.edge_faces = edge_faces;
        self.vertex_faces = vertex_faces;
        self.vertex_edges = vertex_edges;
    }

    pub fn other_end(&self, e: u32, v: u32) -> u32 {
        let [a, b] = self.edge_verts[e as usize];
        if a == v {
            b
        } else {
            a
        }
    }

    /// OpenSubdiv's base tagging: boundary and non-manifold edges are
    /// infinitely sharp; non-manifold vertices too (unless on a crease of
    /// exactly two non-manifold edges), and with `sharp_corners`, vertices
    /// with one face and two edges.
    pub fn sharpen_boundaries(&mut self, sharp_corners: bool) {
        for e in 0..self.edge_verts.len() {
            if self.edge_faces.row(e).len() != 2 {
                self.edge_sharpness[e] = INFINITE;
            }
        }
        for v in 0..self.num_vertices {
            let (edges, faces) = (self.vertex_edges.row(v), self.vertex_faces.row(v));
            if edges.is_empty() {
                continue;
            }
            let face_counts = edges.iter().map(|&e| self.edge_faces.row(e as usize).len());
            let non_manifold_edges = face_counts.clone().filter(|&c| c > 2).count();
            let boundary_edges = face_counts.filter(|&c| c < 2).count();
            let manifold = non_manifold_edges == 0
                && match boundary_edges {
                    0 => faces.len() == edges.len(),
                    2 => faces.len() + 1 == edges.len(),
                    _ => false,
                };
            if faces.len() == 1 && edges.len() == 2 {
                if sharp_corners {
                    self.vertex_sharpness[v] = INFINITE;
                }
            } else if !manifold && non_manifold_edges != 2 {
                self.vertex_sharpness[v] = INFINITE;
            }
        }
    }
}
