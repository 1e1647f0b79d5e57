//! The half-edges polybevel walks: every face corner is the half-edge from
//! its point to the next corner's, twins paired by sorting, and each
//! point's faces ordered into one fan (closed, or open at the boundary).

use geode_geo::Geometry;
use rayon::prelude::*;

use crate::ModelError;

pub(super) const NONE: u32 = u32::MAX;

/// Half-edges of a polygon mesh, numbered by vertex (face corner).
pub(super) struct HalfEdges {
    /// Per half-edge: its face.
    pub face: Vec<u32>,
    /// Per half-edge: the half-edge running the other way (`NONE` on the
    /// boundary).
    pub twin: Vec<u32>,
    /// Per point: its outgoing half-edges (CSR).
    out_start: Vec<u32>,
    out: Vec<u32>,
}

impl HalfEdges {
    /// Refuses primitives other than polygons of three corners or more,
    /// edges of more than two faces and faces that disagree on which way
    /// round they go.
    pub fn new(g: &Geometry) -> Result<HalfEdges, ModelError> {
        for k in 0..g.num_prims() {
            if g.prim_kind(k) != geode_geo::PrimKind::Polygon {
                return Err(ModelError::Invalid(format!(
                    "polybevel takes polygons; primitive {k} is a {}",
                    g.prim_kind(k).name()
                )));
            }
            if g.prim_vertex_range(k).len() < 3 {
                return Err(ModelError::Invalid(format!(
                    "polybevel takes polygons of three corners or more; primitive {k} has {}",
                    g.prim_vertex_range(k).len()
                )));
            }
        }
        let mut face = vec![0u32; g.num_vertices()];
        for k in 0..g.num_prims() {
            face[g.prim_vertex_range(k)].fill(k as u32);
        }
        let mut me = HalfEdges {
            face,
            twin: vec![NONE; g.num_vertices()],
            out_start: Vec::new(),
            out: Vec::new(),
        };
        me.pair_twins(g)?;
        me.index_outgoing(g);
        Ok(me)
    }

    /// Twins by a total sort of (lower point, higher point, half-edge), so
    /// the pairing is the same on any thread count.
    fn pair_twins(&mut self, g: &Geometry) -> Result<(), ModelError> {
        let mut keys: Vec<(u32, u32, u32)> = (0..g.num_vertices() as u32)
            .into_par_iter()
            .map(|h| {
                let (a, b) = (self.origin(g, h), self.dest(g, h));
                (a.min(b), a.max(b), h)
            })
            .collect();
        keys.par_sort_unstable();
        let mut k = 0;
        while k < keys.len() {
            let mut e = k + 1;
            while e < keys.len() && (keys[e].0, keys[e].1) == (keys[k].0, keys[k].1) {
                e += 1;
            }
            let (a, b) = (keys[k].0, keys[k].1);
            if a == b {
                return Err(ModelError::Invalid(format!(
                    "primitive {} repeats point {a} on consecutive corners",
                    self.face[keys[k].2 as usize]
                )));
            }
            if e - k > 2 {
                return Err(ModelError::Invalid(format!(
                    "polybevel needs a manifold mesh; the edge between points {a} and {b} has {} faces",
                    e - k
                )));
            }
            if e - k == 2 {
                let (x, y) = (keys[k].2, keys[k + 1].2);
                if self.origin(g, x) == self.origin(g, y) {
                    return Err(ModelError::Invalid(format!(
                        "polybevel needs consistently wound faces; primitives {} and {} run the same way along the edge between points {a} and {b}",
                        self.face[x as usize], self.face[y as usize]
                    )));
                }
                self.twin[x as usize] = y;
                self.twin[y as usize] = x;
            }
            k = e;
        }
        Ok(())
    }

    fn index_outgoing(&mut self, g: &Geometry) {
        let mut start = vec![0u32; g.num_points() + 1];
        for &p in g.vertex_points() {
            start[p as usize + 1] += 1;
        }
        for i in 0..g.num_points() {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut out = vec![0u32; g.num_vertices()];
        for (h, &p) in g.vertex_points().iter().enumerate() {
            out[fill[p as usize] as usize] = h as u32;
            fill[p as usize] += 1;
        }
        self.out_start = start;
        self.out = out;
    }

    pub fn origin(&self, g: &Geometry, h: u32) -> u32 {
        g.vertex_points()[h as usize]
    }

    pub fn dest(&self, g: &Geometry, h: u32) -> u32 {
        g.vertex_points()[self.next(g, h) as usize]
    }

    /// The next corner of the half-edge's face.
    pub fn next(&self, g: &Geometry, h: u32) -> u32 {
        let r = g.prim_vertex_range(self.face[h as usize] as usize);
        if h as usize + 1 == r.end {
            r.start as u32
        } else {
            h + 1
        }
    }

    pub fn prev(&self, g: &Geometry, h: u32) -> u32 {
        let r = g.prim_vertex_range(self.face[h as usize] as usize);
        if h as usize == r.start {
            r.end as u32 - 1
        } else {
            h - 1
        }
    }

    pub fn outgoing(&self, p: u32) -> &[u32] {
        &self.out[self.out_start[p as usize] as usize..self.out_start[p as usize + 1] as usize]
    }

    /// The faces around point `p` as their outgoing half-edges, in the
    /// order the faces' winding turns (face i's outgoing edge is face
    /// i + 1's incoming one), and whether the fan closes. An open fan
    /// starts at the face whose incoming edge is on the boundary. A point
    /// whose faces make more than one fan is refused.
    pub fn fan(&self, g: &Geometry, p: u32) -> Result<(Vec<u32>, bool), ModelError> {
        let out = self.outgoing(p);
        let start = out
            .iter()
            .copied()
            .find(|&h| self.twin[self.prev(g, h) as usize] == NONE);
        let closed = start.is_none();
        let start = start.unwrap_or(out[0]);
        let mut fan = vec![start];
        let mut h = start;
        loop {
            let t = self.twin[h as usize];
            if t == NONE {
                break;
            }
            h = self.next(g, t);
            if h == start || fan.len() > out.len() {
                break;
            }
            fan.push(h);
        }
        if fan.len() != out.len() {
            return Err(ModelError::Invalid(format!(
                "polybevel needs a manifold mesh; the faces at point {p} make more than one fan"
            )));
        }
        Ok((fan, closed))
    }
}
