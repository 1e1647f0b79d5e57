//! One level of Catmull-Clark refinement with OpenSubdiv's Catmark rules:
//! the child topology (a quad per face corner), child sharpness (uniform
//! decrement or Chaikin), and values refined by the face, edge and vertex
//! masks, semi-sharp transitions blended by their fractional weights.

use rayon::prelude::*;

use super::level::{decrement, is_sharp, Level, Rows, INFINITE};
use super::scheme::{self, Term};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule {
    Smooth,
    Dart,
    Crease,
    Corner,
}

impl Rule {
    pub(crate) fn of(vertex_sharpness: f32, sharp_edges: usize) -> Rule {
        if is_sharp(vertex_sharpness) {
            return Rule::Corner;
        }
        match sharp_edges {
            0 => Rule::Smooth,
            1 => Rule::Dart,
            2 => Rule::Crease,
            _ => Rule::Corner,
        }
    }
}

/// How each parent vertex and edge is refined.
pub struct Plan {
    pub parent_rule: Vec<Rule>,
    pub child_rule: Vec<Rule>,
    /// Parent-rule weight where the rules differ (OpenSubdiv's fractional weight).
    pub vertex_weight: Vec<f32>,
    /// Crease weight of each edge point: 0 smooth, 1 crease, between: blend.
    pub edge_weight: Vec<f32>,
}

/// Chaikin's child sharpness for edge sharpness `s` at a vertex whose
/// incident edges have sharpnesses `around` (OpenSubdiv's rule).
fn chaikin(s: f32, around: &[f32]) -> f32 {
    if around.len() < 2 {
        return decrement(s);
    }
    if !is_sharp(s) {
        return 0.0;
    }
    if s >= INFINITE {
        return INFINITE;
    }
    let semi: Vec<f32> = around
        .iter()
        .copied()
        .filter(|&x| x > 0.0 && x < INFINITE)
        .collect();
    let mut s = s;
    if semi.len() > 1 {
        let others = (semi.iter().sum::<f32>() - s) / (semi.len() - 1) as f32;
        s = 0.75 * s + 0.25 * others;
    }
    s -= 1.0;
    if is_sharp(s) {
        s
    } else {
        0.0
    }
}

/// Child sharpness of the half of edge `e` at its end `v`.
fn child_edge_sharpness(p: &Level, e: u32, v: u32, chaikin_rule: bool) -> f32 {
    let s = p.edge_sharpness[e as usize];
    if !chaikin_rule {
        return decrement(s);
    }
    let around: Vec<f32> = p
        .vertex_edges
        .row(v as usize)
        .iter()
        .map(|&x| p.edge_sharpness[x as usize])
        .collect();
    chaikin(s, &around)
}

/// The child level of `p` (vertices: parent vertices' children, then faces',
/// then edges'; a quad per parent face corner).
pub fn refine_topology(p: &Level, chaikin_rule: bool) -> Level {
    refine_topology_with(p, chaikin_rule, true, &|| false).expect("never stopped")
}

/// Rows between two polls of `stop` in the serial adjacency walks: a few
/// milliseconds of work, so a cancel lands promptly on the finest levels.
const ROWS_PER_POLL: usize = 1 << 14;

/// Whether a walk at row `i` should give up.
fn stopped_at(i: usize, stop: &(dyn Fn() -> bool + Sync)) -> bool {
    i.is_multiple_of(ROWS_PER_POLL) && stop()
}

/// The child level. With `adjacency`, whole: its edges and the adjacency
/// rows (edges' faces, vertices' faces and edges). Without, a last level
/// that is only output (not refined further, no limit masks), as
/// OpenSubdiv's uniform refinement does by default: its faces, holes and
/// vertex sharpness, and the sharpness of its halves of parent edges
/// (`plan` reads them), but no edges of its own. `None` when `stop` said
/// so, polled between phases and within the adjacency walks.
pub fn refine_topology_with(
    p: &Level,
    chaikin_rule: bool,
    adjacency: bool,
    stop: &(dyn Fn() -> bool + Sync),
) -> Option<Level> {
    let (nv, nf, ne) = (p.num_vertices, p.faces.len(), p.edge_verts.len());
    let vc = |v: u32| v;
    let fc = |f: usize| (nv + f) as u32;
    let ec = |e: u32| (nv + nf) as u32 + e;
    let corners = p.faces.items.len();
    let half = |e: u32, v: u32| -> u32 { 2 * e + u32::from(p.edge_verts[e as usize][0] != v) };
    let interior = |corner: usize| (2 * ne + corner) as u32;
    let face_of = CornerFaces::of(p);
    // Every array is filled in parallel: each parent edge makes two child
    // edges, each parent face corner an interior edge and a quad.
    let edges = if adjacency { 2 * ne + corners } else { 0 };
    let mut edge_verts = vec![[0u32; 2]; edges];
    let mut edge_sharpness = vec![0.0f32; edges.max(2 * ne)];
    edge_sharpness[..2 * ne]
        .par_chunks_mut(2)
        .enumerate()
        .try_for_each(|(e, es)| {
            if stopped_at(e, stop) {
                return None;
            }
            let [a, b] = p.edge_verts[e];
            es[0] = child_edge_sharpness(p, e as u32, a, chaikin_rule);
            es[1] = child_edge_sharpness(p, e as u32, b, chaikin_rule);
            Some(())
        })?;
    let mut face_edges = vec![0u32; if adjacency { 4 * corners } else { 0 }];
    if adjacency {
        let (halves, inner) = edge_verts.split_at_mut(2 * ne);
        halves.par_chunks_mut(2).enumerate().for_each(|(e, ev)| {
            let [a, b] = p.edge_verts[e];
            ev[0] = [vc(a), ec(e as u32)];
            ev[1] = [vc(b), ec(e as u32)];
        });
        inner.par_iter_mut().enumerate().try_for_each(|(c, ev)| {
            if stopped_at(c, stop) {
                return None;
            }
            *ev = [ec(p.face_edges[c]), fc(face_of.face(c))];
            Some(())
        })?;
        fill_quads(&mut face_edges, p, &face_of, stop, |c, prev| {
            let v = p.faces.items[c];
            let (e_next, e_prev) = (p.face_edges[c], p.face_edges[prev]);
            [
                half(e_next, v),
                interior(c),
                interior(prev),
                half(e_prev, v),
            ]
        })?;
    }
    let mut face_verts = vec![0u32; 4 * corners];
    fill_quads(&mut face_verts, p, &face_of, stop, |c, prev| {
        let (v, f) = (p.faces.items[c], face_of.face(c));
        [vc(v), ec(p.face_edges[c]), fc(f), ec(p.face_edges[prev])]
    })?;
    let hole: Vec<bool> = (0..corners)
        .into_par_iter()
        .map(|c| p.hole[face_of.face(c)])
        .collect();
    if stop() {
        return None;
    }
    let mut child = Level {
        num_vertices: nv + nf + ne,
        faces: Rows {
            offsets: (0..=corners as u32)
                .into_par_iter()
                .map(|i| 4 * i)
                .collect(),
            items: face_verts,
        },
        face_edges,
        hole,
        edge_verts,
        edge_sharpness,
        vertex_sharpness: (0..nv + nf + ne)
            .into_par_iter()
            .map(|i| {
                if i < nv {
                    decrement(p.vertex_sharpness[i])
                } else {
                    0.0
                }
            })
            .collect(),
        ..Level::default()
    };
    if stop() {
        return None;
    }
    if !adjacency {
        return Some(child);
    }
    let (edge_faces, (vertex_faces, vertex_edges)) = rayon::join(
        || child_edge_faces(p, stop),
        || {
            rayon::join(
                || child_vertex_faces(p, stop),
                || child_vertex_edges(p, stop),
            )
        },
    );
    child.edge_faces = edge_faces?;
    child.vertex_faces = vertex_faces?;
    child.vertex_edges = vertex_edges?;
    Some(child)
}

/// Fills each parent corner's child quad from `items(corner, previous
/// corner)` (vertex child, next edge's, face's, previous edge's), placed
/// as [`child_slot`] says; `None` when `stop` said so.
fn fill_quads(
    out: &mut [u32],
    p: &Level,
    face_of: &CornerFaces,
    stop: &(dyn Fn() -> bool + Sync),
    items: impl Fn(usize, usize) -> [u32; 4] + Sync,
) -> Option<()> {
    out.par_chunks_mut(4).enumerate().try_for_each(|(c, quad)| {
        if stopped_at(c, stop) {
            return None;
        }
        let (n, k, prev) = face_of.place(p, c);
        for (i, item) in items(c, prev).into_iter().enumerate() {
            quad[child_slot(n, k, i)] = item;
        }
        Some(())
    })
}

/// The face of each parent corner: a division where every face is a quad
/// (every level after the first), else a table.
enum CornerFaces {
    Quads,
    Table(Vec<u32>),
}

impl CornerFaces {
    fn of(p: &Level) -> CornerFaces {
        let quads = p.faces.items.len() == 4 * p.faces.len()
            && p.faces
                .offsets
                .par_iter()
                .enumerate()
                .all(|(f, &o)| o as usize == 4 * f);
        if quads {
            return CornerFaces::Quads;
        }
        CornerFaces::Table(
            (0..p.faces.len())
                .into_par_iter()
                .flat_map_iter(|f| std::iter::repeat_n(f as u32, p.faces.row(f).len()))
                .collect(),
        )
    }

    fn face(&self, c: usize) -> usize {
        match self {
            CornerFaces::Quads => c / 4,
            CornerFaces::Table(t) => t[c] as usize,
        }
    }

    /// Corner `c`'s face size, its place in the face and the previous
    /// corner.
    fn place(&self, p: &Level, c: usize) -> (usize, usize, usize) {
        let f = self.face(c);
        let base = p.faces.offsets[f] as usize;
        let n = p.faces.offsets[f + 1] as usize - base;
        let k = c - base;
        (n, k, base + (k + n - 1) % n)
    }
}

/// Where item `i` of the child quad of corner `k` (vertex child, next edge
/// child, face child, previous edge child) goes: in a quad's children the
/// vertex child keeps its parent corner's place, as in OpenSubdiv, so a
/// child quad keeps its parent's orientation; other faces' children start
/// at their vertex child.
pub(crate) fn child_slot(n: usize, k: usize, i: usize) -> usize {
    if n == 4 {
        (k + i) % 4
    } else {
        i
    }
}

/// Rows written in order: each call of `row` appends one row's items.
struct RowWriter {
    rows: Rows,
}

impl RowWriter {
    fn with_capacity(rows: usize, items: usize) -> RowWriter {
        let mut offsets = Vec::with_capacity(rows + 1);
        offsets.push(0);
        RowWriter {
            rows: Rows {
                offsets,
                items: Vec::with_capacity(items),
            },
        }
    }

    fn push(&mut self, item: u32) {
        self.rows.items.push(item);
    }

    fn end_row(&mut self) {
        self.rows.offsets.push(self.rows.items.len() as u32);
    }
}

/// The corner of parent face `f` whose edge (to the next corner) is `e`.
pub(crate) fn corner_of_edge(p: &Level, f: u32, e: u32) -> usize {
    let range = p.faces.offsets[f as usize] as usize..p.faces.offsets[f as usize + 1] as usize;
    range
        .clone()
        .find(|&c| p.face_edges[c] == e)
        .unwrap_or(range.start)
}

/// The next corner of `c` around its face.
pub(crate) fn next_corner(p: &Level, f: u32, c: usize) -> usize {
    let (start, end) = (
        p.faces.offsets[f as usize] as usize,
        p.faces.offsets[f as usize + 1] as usize,
    );
    if c + 1 == end {
        start
    } else {
        c + 1
    }
}

/// Child edges' faces, built from the parent's (no search over the child):
/// a half of parent edge `e` lies in the quads at its end's corner of each
/// face of `e`; an interior edge of corner `c` in the quads of `c` and the
/// next corner.
fn child_edge_faces(p: &Level, stop: &(dyn Fn() -> bool + Sync)) -> Option<Rows> {
    let corners = p.faces.items.len();
    let mut w = RowWriter::with_capacity(
        2 * p.edge_verts.len() + corners,
        2 * p.edge_faces.items.len() + 2 * corners,
    );
    for (e, ends) in p.edge_verts.iter().enumerate() {
        if stopped_at(e, stop) {
            return None;
        }
        for end in ends {
            for &f in p.edge_faces.row(e) {
                let c = corner_of_edge(p, f, e as u32);
                // The corner at this end: where the edge starts, or the next.
                let at = if p.faces.items[c] == *end {
                    c
                } else {
                    next_corner(p, f, c)
                };
                w.push(at as u32);
            }
            w.end_row();
        }
    }
    for f in 0..p.faces.len() {
        if stopped_at(f, stop) {
            return None;
        }
        for c in p.faces.offsets[f] as usize..p.faces.offsets[f + 1] as usize {
            w.push(c as u32);
            w.push(next_corner(p, f as u32, c) as u32);
            w.end_row();
        }
    }
    Some(w.rows)
}

/// Child vertices' faces: a vertex child lies in the quad of each of its
/// parent's corners, a face child in its face's quads, an edge child in the
/// quads at both ends of each face of its edge.
fn child_vertex_faces(p: &Level, stop: &(dyn Fn() -> bool + Sync)) -> Option<Rows> {
    let (nv, nf, ne) = (p.num_vertices, p.faces.len(), p.edge_verts.len());
    let corners = p.faces.items.len();
    let mut w = RowWriter::with_capacity(nv + nf + ne, 2 * corners + 2 * p.edge_faces.items.len());
    // Corners of each parent vertex, grouped (faces in the parent's order).
    for v in 0..nv {
        if stopped_at(v, stop) {
            return None;
        }
        let mut last = u32::MAX;
        for &f in p.vertex_faces.row(v) {
            if f == last {
                continue; // a face touching the vertex twice is listed once per corner below
            }
            last = f;
            for c in p.faces.offsets[f as usize] as usize..p.faces.offsets[f as usize + 1] as usize
            {
                if p.faces.items[c] == v as u32 {
                    w.push(c as u32);
                }
            }
        }
        w.end_row();
    }
    for f in 0..nf {
        for c in p.faces.offsets[f]..p.faces.offsets[f + 1] {
            w.push(c);
        }
        w.end_row();
    }
    for e in 0..ne {
        if stopped_at(e, stop) {
            return None;
        }
        for &f in p.edge_faces.row(e) {
            let c = corner_of_edge(p, f, e as u32);
            w.push(c as u32);
            w.push(next_corner(p, f, c) as u32);
        }
        w.end_row();
    }
    Some(w.rows)
}

/// Child vertices' edges: a vertex child's are the halves of its parent's
/// edges at it, a face child's its interior edges, an edge child's its two
/// halves and the interior edge in each face of its edge.
fn child_vertex_edges(p: &Level, stop: &(dyn Fn() -> bool + Sync)) -> Option<Rows> {
    let (nv, nf, ne) = (p.num_vertices, p.faces.len(), p.edge_verts.len());
    let corners = p.faces.items.len();
    let mut w = RowWriter::with_capacity(
        nv + nf + ne,
        p.vertex_edges.items.len() + corners + 2 * ne + p.edge_faces.items.len(),
    );
    for v in 0..nv {
        if stopped_at(v, stop) {
            return None;
        }
        for &e in p.vertex_edges.row(v) {
            let [a, b] = p.edge_verts[e as usize];
            if a == v as u32 {
                w.push(2 * e);
            }
            if b == v as u32 {
                w.push(2 * e + 1);
            }
        }
        w.end_row();
    }
    for f in 0..nf {
        for c in p.faces.offsets[f]..p.faces.offsets[f + 1] {
            w.push((2 * ne) as u32 + c);
        }
        w.end_row();
    }
    for e in 0..ne {
        if stopped_at(e, stop) {
            return None;
        }
        w.push(2 * e as u32);
        w.push(2 * e as u32 + 1);
        for &f in p.edge_faces.row(e) {
            w.push((2 * ne + corner_of_edge(p, f, e as u32)) as u32);
        }
        w.end_row();
    }
    Some(w.rows)
}

/// The rules of every parent vertex and edge, from parent and child sharpness.
pub fn plan(p: &Level, c: &Level, chaikin_rule: bool) -> Plan {
    let nv = p.num_vertices;
    let per_vertex: Vec<(Rule, Rule, f32)> = (0..nv)
        .into_par_iter()
        .map(|v| {
            let edges = p.vertex_edges.row(v);
            let (pv, cv) = (p.vertex_sharpness[v], c.vertex_sharpness[v]);
            let child_of = |e: u32| {
                c.edge_sharpness
                    [(2 * e + u32::from(p.edge_verts[e as usize][0] != v as u32)) as usize]
            };
            // The common case: nothing sharp around the vertex.
            if !is_sharp(pv)
                && edges
                    .iter()
                    .all(|&e| !is_sharp(p.edge_sharpness[e as usize]))
            {
                return (Rule::Smooth, Rule::Smooth, 0.0);
            }
            let (mut parent_sharp, mut child_sharp) = (0, 0);
            // OpenSubdiv's ComputeFractionalWeightAtVertex.
            let (mut count, mut sum) = (0, 0.0f32);
            if is_sharp(pv) && !is_sharp(cv) {
                count += 1;
                sum += pv;
            }
            for &e in edges {
                let (a, b) = (p.edge_sharpness[e as usize], child_of(e));
                parent_sharp += usize::from(is_sharp(a));
                child_sharp += usize::from(is_sharp(b));
                if is_sharp(a) && !is_sharp(b) {
                    count += 1;
                    sum += a;
                }
            }
            let pr = Rule::of(pv, parent_sharp);
            let cr = Rule::of(cv, child_sharp);
            let w = if count == 0 {
                0.0
            } else {
                (sum / count as f32).min(1.0)
            };
            (pr, cr, w)
        })
        .collect();
    let edge_weight = (0..p.edge_verts.len())
        .into_par_iter()
        .map(|e| {
            let s = p.edge_sharpness[e];
            // A full crease at sharpness 1 or more, or (Chaikin) where both
            // child halves stay sharp; a transition blend below that.
            let full = s >= 1.0
                || (chaikin_rule
                    && is_sharp(c.edge_sharpness[2 * e])
                    && is_sharp(c.edge_sharpness[2 * e + 1]));
            if !is_sharp(s) {
                0.0
            } else if full {
                1.0
            } else {
                s
            }
        })
        .collect();
    Plan {
        parent_rule: per_vertex.iter().map(|x| x.0).collect(),
        child_rule: per_vertex.iter().map(|x| x.1).collect(),
        vertex_weight: per_vertex.iter().map(|x| x.2).collect(),
        edge_weight,
    }
}

/// Refines values of `dim` components per parent vertex into child values.
pub fn refine_values(p: &Level, c: &Level, plan: &Plan, src: &[f64], dim: usize) -> Vec<f64> {
    refine_values_cancellable(p, c, plan, src, dim, &|| false).expect("never cancelled")
}

/// [`refine_values`], polling `cancel` between grains of work: `None` once
/// it answers true.
pub fn refine_values_cancellable(
    p: &Level,
    c: &Level,
    plan: &Plan,
    src: &[f64],
    dim: usize,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Option<Vec<f64>> {
    // Fixed widths let the compiler keep a value in registers and drop the
    // bounds checks; positions (3) are the hot case.
    match dim {
        1 => refine_fixed::<1>(p, c, plan, src, cancel),
        2 => refine_fixed::<2>(p, c, plan, src, cancel),
        3 => refine_fixed::<3>(p, c, plan, src, cancel),
        4 => refine_fixed::<4>(p, c, plan, src, cancel),
        _ => {
            // Wider values: one component at a time.
            let n = src.len() / dim.max(1);
            let columns: Vec<Vec<f64>> = (0..dim)
                .map(|k| {
                    let column: Vec<f64> = (0..n).map(|i| src[i * dim + k]).collect();
                    refine_fixed::<1>(p, c, plan, &column, cancel)
                })
                .collect::<Option<_>>()?;
            let m = columns.first().map_or(0, Vec::len);
            Some((0..m * dim).map(|i| columns[i % dim][i / dim]).collect())
        }
    }
}

type Value<const N: usize> = [f64; N];

fn add<const N: usize>(o: &mut Value<N>, w: f64, x: &Value<N>) {
    for k in 0..N {
        o[k] += w * x[k];
    }
}

/// Elements per parallel task: enough to amortise the scheduling.
const GRAIN: usize = 2048;

/// Runs `each(index, value)` over `part` in parallel grains, stopping at the
/// first grain that finds `cancel` true.
fn for_each_grain<T: Send>(
    part: &mut [T],
    cancel: &(dyn Fn() -> bool + Sync),
    each: impl Fn(usize, &mut T) + Sync,
) -> Option<()> {
    part.par_chunks_mut(GRAIN)
        .enumerate()
        .try_for_each(|(grain, chunk)| {
            if cancel() {
                return None;
            }
            for (k, o) in chunk.iter_mut().enumerate() {
                each(grain * GRAIN + k, o);
            }
            Some(())
        })
}

fn refine_fixed<const N: usize>(
    p: &Level,
    c: &Level,
    plan: &Plan,
    src: &[f64],
    cancel: &(dyn Fn() -> bool + Sync),
) -> Option<Vec<f64>> {
    let (nv, nf, ne) = (p.num_vertices, p.faces.len(), p.edge_verts.len());
    let (src, _) = src.as_chunks::<N>();
    let mut out = vec![[0.0f64; N]; nv + nf + ne];
    let (vertex_part, rest) = out.split_at_mut(nv);
    let (face_part, edge_part) = rest.split_at_mut(nf);
    // Each output is summed in registers and stored once: a fresh zeroed
    // page read before it is written maps the shared zero page first, and
    // the write then costs a copy-on-write fault with a TLB shootdown on
    // every core (a quarter of the time at level 3 on the reference VM).
    for_each_grain(face_part, cancel, |f, o| {
        let verts = p.faces.row(f);
        let w = 1.0 / verts.len() as f64;
        let mut sum = [0.0; N];
        for &v in verts {
            add(&mut sum, w, &src[v as usize]);
        }
        *o = sum;
    })?;
    let face_points: &[Value<N>] = face_part;
    for_each_grain(edge_part, cancel, |e, o| {
        let [a, b] = p.edge_verts[e];
        let faces = p.edge_faces.row(e);
        let (end_w, face_w) = scheme::edge_point(plan.edge_weight[e] as f64, faces.len());
        let (x, y) = (&src[a as usize], &src[b as usize]);
        let mut sum = [0.0; N];
        for k in 0..N {
            sum[k] = end_w * (x[k] + y[k]);
        }
        if face_w > 0.0 {
            for &f in faces {
                add(&mut sum, face_w, &face_points[f as usize]);
            }
        }
        *o = sum;
    })?;
    for_each_grain(vertex_part, cancel, |v, o| {
        let edges = p.vertex_edges.row(v);
        let me = &src[v];
        if edges.is_empty() {
            *o = *me;
            return;
        }
        let mut sum = [0.0; N];
        let faces = p.vertex_faces.row(v);
        let parent_sharp = |k: usize| is_sharp(p.edge_sharpness[edges[k] as usize]);
        let child_sharp = |k: usize| {
            let e = edges[k];
            let half = 2 * e + u32::from(p.edge_verts[e as usize][0] != v as u32);
            is_sharp(c.edge_sharpness[half as usize])
        };
        scheme::blended_vertex_point(
            false,
            (
                plan.parent_rule[v],
                plan.child_rule[v],
                plan.vertex_weight[v] as f64,
            ),
            edges.len(),
            faces.len(),
            parent_sharp,
            child_sharp,
            &mut |t, w| match t {
                Term::Vertex => add(&mut sum, w, me),
                Term::EdgeEnd(k) => {
                    add(&mut sum, w, &src[p.other_end(edges[k], v as u32) as usize])
                }
                Term::FacePoint(k) => add(&mut sum, w, &face_points[faces[k] as usize]),
                Term::Opposite(_) => {}
            },
        );
        *o = sum;
    })?;
    Some(out.into_flattened())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chaikin_follows_opensubdiv() {
        // One semi-sharp edge at the vertex: plain decrement.
        assert_eq!(chaikin(2.5, &[2.5, 0.0, 0.0]), 1.5);
        // Two: 3/4 own + 1/4 the other's, minus one.
        assert!((chaikin(2.0, &[2.0, 4.0, 0.0]) - (0.75 * 2.0 + 0.25 * 4.0 - 1.0)).abs() < 1e-6);
        assert_eq!(chaikin(INFINITE, &[INFINITE, 2.0]), INFINITE);
        assert_eq!(chaikin(0.5, &[0.5, 0.5]), 0.0);
    }
}
