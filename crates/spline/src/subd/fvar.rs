//! Face-varying values (uv and other per-corner data) refined with
//! OpenSubdiv's face-varying rules. Corners at one vertex with equal values
//! share a value; where they differ (a seam) or the mesh ends, the value's
//! region has a boundary. Inside a region values refine like points (the
//! vertex's own rule, creases included); on a region's boundary the
//! interpolation option decides: smooth boundary curves (a crease along
//! the boundary), pinned corners, junctions, darts and concave corners
//! (the "corners" family), every boundary value pinned (`Boundaries`), or
//! bilinear everywhere (`All`, OpenSubdiv's default).

use rayon::prelude::*;

use super::fvar_linear::refine_linear;
use super::level::{Level, INFINITE};
use super::refine::{child_slot, corner_of_edge, next_corner, Plan, Rule};
use super::scheme::{self, Term};

/// OpenSubdiv's `FVarLinearInterpolation`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FVarLinear {
    /// Smooth everywhere; region boundaries are smooth curves.
    None,
    /// Also pin a region's corners (a value on one face).
    CornersOnly,
    /// Also pin junctions of three or more regions.
    CornersPlus1,
    /// Also pin darts and concave corners.
    CornersPlus2,
    /// Pin every value on a region boundary; smooth inside.
    Boundaries,
    /// Bilinear everywhere.
    All,
}

impl FVarLinear {
    /// From OpenSubdiv's `facevaryinginterpolateboundary` tag value.
    pub fn from_tag(tag: i32) -> FVarLinear {
        match tag {
            0 => FVarLinear::None,
            1 => FVarLinear::CornersOnly,
            2 => FVarLinear::CornersPlus1,
            3 => FVarLinear::CornersPlus2,
            4 => FVarLinear::Boundaries,
            _ => FVarLinear::All,
        }
    }
}

/// A face-varying channel of one level: `dim` components per value and
/// the value of every face corner.
#[derive(Clone, Debug, PartialEq)]
pub struct FVarChannel {
    pub dim: usize,
    pub values: Vec<f64>,
    pub corner_value: Vec<u32>,
}

impl FVarChannel {
    /// Per-corner data (`dim` numbers per corner of `level`) as a channel:
    /// corners at one vertex with bit-identical data share a value.
    pub fn from_corners(level: &Level, data: &[f64], dim: usize) -> FVarChannel {
        let corners = level.faces.items.len();
        let mut corner_value = vec![u32::MAX; corners];
        let mut values = Vec::new();
        let mut at_vertex: Vec<Vec<(usize, u32)>> = vec![Vec::new(); level.num_vertices];
        let same = |a: usize, b: usize| {
            data[a * dim..(a + 1) * dim]
                .iter()
                .zip(&data[b * dim..(b + 1) * dim])
                .all(|(x, y)| x.to_bits() == y.to_bits())
        };
        for c in 0..corners {
            let v = level.faces.items[c] as usize;
            let found = at_vertex[v].iter().find(|&&(other, _)| same(c, other));
            corner_value[c] = match found {
                Some(&(_, id)) => id,
                None => {
                    let id = (values.len() / dim) as u32;
                    values.extend_from_slice(&data[c * dim..(c + 1) * dim]);
                    at_vertex[v].push((c, id));
                    id
                }
            };
        }
        FVarChannel {
            dim,
            values,
            corner_value,
        }
    }

    /// Each corner's data, `dim` numbers per corner.
    #[cfg(test)]
    pub fn corner_data(&self) -> Vec<f64> {
        let d = self.dim;
        self.corner_value
            .iter()
            .flat_map(|&v| {
                self.values[v as usize * d..(v as usize + 1) * d]
                    .iter()
                    .copied()
            })
            .collect()
    }

    fn value(&self, id: u32) -> &[f64] {
        &self.values[id as usize * self.dim..(id as usize + 1) * self.dim]
    }

    /// The channel pushed to the limit surface of the all-quad level `l`
    /// (the values at their limit by the same rules; corners keep their
    /// values' identities).
    pub fn limit(&self, l: &Level, mode: FVarLinear) -> FVarChannel {
        // The level's own rules (no transition: the limit has no child).
        let rules: Vec<Rule> = (0..l.num_vertices)
            .map(|v| {
                let sharp = l
                    .vertex_edges
                    .row(v)
                    .iter()
                    .filter(|&&e| super::level::is_sharp(l.edge_sharpness[e as usize]))
                    .count();
                Rule::of(l.vertex_sharpness[v], sharp)
            })
            .collect();
        let plan = Plan {
            parent_rule: rules.clone(),
            child_rule: rules,
            vertex_weight: vec![0.0; l.num_vertices],
            edge_weight: vec![0.0; l.edge_verts.len()],
        };
        let mut r = Refinement::new(self, l, l, &plan, mode);
        r.limit = true;
        let mut values = self.values.clone();
        let d = self.dim;
        let no_faces = |_: u32| -> &[f64] { &[] };
        let limits: Vec<(u32, Vec<f64>)> = (0..l.num_vertices)
            .into_par_iter()
            .flat_map_iter(|v| {
                let r = &r;
                (0..r.spans_of(v).len()).map(move |s| {
                    let mut out = vec![0.0; d];
                    r.vertex_value(v as u32, s, &no_faces, &mut out);
                    (r.spans_of(v)[s].value, out)
                })
            })
            .collect();
        for (id, x) in limits {
            values[id as usize * d..(id as usize + 1) * d].copy_from_slice(&x);
        }
        FVarChannel {
            dim: d,
            values,
            corner_value: self.corner_value.clone(),
        }
    }

    /// The channel on the child level `c` of `p`: linear boundaries (the
    /// default) and bilinear need no spans and take their own few passes.
    pub fn refine(&self, p: &Level, c: &Level, plan: &Plan, mode: FVarLinear) -> FVarChannel {
        match mode {
            FVarLinear::Boundaries => refine_linear(self, p, c, plan, false),
            FVarLinear::All => refine_linear(self, p, c, plan, true),
            _ => self.refine_by_spans(p, c, plan, mode),
        }
    }

    /// [`FVarChannel::refine`] by the span rules under any option (the
    /// tests hold the linear options' passes to them).
    pub fn refine_by_spans(
        &self,
        p: &Level,
        c: &Level,
        plan: &Plan,
        mode: FVarLinear,
    ) -> FVarChannel {
        Refinement::new(self, p, c, plan, mode).run()
    }
}

/// Whether each edge has one value at each end on every side (an interior
/// edge of one region): two faces that agree on both ends' values.
pub(super) fn continuous_edges(ch: &FVarChannel, p: &Level) -> Vec<bool> {
    (0..p.edge_verts.len())
        .into_par_iter()
        .with_min_len(1024)
        .map(|e| {
            let faces = p.edge_faces.row(e);
            if faces.len() != 2 {
                return false;
            }
            let ends = |f: u32| {
                let (a, b) = edge_corners(p, f, e as u32);
                let (va, vb) = (p.faces.items[a], p.faces.items[b]);
                let (xa, xb) = (ch.corner_value[a], ch.corner_value[b]);
                if va <= vb {
                    (xa, xb)
                } else {
                    (xb, xa)
                }
            };
            ends(faces[0]) == ends(faces[1])
        })
        .collect()
}

/// The corner of face `f` that starts edge `e`, and the next corner.
pub(super) fn edge_corners(p: &Level, f: u32, e: u32) -> (usize, usize) {
    let c = corner_of_edge(p, f, e);
    (c, next_corner(p, f, c))
}

/// The corners of face `f` at vertex `v`.
fn corners_at(p: &Level, f: u32, v: u32) -> impl Iterator<Item = usize> + '_ {
    (p.faces.offsets[f as usize] as usize..p.faces.offsets[f as usize + 1] as usize)
        .filter(move |&c| p.faces.items[c] == v)
}

/// A vertex's spans: one, or several with each corner's span.
enum Spans {
    One(Span),
    Many(Vec<Span>, Vec<(usize, u32)>),
}

/// The faces around a vertex that hold one value there.
struct Span {
    value: u32,
    faces: Vec<u32>,
    corners: usize,
    /// Runs of those faces joined across continuous edges (more than one:
    /// the value's faces touch only at the vertex).
    runs: usize,
    /// Infinitely sharp edges inside the span.
    inf_sharp_edges: usize,
    /// Every face at the vertex (then `faces` is left empty): the common
    /// case, built without allocating.
    whole: bool,
}

struct Refinement<'a> {
    ch: &'a FVarChannel,
    p: &'a Level,
    c: &'a Level,
    plan: &'a Plan,
    /// Limit masks instead of refinement masks (the level is its own child).
    limit: bool,
    mode: FVarLinear,
    /// The values at each vertex (its siblings) with their faces.
    spans: Vec<Span>,
    /// Where each vertex's spans start in `spans` (one more than vertices).
    span_offsets: Vec<u32>,
    /// Each parent corner's span (an index into its vertex's spans).
    corner_span: Vec<u32>,
    /// Whether each edge has one value at each end on every side (an
    /// interior edge of one region).
    continuous: Vec<bool>,
}

impl<'a> Refinement<'a> {
    fn new(
        ch: &'a FVarChannel,
        p: &'a Level,
        c: &'a Level,
        plan: &'a Plan,
        mode: FVarLinear,
    ) -> Self {
        let continuous = continuous_edges(ch, p);
        let per_vertex: Vec<_> = (0..p.num_vertices)
            .into_par_iter()
            .map(|v| spans_at(ch, p, &continuous, v as u32))
            .collect();
        let mut corner_span = vec![0u32; p.faces.items.len()];
        let mut spans = Vec::with_capacity(p.num_vertices);
        let mut span_offsets = Vec::with_capacity(p.num_vertices + 1);
        for found in per_vertex {
            span_offsets.push(spans.len() as u32);
            match found {
                Spans::One(span) => spans.push(span),
                Spans::Many(many, assigned) => {
                    for (c, k) in assigned {
                        corner_span[c] = k;
                    }
                    spans.extend(many);
                }
            }
        }
        span_offsets.push(spans.len() as u32);
        Refinement {
            ch,
            p,
            c,
            plan,
            mode,
            limit: false,
            spans,
            span_offsets,
            corner_span,
            continuous,
        }
    }

    fn run(&self) -> FVarChannel {
        let (p, d) = (self.p, self.ch.dim);
        let nf = p.faces.len();
        // Child values: each vertex's siblings, each face, each edge (one,
        // or one per side where the edge is a region boundary).
        let mut vertex_base = Vec::with_capacity(p.num_vertices + 1);
        let mut n = 0u32;
        for v in 0..p.num_vertices {
            vertex_base.push(n);
            n += self.spans_of(v).len() as u32;
        }
        let face_base = n;
        n += nf as u32;
        let mut edge_base = Vec::with_capacity(p.edge_verts.len());
        for e in 0..p.edge_verts.len() {
            edge_base.push(n);
            n += if self.continuous[e] {
                1
            } else {
                p.edge_faces.row(e).len().max(1) as u32
            };
        }
        let mut values = vec![0.0f64; n as usize * d];
        let (front, face_and_edge) = values.split_at_mut(face_base as usize * d);
        let (face_values, edge_part) = face_and_edge.split_at_mut(nf * d);
        face_values
            .par_chunks_mut(d)
            .enumerate()
            .with_min_len(1024)
            .for_each(|(f, out)| {
                let r = p.faces.offsets[f] as usize..p.faces.offsets[f + 1] as usize;
                let w = 1.0 / r.len() as f64;
                out.iter_mut().for_each(|x| *x = 0.0);
                for c in r {
                    let x = self.ch.value(self.ch.corner_value[c]);
                    (0..d).for_each(|k| out[k] += x[k] * w);
                }
            });
        let face_values = &*face_values;
        let face_value = |f: u32| &face_values[f as usize * d..(f as usize + 1) * d];
        // Edges (one value, or one per side), then vertices (one per value
        // at the vertex), each computed apart in parallel.
        let ne = edge_base.len();
        let start = edge_base.first().copied().unwrap_or(n);
        let edge_at = |e: usize| (edge_base.get(e).copied().unwrap_or(n) - start) as usize * d;
        blocks(edge_part, ne, edge_at).for_each(|(edges, block)| {
            let base = edge_at(edges.start);
            for e in edges {
                let run = &mut block[edge_at(e) - base..edge_at(e + 1) - base];
                self.edge_values(e, &face_value, run);
            }
        });

        // Vertex values sit in vertex order at the front: fill them in
        // place, a vertex's run at a time.
        let vertex_at = |v: usize| self.span_offsets[v] as usize * d;
        blocks(front, p.num_vertices, vertex_at).for_each(|(vertices, block)| {
            let base = vertex_at(vertices.start);
            for v in vertices {
                let run = &mut block[vertex_at(v) - base..vertex_at(v + 1) - base];
                for (s, o) in run.chunks_mut(d).enumerate() {
                    self.vertex_value(v as u32, s, &face_value, o);
                }
            }
        });
        // Child corners: a quad per parent corner (vertex, next edge, face,
        // previous edge), as the child topology.
        let mut corner_value = vec![0u32; 4 * p.faces.items.len()];
        let corner_at = |f: usize| 4 * p.faces.offsets[f] as usize;
        blocks(&mut corner_value, nf, corner_at).for_each(|(faces, block)| {
            let base = corner_at(faces.start);
            for f in faces {
                let run = &mut block[corner_at(f) - base..corner_at(f + 1) - base];
                let (start, end) = (p.faces.offsets[f] as usize, p.faces.offsets[f + 1] as usize);
                for (corner, quad) in (start..end).zip(run.chunks_mut(4)) {
                    let prev = if corner == start { end - 1 } else { corner - 1 };
                    let v = p.faces.items[corner] as usize;
                    let s = self.corner_span[corner];
                    let side = |e: u32| {
                        let base = edge_base[e as usize];
                        if self.continuous[e as usize] {
                            base
                        } else {
                            let faces = p.edge_faces.row(e as usize);
                            base + faces.iter().position(|&x| x == f as u32).unwrap_or(0) as u32
                        }
                    };
                    let items = [
                        vertex_base[v] + s,
                        side(p.face_edges[corner]),
                        face_base + f as u32,
                        side(p.face_edges[prev]),
                    ];
                    for (i, item) in items.into_iter().enumerate() {
                        quad[child_slot(end - start, corner - start, i)] = item;
                    }
                }
            }
        });
        debug_assert_eq!(corner_value.len(), self.c.faces.items.len());
        FVarChannel {
            dim: d,
            values,
            corner_value,
        }
    }

    fn spans_of(&self, v: usize) -> &[Span] {
        &self.spans[self.span_offsets[v] as usize..self.span_offsets[v + 1] as usize]
    }

    /// The child values of edge `e`: one where it is continuous, else one
    /// per side (the midpoint of that face's ends).
    fn edge_values(
        &self,
        e: usize,
        face_value: &(dyn Fn(u32) -> &'a [f64] + Sync),
        out: &mut [f64],
    ) {
        let (p, d) = (self.p, self.ch.dim);
        let faces = p.edge_faces.row(e);
        let ends = |f: u32| {
            let (a, b) = edge_corners(p, f, e as u32);
            (
                self.ch.value(self.ch.corner_value[a]),
                self.ch.value(self.ch.corner_value[b]),
            )
        };
        if self.continuous[e] && self.mode != FVarLinear::All {
            let (xa, xb) = ends(faces[0]);
            let (end_w, face_w) = scheme::edge_point(self.plan.edge_weight[e] as f64, faces.len());
            for (k, o) in out.iter_mut().enumerate() {
                *o = end_w * (xa[k] + xb[k])
                    + faces
                        .iter()
                        .map(|&f| face_w * face_value(f)[k])
                        .sum::<f64>();
            }
        } else {
            // Midpoints, one per side (a continuous edge under `All` gives
            // the same midpoint from either side).
            let sides = if self.continuous[e] {
                &faces[..1]
            } else {
                faces
            };
            for (&f, o) in sides.iter().zip(out.chunks_mut(d)) {
                let (xa, xb) = ends(f);
                for k in 0..d {
                    o[k] = 0.5 * (xa[k] + xb[k]);
                }
            }
        }
    }

    /// The child value of span `s` at vertex `v`.
    fn vertex_value(
        &self,
        v: u32,
        s: usize,
        face_value: &(dyn Fn(u32) -> &'a [f64] + Sync),
        out: &mut [f64],
    ) where
        Self: 'a,
    {
        let (p, d) = (self.p, self.ch.dim);
        let span = &self.spans_of(v as usize)[s];
        let me = self.ch.value(span.value);
        let edges = p.vertex_edges.row(v as usize);
        if self.mode == FVarLinear::All || edges.is_empty() {
            out.copy_from_slice(me);
            return;
        }
        let region: &[u32] = if span.whole {
            p.vertex_faces.row(v as usize)
        } else {
            &span.faces
        };
        // The value at the far end of edge e, seen from a face of the region.
        let far = |e: u32| -> Option<&[f64]> {
            let faces = p.edge_faces.row(e as usize);
            // Every face at the vertex is in a whole span's region.
            let f = if span.whole {
                faces.first().copied()
            } else {
                faces.iter().copied().find(|&f| region.contains(&f))
            }?;
            let (a, b) = edge_corners(p, f, e);
            let other = if p.faces.items[a] == v { b } else { a };
            Some(self.ch.value(self.ch.corner_value[other]))
        };
        // The region's boundary, side by side: a seam edge whose two faces
        // both hold this value bounds the region twice (it wraps round and
        // meets itself), a mesh boundary edge once.
        let boundary: Vec<(u32, u32)> = edges
            .iter()
            .filter(|&&e| !self.continuous[e as usize])
            .flat_map(|&e| {
                p.edge_faces
                    .row(e as usize)
                    .iter()
                    .filter(|f| region.contains(f))
                    .map(move |&f| (e, f))
            })
            .collect();
        let far_side = |(e, f): (u32, u32)| {
            let (a, b) = edge_corners(p, f, e);
            let other = if p.faces.items[a] == v { b } else { a };
            self.ch.value(self.ch.corner_value[other])
        };
        let (pr, cr, w) = (
            self.plan.parent_rule[v as usize],
            self.plan.child_rule[v as usize],
            self.plan.vertex_weight[v as usize] as f64,
        );
        // Mismatched (OpenSubdiv's term): a seam at the vertex, or a mesh
        // boundary the option makes linear, or a mesh corner it pins.
        let spans = self.spans_of(v as usize);
        let vertex_boundary = edges
            .iter()
            .any(|&e| p.edge_faces.row(e as usize).len() < 2);
        let seam = spans.len() > 1
            || edges
                .iter()
                .any(|&e| !self.continuous[e as usize] && p.edge_faces.row(e as usize).len() >= 2);
        let linear_boundaries = matches!(self.mode, FVarLinear::Boundaries | FVarLinear::All);
        let mismatch = seam
            || (vertex_boundary && linear_boundaries)
            || (vertex_boundary
                && p.vertex_faces.row(v as usize).len() == 1
                && self.mode != FVarLinear::None);
        if !mismatch {
            // Inside one region: the vertex's own rule on the values.
            let faces = p.vertex_faces.row(v as usize);
            out.iter_mut().for_each(|x| *x = 0.0);
            let mut emit = |t: Term, wt: f64| {
                let x: Option<&[f64]> = match t {
                    Term::Vertex => Some(me),
                    Term::EdgeEnd(k) => far(edges[k]),
                    Term::FacePoint(k) => Some(face_value(faces[k])),
                    Term::Opposite(k) => {
                        let f = faces[k] as usize;
                        let r = p.faces.offsets[f] as usize..p.faces.offsets[f + 1] as usize;
                        let len = r.len();
                        r.clone().find(|&c| p.faces.items[c] == v).map(|c| {
                            let opposite = r.start + (c - r.start + len / 2) % len;
                            self.ch.value(self.ch.corner_value[opposite])
                        })
                    }
                };
                if let Some(x) = x {
                    (0..d).for_each(|k| out[k] += wt * x[k]);
                }
            };
            let parent_sharp =
                |k: usize| super::level::is_sharp(p.edge_sharpness[edges[k] as usize]);
            let child_sharp = |k: usize| {
                let e = edges[k];
                let half = 2 * e + u32::from(p.edge_verts[e as usize][0] != v);
                super::level::is_sharp(self.c.edge_sharpness[half as usize])
            };
            let (n_e, n_f) = (edges.len(), faces.len());
            let rules = (pr, cr, w);
            scheme::blended_vertex_point(
                self.limit,
                rules,
                n_e,
                n_f,
                parent_sharp,
                child_sharp,
                &mut emit,
            );
            return;
        }
        // On a region's boundary: pinned, or a smooth curve, by
        // OpenSubdiv's tagging of mismatched values.
        let dependent = matches!(
            self.mode,
            FVarLinear::CornersPlus1 | FVarLinear::CornersPlus2
        );
        let corners_sharp = self.mode != FVarLinear::None;
        let sharpen_darts = self.mode == FVarLinear::CornersPlus2;
        let non_manifold = edges
            .iter()
            .any(|&e| p.edge_faces.row(e as usize).len() > 2);
        let mut all_sharp = linear_boundaries
            || non_manifold
            || p.vertex_sharpness[v as usize] >= INFINITE
            || (dependent && spans.len() > 2)
            || (sharpen_darts && spans.len() == 1 && !vertex_boundary);
        if !all_sharp && dependent && spans.len() == 2 {
            all_sharp = spans.iter().any(|x| x.inf_sharp_edges > 0 || x.runs > 1)
                || (sharpen_darts && spans.iter().any(|x| x.corners == 1));
        }
        let pinned = all_sharp
            || span.runs > 1
            || span.inf_sharp_edges > 0
            || (span.corners == 1 && corners_sharp)
            || boundary.len() != 2;
        if pinned {
            out.copy_from_slice(me);
            return;
        }
        // A smooth boundary curve: the crease rule along the region's two
        // boundary edges.
        let (a, b) = (far_side(boundary[0]), far_side(boundary[1]));
        let (own, end) = scheme::crease(self.limit);
        for k in 0..d {
            out[k] = own * me[k] + end * (a[k] + b[k]);
        }
    }
}

/// The spans at vertex `v`, each corner at `v` numbered by its span in
/// `corner_span`: corners are joined across the continuous edges at `v`.
fn spans_at(ch: &FVarChannel, p: &Level, continuous: &[bool], v: u32) -> Spans {
    // The common case: one value all round and every edge continuous.
    let faces = p.vertex_faces.row(v as usize);
    let edges = p.vertex_edges.row(v as usize);
    if let Some(&f0) = faces.first() {
        let value = corners_at(p, f0, v).next().map(|c| ch.corner_value[c]);
        let single = faces
            .iter()
            .all(|&f| corners_at(p, f, v).all(|c| Some(ch.corner_value[c]) == value));
        if single && edges.iter().all(|&e| continuous[e as usize]) {
            let inf_sharp_edges = edges
                .iter()
                .filter(|&&e| p.edge_sharpness[e as usize] >= INFINITE)
                .count();
            let span = Span {
                value: value.unwrap_or(0),
                faces: Vec::new(),
                corners: faces.len(),
                runs: 1,
                inf_sharp_edges,
                whole: true,
            };
            return Spans::One(span);
        }
    }
    let corners: Vec<(usize, u32)> = p
        .vertex_faces
        .row(v as usize)
        .iter()
        .flat_map(|&f| corners_at(p, f, v).map(move |c| (c, f)))
        .collect();
    // Union-find over the corners at v, lowest index as root.
    let mut parent: Vec<usize> = (0..corners.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let local = |f: u32, e: u32| {
        let (a, b) = edge_corners(p, f, e);
        let at = if p.faces.items[a] == v { a } else { b };
        corners.iter().position(|&(c, _)| c == at)
    };
    for &e in p.vertex_edges.row(v as usize) {
        if !continuous[e as usize] {
            continue;
        }
        let faces = p.edge_faces.row(e as usize);
        if let (Some(a), Some(b)) = (local(faces[0], e), local(faces[1], e)) {
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            parent[ra.max(rb)] = ra.min(rb);
        }
    }
    let mut spans: Vec<Span> = Vec::new();
    let mut counted_roots: Vec<(u32, usize)> = Vec::new();
    let mut span_of = vec![0u32; corners.len()];
    for (i, &(c, f)) in corners.iter().enumerate() {
        let value = ch.corner_value[c];
        let k = match spans.iter().position(|s| s.value == value) {
            Some(k) => k,
            None => {
                spans.push(Span {
                    value,
                    faces: Vec::new(),
                    corners: 0,
                    runs: 0,
                    inf_sharp_edges: 0,
                    whole: false,
                });
                spans.len() - 1
            }
        };
        let r = root(&mut parent, i);
        if !counted_roots.contains(&(value, r)) {
            counted_roots.push((value, r));
            spans[k].runs += 1;
        }
        if !spans[k].faces.contains(&f) {
            spans[k].faces.push(f);
        }
        spans[k].corners += 1;
        span_of[i] = k as u32;
    }
    for &e in p.vertex_edges.row(v as usize) {
        if continuous[e as usize] && p.edge_sharpness[e as usize] >= INFINITE {
            let f = p.edge_faces.row(e as usize)[0];
            if let Some(k) = local(f, e).map(|i| span_of[i] as usize) {
                spans[k].inf_sharp_edges += 1;
            }
        }
    }
    let assigned = corners.iter().map(|&(c, _)| c).zip(span_of).collect();
    Spans::Many(spans, assigned)
}

/// Items per parallel block of [`blocks`].
const BLOCK: usize = 1024;

/// `out` cut into one piece per block of `BLOCK` items, item `i`'s output
/// starting at `at(i)` (ascending, `at(n)` the end), for the blocks to
/// fill in parallel: items with outputs of different sizes, placed without
/// a serial pass over every item.
pub(super) fn blocks<T: Send>(
    out: &mut [T],
    n: usize,
    at: impl Fn(usize) -> usize,
) -> impl ParallelIterator<Item = (std::ops::Range<usize>, &mut [T])> {
    let mut pieces = Vec::with_capacity(n.div_ceil(BLOCK));
    let mut rest = out;
    for first in (0..n).step_by(BLOCK) {
        let last = (first + BLOCK).min(n);
        let (piece, tail) = rest.split_at_mut(at(last) - at(first));
        pieces.push((first..last, piece));
        rest = tail;
    }
    pieces.into_par_iter()
}
