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
use super::fvar_step::{blocks, edge_corners, Step};
use super::level::{Level, INFINITE};
use super::refine::{Plan, Rule};
use super::scheme;

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

        let limits: Vec<(u32, Vec<f64>)> = (0..l.num_vertices)
            .into_par_iter()
            .flat_map_iter(|v| {
                let r = &r;
                (0..r.spans_of(v).len()).map(move |s| {
                    let mut out = vec![0.0; d];
                    r.vertex_value(v as u32, s, &[], &mut out);
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
        let continuous = Step { ch, p, c, plan }.continuous_edges();
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

    fn step(&self) -> Step<'a> {
        Step {
            ch: self.ch,
            p: self.p,
            c: self.c,
            plan: self.plan,
        }
    }

    /// Child values: each vertex's siblings (its spans' values, in vertex
    /// order), then each face's, then each edge's (one, or one per side
    /// where the edge is a region boundary).
    fn run(&self) -> FVarChannel {
        let (p, d, step) = (self.p, self.ch.dim, self.step());
        let layout = step.layout(&self.continuous, self.spans.len());
        let mut values = vec![0.0f64; layout.len() * d];
        let all_linear = self.mode == FVarLinear::All;
        let (front, face_values) =
            step.faces_and_edges(&self.continuous, &layout, all_linear, &mut values);
        let vertex_at = |v: usize| self.span_offsets[v] as usize * d;
        blocks(front, p.num_vertices, vertex_at).for_each(|(vertices, block)| {
            let base = vertex_at(vertices.start);
            for v in vertices {
                let run = &mut block[vertex_at(v) - base..vertex_at(v + 1) - base];
                for (s, o) in run.chunks_mut(d).enumerate() {
                    self.vertex_value(v as u32, s, face_values, o);
                }
            }
        });
        let corner_value = step.corners(&self.continuous, &layout, |corner| {
            let v = p.faces.items[corner] as usize;
            self.span_offsets[v] + self.corner_span[corner]
        });
        FVarChannel {
            dim: d,
            values,
            corner_value,
        }
    }

    fn spans_of(&self, v: usize) -> &[Span] {
        &self.spans[self.span_offsets[v] as usize..self.span_offsets[v + 1] as usize]
    }

    /// The child value of span `s` at vertex `v`.
    fn vertex_value(&self, v: u32, s: usize, face_values: &[f64], out: &mut [f64]) {
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
            // Inside one region (the vertex's one value): the vertex's own
            // rule on the values.
            self.step().vertex_rule(v, me, face_values, self.limit, out);
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
