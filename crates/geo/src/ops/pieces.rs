//! Connected pieces and their extraction: Houdini's Connectivity (which
//! primitives touch, through a shared point or a shared edge, optionally
//! only where an attribute agrees) by union-find, pieces numbered by their
//! first primitive; and the pieces, or any lists of primitives, cut out as
//! geometries of their own in one pass each (for-each loops, split).

use rayon::prelude::*;

use crate::attrib::{AttribClass, AttribData, StringColumn};
use crate::geometry::{Geometry, PrimKind};
use crate::group::Group;
use crate::AttribTable;

/// What makes two primitives one piece.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Connect {
    /// They use a point in common.
    SharedPoint,
    /// They have an edge in common (polygon and polyline edges).
    SharedEdge,
}

/// Pieces by primitive, and by point (a point takes its primitives' piece;
/// a point no primitive uses is a piece of its own, numbered after every
/// primitive's piece, in point order).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pieces {
    pub of_prim: Vec<u32>,
    pub of_point: Vec<u32>,
    /// Pieces with primitives (numbered first).
    pub prim_pieces: usize,
    /// Every piece, loose points included.
    pub count: usize,
}

impl Pieces {
    /// The primitives of each piece, in order, and each piece's points no
    /// primitive uses.
    pub fn members(&self) -> Vec<(Vec<u32>, Vec<u32>)> {
        let mut out: Vec<(Vec<u32>, Vec<u32>)> = vec![(Vec::new(), Vec::new()); self.count];
        for (prim, &k) in self.of_prim.iter().enumerate() {
            out[k as usize].0.push(prim as u32);
        }
        for (point, &k) in self.of_point.iter().enumerate() {
            if k as usize >= self.prim_pieces {
                out[k as usize].1.push(point as u32);
            }
        }
        out
    }
}

/// Union-find over `n` elements; a root is its set's smallest element, so
/// the result does not depend on the order of the unions.
struct Sets(Vec<u32>);

impl Sets {
    fn new(n: usize) -> Sets {
        Sets((0..n as u32).collect())
    }

    fn root(&mut self, mut x: u32) -> u32 {
        while self.0[x as usize] != x {
            let up = self.0[self.0[x as usize] as usize];
            self.0[x as usize] = up;
            x = up;
        }
        x
    }

    fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.root(a), self.root(b));
        if ra != rb {
            let (lo, hi) = (ra.min(rb), ra.max(rb));
            self.0[hi as usize] = lo;
        }
    }
}

/// Whether elements `i` and `j` of a column hold the same value (strings
/// by text, floats by bits).
pub fn same_value(data: &AttribData, i: usize, j: usize) -> bool {
    if let AttribData::String(s) = data {
        return s.indices[i] == s.indices[j] || s.get(i) == s.get(j);
    }
    if let Some((f, w)) = data.as_floats() {
        return f[i * w..(i + 1) * w]
            .iter()
            .zip(&f[j * w..(j + 1) * w])
            .all(|(a, b)| a.to_bits() == b.to_bits());
    }
    data.get(i) == data.get(j)
}

/// Elements numbered by their value, in order of first appearance, and
/// the first element of each value: the pieces of a `name` or `class`
/// attribute. Floats compare by bits, strings by text.
pub fn value_classes(data: &AttribData) -> (Vec<u32>, Vec<u32>) {
    use std::collections::HashMap;
    let n = data.len();
    let mut firsts: Vec<u32> = Vec::new();
    let mut of = Vec::with_capacity(n);
    let mut number = |key: Vec<u32>, i: usize, seen: &mut HashMap<Vec<u32>, u32>| {
        let next = firsts.len() as u32;
        let k = *seen.entry(key).or_insert_with(|| {
            firsts.push(i as u32);
            next
        });
        of.push(k);
    };
    let mut seen = HashMap::new();
    if let AttribData::String(s) = data {
        // Equal text may sit at two table indices: key by the first index
        // of each text.
        let mut canon: HashMap<&str, u32> = HashMap::new();
        let ids: Vec<u32> = s
            .table
            .iter()
            .enumerate()
            .map(|(k, t)| *canon.entry(t.as_str()).or_insert(k as u32))
            .collect();
        for (i, &k) in s.indices.iter().enumerate() {
            number(vec![ids[k as usize]], i, &mut seen);
        }
    } else if let Some((f, w)) = data.as_floats() {
        for i in 0..n {
            number(
                f[i * w..(i + 1) * w].iter().map(|x| x.to_bits()).collect(),
                i,
                &mut seen,
            );
        }
    } else if let AttribData::Int(v) = data {
        for (i, x) in v.iter().enumerate() {
            number(vec![*x as u32], i, &mut seen);
        }
    } else {
        // Arrays: by their printed values (rare as piece attributes).
        let mut printed: HashMap<String, u32> = HashMap::new();
        for i in 0..n {
            let next = printed.len() as u32;
            let k = *printed.entry(format!("{:?}", data.get(i))).or_insert(next);
            number(vec![k], i, &mut seen);
        }
    }
    (of, firsts)
}

/// The pieces of `g`. With `agree`, two primitives join only where the
/// column agrees: a primitive column must hold the same value on both, a
/// vertex column (uv islands) the same value on the vertices at each shared
/// point. Edges are polygon edges; packed primitives stand alone.
pub fn connectivity(
    g: &Geometry,
    connect: Connect,
    agree: Option<(AttribClass, &AttribData)>,
) -> Pieces {
    connectivity_cancellable(g, connect, agree, &|| false).expect("never cancelled")
}

/// Elements between polls of `cancel`.
const POLL: usize = 1 << 16;

/// [`connectivity`], polling `cancel` every 65,536 elements: `None` once
/// it answers true.
pub fn connectivity_cancellable(
    g: &Geometry,
    connect: Connect,
    agree: Option<(AttribClass, &AttribData)>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Option<Pieces> {
    let mut sets = Sets::new(g.num_prims());
    let prim_of_vertex = prim_of_vertex(g);
    // Whether vertices `a` and `b` (of two primitives, on one point) let
    // their primitives join.
    let agrees = |a: usize, b: usize| match agree {
        Some((AttribClass::Primitive, d)) => {
            same_value(d, prim_of_vertex[a] as usize, prim_of_vertex[b] as usize)
        }
        Some((AttribClass::Vertex, d)) => same_value(d, a, b),
        _ => true,
    };
    match connect {
        Connect::SharedPoint => {
            // Each point keeps one vertex per distinct value seen there; a
            // vertex joins the one it agrees with.
            let mut seen: Vec<Vec<u32>> = vec![Vec::new(); g.num_points()];
            for (v, &p) in g.vertex_points().iter().enumerate() {
                if v % POLL == 0 && cancel() {
                    return None;
                }
                if !is_linked(g, prim_of_vertex[v]) {
                    continue;
                }
                let firsts = &mut seen[p as usize];
                match firsts.iter().find(|&&w| agrees(w as usize, v)) {
                    Some(&w) => sets.union(prim_of_vertex[w as usize], prim_of_vertex[v]),
                    None => firsts.push(v as u32),
                }
            }
        }
        Connect::SharedEdge => {
            let topo = g.topology();
            let vp = g.vertex_points();
            for e in 0..topo.edges().len() {
                if e % POLL == 0 && cancel() {
                    return None;
                }
                let mut hs = topo.edge_half_edges(e);
                let Some(a) = hs.next() else { continue };
                let na = topo.next(g, a).0 as usize;
                for b in hs {
                    let nb = topo.next(g, b).0 as usize;
                    let (a, b) = (a.0 as usize, b.0 as usize);
                    // The vertices of the two sides at each end.
                    let ((x, y), (z, w)) = if vp[a] == vp[b] {
                        ((a, b), (na, nb))
                    } else {
                        ((a, nb), (na, b))
                    };
                    if agrees(x, y) && agrees(z, w) {
                        sets.union(prim_of_vertex[a], prim_of_vertex[b]);
                    }
                }
            }
        }
    }
    Some(number(g, &mut sets, &prim_of_vertex))
}

/// Whether primitive `prim` joins pieces (packed primitives stand alone).
fn is_linked(g: &Geometry, prim: u32) -> bool {
    matches!(
        g.prim_kind(prim as usize),
        PrimKind::Polygon | PrimKind::Polyline | PrimKind::Patch(_)
    )
}

fn prim_of_vertex(g: &Geometry) -> Vec<u32> {
    let mut out = vec![0u32; g.num_vertices()];
    for prim in 0..g.num_prims() {
        for v in g.prim_vertex_range(prim) {
            out[v] = prim as u32;
        }
    }
    out
}

/// Pieces numbered by their first primitive, then loose points.
fn number(g: &Geometry, sets: &mut Sets, prim_of_vertex: &[u32]) -> Pieces {
    let np = g.num_prims();
    let mut of_root = vec![u32::MAX; np];
    let mut of_prim = vec![0u32; np];
    let mut next = 0u32;
    for (prim, piece) in of_prim.iter_mut().enumerate() {
        let r = sets.root(prim as u32) as usize;
        if of_root[r] == u32::MAX {
            of_root[r] = next;
            next += 1;
        }
        *piece = of_root[r];
    }
    let prim_pieces = next as usize;
    let mut of_point = vec![u32::MAX; g.num_points()];
    for (v, &p) in g.vertex_points().iter().enumerate() {
        if of_point[p as usize] == u32::MAX {
            of_point[p as usize] = of_prim[prim_of_vertex[v] as usize];
        }
    }
    for k in of_point.iter_mut().filter(|k| **k == u32::MAX) {
        *k = next;
        next += 1;
    }
    Pieces {
        of_prim,
        of_point,
        prim_pieces,
        count: next as usize,
    }
}

/// A geometry of the primitives `prims` (in that order) and the points they
/// use, with `loose` points besides, every attribute and group carried.
/// Points keep their relative order; string columns keep only the strings
/// they use.
pub fn extract(g: &Geometry, prims: &[u32], loose: &[u32]) -> Geometry {
    let vp = g.vertex_points();
    let picked = super::edit::gather_prims(g, prims.iter().copied(), None);
    let mut points: Vec<u32> = picked.vertices.iter().map(|&v| vp[v as usize]).collect();
    points.extend_from_slice(loose);
    points.sort_unstable();
    points.dedup();
    let local = |p: u32| points.binary_search(&p).expect("a used point") as u32;
    let mut out = Geometry::new();
    out.points = compact_strings(g.points.gather(&points));
    out.vertices = compact_strings(g.vertices.gather(&picked.vertices));
    out.prims = compact_strings(g.prims.gather(prims));
    out.detail = g.detail.clone();
    out.vertex_point = picked
        .vertices
        .iter()
        .map(|&v| local(vp[v as usize]))
        .collect::<Vec<_>>()
        .into();
    out.prim_offsets = picked.offsets.into();
    out.prim_kinds = picked.kinds.into();
    out.packed = picked.packed.into();
    out.patches = picked.patches;
    out.point_groups = g
        .point_groups
        .iter()
        .map(|(k, grp)| (k.clone(), grp.gather(&points)))
        .collect();
    out.prim_groups = g
        .prim_groups
        .iter()
        .map(|(k, grp)| (k.clone(), grp.gather(prims)))
        .collect();
    out.payloads = g.payloads.clone();
    out
}

/// Every piece of `pieces` as its own geometry, in piece order (pieces in
/// parallel).
pub fn split_pieces(g: &Geometry, pieces: &Pieces) -> Vec<Geometry> {
    split_pieces_cancellable(g, pieces, &|| false).expect("never cancelled")
}

/// [`split_pieces`], polling `cancel` per 256 pieces: `None` once it
/// answers true.
pub fn split_pieces_cancellable(
    g: &Geometry,
    pieces: &Pieces,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Option<Vec<Geometry>> {
    let members = pieces.members();
    let chunks: Vec<Option<Vec<Geometry>>> = members
        .par_chunks(256)
        .map(|c| {
            if cancel() {
                return None;
            }
            Some(
                c.iter()
                    .map(|(prims, loose)| extract(g, prims, loose))
                    .collect(),
            )
        })
        .collect();
    let mut out = Vec::with_capacity(members.len());
    for c in chunks {
        out.extend(c?);
    }
    Some(out)
}

/// The primitives in `group` and out of it, as two geometries (Houdini's
/// Split); points no primitive uses stay with the first.
pub fn split_by_group(g: &Geometry, group: &Group) -> (Geometry, Geometry) {
    let (inside, outside): (Vec<u32>, Vec<u32>) =
        (0..g.num_prims() as u32).partition(|&p| group.contains(p as usize));
    let mut used = vec![false; g.num_points()];
    for &p in g.vertex_points() {
        used[p as usize] = true;
    }
    let loose: Vec<u32> = (0..g.num_points() as u32)
        .filter(|&p| !used[p as usize])
        .collect();
    (extract(g, &inside, &loose), extract(g, &outside, &[]))
}

/// A table whose string columns keep only the strings their elements use
/// (a piece of a shattered shape need not carry every piece's name).
fn compact_strings(mut table: AttribTable) -> AttribTable {
    let names: Vec<String> = table
        .iter()
        .filter(|(_, a)| {
            a.as_strings()
                .is_some_and(|s| s.table.len() > s.indices.len())
        })
        .map(|(n, _)| n.to_owned())
        .collect();
    for name in names {
        let Some(a) = table.get(&name) else { continue };
        let Some(s) = a.as_strings() else { continue };
        let mut column = StringColumn {
            table: Vec::new(),
            indices: Vec::with_capacity(s.indices.len()),
        };
        let mut remap = std::collections::HashMap::new();
        for &i in &s.indices {
            let k = *remap.entry(i).or_insert_with(|| {
                column.table.push(s.table[i as usize].clone());
                column.table.len() as u32 - 1
            });
            column.indices.push(k);
        }
        let compacted = a.with_data(AttribData::String(column));
        let _ = table.remove(&name);
        table.insert(&name, compacted).expect("same length");
    }
    table
}

#[cfg(test)]
mod tests;
