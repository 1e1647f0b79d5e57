//! The passes of reduction by half-edge collapses: every edge's quadric
//! cost in parallel, then in cost order a set of collapses each checked on
//! what no earlier one changes, then their samples measured in one batch.
//! The order is total (cost bucket, then the order edges were found), so
//! the result does not depend on threads.

use glam::Vec3;
use rayon::prelude::*;

use super::closest::closest_on_triangle;
use super::quadric::Quadric;
use super::reduce::{Deviation, ReduceOptions, Reduced};
use super::thickness::Cancelled;

/// How far from the plane of two of a vertex's face normals a third must
/// reach (the volume they span) for the vertex to count as a corner.
const CORNER_SPAN: f32 = 0.3;

/// Vertex-to-triangle incidence, compressed.
struct Incidence {
    offsets: Vec<u32>,
    faces: Vec<u32>,
}

impl Incidence {
    fn build(vertices: usize, tris: &[[u32; 3]]) -> Incidence {
        let mut offsets = vec![0u32; vertices + 1];
        for t in tris {
            for &v in t {
                offsets[v as usize + 1] += 1;
            }
        }
        for i in 0..vertices {
            offsets[i + 1] += offsets[i];
        }
        let mut fill = offsets.clone();
        let mut faces = vec![0u32; offsets[vertices] as usize];
        for (f, t) in tris.iter().enumerate() {
            for &v in t {
                faces[fill[v as usize] as usize] = f as u32;
                fill[v as usize] += 1;
            }
        }
        Incidence { offsets, faces }
    }

    fn of(&self, v: u32) -> &[u32] {
        &self.faces[self.offsets[v as usize] as usize..self.offsets[v as usize + 1] as usize]
    }
}

/// The mesh being reduced and what each pass reads.
struct State<'a> {
    positions: &'a [Vec3],
    tris: Vec<[u32; 3]>,
    quadrics: Vec<Quadric>,
    /// Each vertex's quadric at its own position: the part of a collapse's
    /// cost the vertex it ends on brings, the same for all its collapses.
    own_error: Vec<f64>,
    /// Vertices whose fan is not one closed disc (a boundary, a pinch): never moved.
    pinned: Vec<bool>,
    /// Vertices no collapse may end on (a part's cut, see `Frozen`).
    frozen: Option<&'a [bool]>,
    /// Directed collapses the measure refused, sorted.
    refused: Vec<u64>,
    /// Vertices that start a refused collapse (the others skip the search).
    refused_from: Vec<bool>,
    /// Vertices whose neighbourhood the last pass's chosen collapses
    /// changed, and the ends of collapses it put off: only edges of
    /// triangles around them can have become collapsible (a collapse's
    /// checks read only its ends' rings, the moved fan and the degree of the
    /// vertices opposite its edge, which can only fall); `None` before the
    /// first pass.
    touched: Option<Vec<bool>>,
}

fn key(from: u32, to: u32) -> u64 {
    (from as u64) << 32 | to as u64
}

/// A collapse of `from` onto `to` and its quadric cost.
#[derive(Clone, Copy, Debug)]
struct Collapse {
    cost: f64,
    from: u32,
    to: u32,
}

/// Triangles a pass's parallel phases give one task (below it, waking
/// threads costs more than the work).
const SERIAL_TRIANGLES: usize = 8192;

/// Triangles below which reduction runs until no collapse is left.
const STALL_FROM: usize = 8192;

/// Cost buckets of the ordering: candidates are ordered by their cost
/// rounded to 1/1024 of the bound (as meshoptimizer does), in the order
/// they were found within a bucket, in one counting pass.
const COST_BUCKETS: usize = 1024;

fn by_cost(candidates: Vec<Collapse>, bound: f64) -> Vec<Collapse> {
    let bucket = |c: &Collapse| {
        if bound > 0.0 {
            ((c.cost / bound * COST_BUCKETS as f64) as usize).min(COST_BUCKETS - 1)
        } else {
            0
        }
    };
    let mut starts = vec![0usize; COST_BUCKETS + 1];
    for c in &candidates {
        starts[bucket(c) + 1] += 1;
    }
    for i in 0..COST_BUCKETS {
        starts[i + 1] += starts[i];
    }
    let mut sorted = vec![
        Collapse {
            cost: 0.0,
            from: 0,
            to: 0
        };
        candidates.len()
    ];
    for c in candidates {
        let b = bucket(&c);
        sorted[starts[b]] = c;
        starts[b] += 1;
    }
    sorted
}

/// Each vertex's quadric: the planes of the triangles around it.
fn initial_quadrics(positions: &[Vec3], tris: &[[u32; 3]], incidence: &Incidence) -> Vec<Quadric> {
    let planes: Vec<Quadric> = tris
        .par_iter()
        .map(|t| Quadric::of_triangle(t.map(|v| positions[v as usize])))
        .collect();
    (0..positions.len() as u32)
        .into_par_iter()
        .map(|v| {
            let mut q = Quadric::default();
            for &f in incidence.of(v) {
                q.add(&planes[f as usize]);
            }
            q
        })
        .collect()
}

/// Whether the triangles around `v` form one closed fan: each neighbour
/// leads exactly one triangle's arm and ends exactly one, and stepping from
/// triangle to triangle across shared edges visits them all in one cycle.
fn is_closed_disc(v: u32, incidence: &Incidence, tris: &[[u32; 3]]) -> bool {
    let faces = incidence.of(v);
    if faces.len() < 3 {
        return faces.is_empty();
    }
    // Read off the triangles in place (a fan is a handful of them; a
    // vector per vertex was 60% of a reduction's allocations).
    let arms = || faces.iter().map(|&f| arm(tris[f as usize], v));
    let once = |pick: fn(&(u32, u32)) -> u32, x: u32| arms().filter(|a| pick(a) == x).count() == 1;
    if !arms().all(|a| once(|b| b.0, a.0) && once(|b| b.1, a.1)) {
        return false;
    }
    let first = arm(tris[faces[0] as usize], v);
    let mut at = first;
    for step in 1..=faces.len() {
        match arms().find(|b| b.0 == at.1) {
            Some(next) => at = next,
            None => return false,
        }
        if at == first {
            return step == faces.len();
        }
    }
    false
}

/// (The corner after `v`, the corner before it) in triangle `t`.
fn arm(t: [u32; 3], v: u32) -> (u32, u32) {
    let i = t.iter().position(|&c| c == v).unwrap_or(0);
    (t[(i + 1) % 3], t[(i + 2) % 3])
}

/// The distinct vertices sharing a triangle with `v`. Around a closed disc
/// (every unpinned vertex: collapses keep fans closed discs) each
/// neighbour follows `v` in exactly one triangle, so the corners after `v`
/// are the ring; elsewhere, every corner once.
fn ring(v: u32, closed: bool, incidence: &Incidence, tris: &[[u32; 3]], out: &mut Vec<u32>) {
    out.clear();
    if closed {
        out.extend(incidence.of(v).iter().map(|&f| arm(tris[f as usize], v).0));
        return;
    }
    for &f in incidence.of(v) {
        for c in tris[f as usize] {
            if c != v && !out.contains(&c) {
                out.push(c);
            }
        }
    }
}

/// The two vertices opposite the edge, if collapsing it keeps a closed
/// manifold: the link condition (the ends share exactly those two
/// neighbours) and no vertex left with fewer than three neighbours (which
/// would fold a tetrahedron into a double triangle).
fn keeps_manifold(ring_from: &[u32], ring_to: &[u32], incidence: &Incidence) -> Option<[u32; 2]> {
    let mut common = ring_from.iter().copied().filter(|w| ring_to.contains(w));
    let opposite = [common.next()?, common.next()?];
    let ok = common.next().is_none()
        && ring_from.len() + ring_to.len() >= 7
        && opposite.iter().all(|&w| incidence.of(w).len() >= 4);
    ok.then_some(opposite)
}

impl<'a> State<'a> {
    /// The state before any collapse: each vertex's quadric from its
    /// triangles, vertices whose fan is not one closed disc pinned.
    fn new(positions: &'a [Vec3], triangles: &[[u32; 3]]) -> State<'a> {
        let tris = triangles.to_vec();
        let incidence = Incidence::build(positions.len(), &tris);
        let quadrics = initial_quadrics(positions, &tris, &incidence);
        State {
            positions,
            own_error: (quadrics.par_iter().zip(positions))
                .map(|(q, &p)| q.sum_at(p))
                .collect(),
            quadrics,
            pinned: (0..positions.len() as u32)
                .into_par_iter()
                .map(|v| !is_closed_disc(v, &incidence, &tris))
                .collect(),
            tris,
            refused: Vec::new(),
            refused_from: vec![false; positions.len()],
            frozen: None,
            touched: None,
        }
    }

    /// `v`'s ring (see [`ring`]), read as a closed disc unless `v` is pinned.
    fn ring(&self, v: u32, incidence: &Incidence, out: &mut Vec<u32>) {
        ring(v, !self.pinned[v as usize], incidence, &self.tris, out);
    }

    /// Each edge worth trying with its cheaper allowed direction, when its
    /// quadric cost is within `bound`. Worth trying: every edge on the first
    /// pass, then those of triangles with a touched corner. Each edge is
    /// taken once, from the triangle where it runs upwards (a closed mesh
    /// holds it once in each direction).
    fn candidates(&self, bound: f64) -> Vec<Collapse> {
        let hot = |t: &[u32; 3]| match &self.touched {
            None => true,
            Some(touched) => t.iter().any(|&v| touched[v as usize]),
        };
        let cost = |from: u32, to: u32| -> Option<Collapse> {
            let from_index = from as usize;
            if self.pinned[from_index]
                || (self.refused_from[from_index]
                    && self.refused.binary_search(&key(from, to)).is_ok())
            {
                return None;
            }
            let (q, to_index) = (&self.quadrics, to as usize);
            let (at, own) = (self.positions[to_index], self.own_error[to_index]);
            let cost = q[from_index].mean_with_sum(&q[to_index], at, own);
            (cost <= bound).then_some(Collapse { cost, from, to })
        };
        let of_triangle = |t: &[u32; 3], out: &mut Vec<Collapse>| {
            if !hot(t) {
                return;
            }
            for i in 0..3 {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                if a > b {
                    continue;
                }
                let best = match (cost(a, b), cost(b, a)) {
                    (Some(x), Some(y)) => Some(if y.cost < x.cost { y } else { x }),
                    (x, y) => x.or(y),
                };
                out.extend(best);
            }
        };
        self.tris
            .par_chunks(SERIAL_TRIANGLES)
            .map(|chunk| {
                let mut out = Vec::new();
                for t in chunk {
                    of_triangle(t, &mut out);
                }
                out
            })
            .collect::<Vec<_>>()
            .concat()
    }

    /// In cost order, the collapses that keep the mesh a closed manifold and
    /// fold nothing, each checked on what no earlier one changes, so any
    /// subset of them may be made at once. A collapse of `u` onto `v`
    /// changes the neighbours of `u`, `v` and `u`'s ring (none of them may
    /// end a later collapse) and drops the degree of the two vertices
    /// opposite its edge (none of them may be opposite a later one's).
    fn independent(
        &mut self,
        candidates: &[Collapse],
        incidence: &Incidence,
        min_normal_cos: f32,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<Vec<Collapse>, Cancelled> {
        let mut changed = vec![false; self.positions.len()];
        let mut hot = vec![false; self.positions.len()];
        let mut thinned = vec![false; self.positions.len()];
        let mut chosen = Vec::new();
        let (mut ring_from, mut ring_to) = (Vec::new(), Vec::new());
        for (i, c) in candidates.iter().enumerate() {
            if i % 65536 == 65535 && cancel() {
                return Err(Cancelled);
            }
            if changed[c.from as usize] || changed[c.to as usize] {
                continue;
            }
            self.ring(c.from, incidence, &mut ring_from);
            self.ring(c.to, incidence, &mut ring_to);
            let Some(opposite) = keeps_manifold(&ring_from, &ring_to, incidence) else {
                continue;
            };
            if opposite.iter().any(|&w| thinned[w as usize]) {
                // Put off: tried again next pass.
                hot[c.from as usize] = true;
                hot[c.to as usize] = true;
                continue;
            }
            if self.folds(c, incidence, min_normal_cos) {
                continue;
            }
            for &w in ring_from.iter().chain([&c.from, &c.to]) {
                changed[w as usize] = true;
                hot[w as usize] = true;
            }
            for w in opposite {
                thinned[w as usize] = true;
            }
            chosen.push(*c);
        }
        self.touched = Some(hot);
        Ok(chosen)
    }

    /// Whether moving `from` onto `to` turns any of `from`'s other triangles
    /// past the allowed angle or makes it degenerate.
    fn folds(&self, c: &Collapse, incidence: &Incidence, min_normal_cos: f32) -> bool {
        let p = |v: u32| self.positions[v as usize];
        incidence.of(c.from).iter().any(|&f| {
            let t = self.tris[f as usize];
            if t.contains(&c.to) {
                return false;
            }
            let moved = t.map(|v| if v == c.from { c.to } else { v });
            let before = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
            let after = (p(moved[1]) - p(moved[0])).cross(p(moved[2]) - p(moved[0]));
            let scale = before.length() * after.length();
            !(scale > 0.0 && before.dot(after) >= min_normal_cos * scale)
        })
    }

    /// For each chosen collapse, whether the measure finds all its samples
    /// (the moved triangles' centroids and the new edges' midpoints) within
    /// `tolerance`, and, where it moves a corner, the moved triangles still
    /// pass within `tolerance` of it (see [`State::covers`]). A collapse
    /// inside a plane (every triangle around the moved vertex in one plane,
    /// to a thousandth of the tolerance) covers the same part of that plane
    /// as before, so it is not measured.
    fn measure(
        &self,
        chosen: &[Collapse],
        incidence: &Incidence,
        tolerance: f64,
        deviation: Deviation,
    ) -> Vec<bool> {
        let p = |v: u32| self.positions[v as usize];
        let mut points = Vec::new();
        let mut ends = Vec::with_capacity(chosen.len());
        let flat = tolerance * 1e-3;
        let mut stays_covered = Vec::with_capacity(chosen.len());
        for c in chosen {
            if self.is_flat_fan(c.from, incidence, flat) {
                ends.push(points.len());
                stays_covered.push(true);
                continue;
            }
            stays_covered
                .push(!self.is_corner(c.from, incidence) || self.covers(c, incidence, tolerance));
            for &f in incidence.of(c.from) {
                let t = self.tris[f as usize];
                if t.contains(&c.to) {
                    continue;
                }
                let moved = t.map(|v| if v == c.from { c.to } else { v });
                points.push((p(moved[0]) + p(moved[1]) + p(moved[2])) / 3.0);
                // The edge from `to` to the corner after it is new (the one
                // before it belongs to the neighbouring moved triangle).
                let i = moved.iter().position(|&v| v == c.to).unwrap_or(0);
                points.push(0.5 * (p(c.to) + p(moved[(i + 1) % 3])));
            }
            ends.push(points.len());
        }
        let mut distances = vec![0.0f32; points.len()];
        deviation(&points, &mut distances);
        let mut start = 0;
        ends.iter()
            .zip(stays_covered)
            .map(|(&end, covered)| {
                let ok = distances[start..end]
                    .iter()
                    .all(|d| (d.abs() as f64) <= tolerance);
                start = end;
                ok && covered
            })
            .collect()
    }

    /// Whether the moved triangles of collapse `c` pass within `tolerance`
    /// of the vertex it removes: the field measures only the triangles'
    /// side, which cannot see a corner sliding along an edge towards a
    /// nearer vertex (the surface's corner would be lost).
    fn covers(&self, c: &Collapse, incidence: &Incidence, tolerance: f64) -> bool {
        let p = |v: u32| self.positions[v as usize];
        let gone = p(c.from);
        incidence
            .of(c.from)
            .iter()
            .map(|&f| self.tris[f as usize])
            .filter(|t| !t.contains(&c.to))
            .any(|t| {
                let moved = t.map(|v| p(if v == c.from { c.to } else { v }));
                closest_on_triangle(&moved, gone).0.distance(gone) as f64 <= tolerance
            })
    }

    /// Whether `v` is a corner: the normals of its triangles span space
    /// (three of them far from coplanar), as where three faces of a solid
    /// meet; smooth and creased fans span at most a plane.
    fn is_corner(&self, v: u32, incidence: &Incidence) -> bool {
        let p = |v: u32| self.positions[v as usize];
        let normals = || {
            incidence.of(v).iter().map(|&f| {
                let [a, b, c] = self.tris[f as usize].map(p);
                (b - a).cross(c - a).normalize_or_zero()
            })
        };
        let Some(first) = normals().next() else {
            return false;
        };
        let Some(second) =
            normals().min_by(|x, y| first.dot(*x).abs().total_cmp(&first.dot(*y).abs()))
        else {
            return false;
        };
        let plane = first.cross(second);
        normals().any(|n| plane.dot(n).abs() > CORNER_SPAN)
    }

    /// Whether every corner of the triangles around `v` lies within `flat`
    /// of the plane through `v` with the fan's area-weighted normal.
    fn is_flat_fan(&self, v: u32, incidence: &Incidence, flat: f64) -> bool {
        let p = |v: u32| self.positions[v as usize].as_dvec3();
        let faces = incidence.of(v);
        let normal = faces
            .iter()
            .map(|&f| {
                let [a, b, c] = self.tris[f as usize].map(p);
                (b - a).cross(c - a)
            })
            .sum::<glam::DVec3>()
            .normalize_or_zero();
        normal != glam::DVec3::ZERO
            && faces.iter().all(|&f| {
                self.tris[f as usize]
                    .iter()
                    .all(|&w| normal.dot(p(w) - p(v)).abs() <= flat)
            })
    }

    /// Makes the accepted collapses (quadrics merge, triangles renumber and
    /// the two around each edge drop out) and remembers the refused ones.
    fn apply(&mut self, chosen: &[Collapse], accepted: &[bool]) -> usize {
        let mut onto: Vec<u32> = (0..self.positions.len() as u32).collect();
        let mut made = 0;
        for (c, &ok) in chosen.iter().zip(accepted) {
            if ok {
                onto[c.from as usize] = c.to;
                let moved = self.quadrics[c.from as usize];
                let to = c.to as usize;
                self.quadrics[to].add(&moved);
                self.own_error[to] = self.quadrics[to].sum_at(self.positions[to]);
                made += 1;
            } else {
                self.refused.push(key(c.from, c.to));
                self.refused_from[c.from as usize] = true;
            }
        }
        self.refused.sort_unstable();
        if made > 0 {
            let tris = std::mem::take(&mut self.tris);
            self.tris = tris
                .into_par_iter()
                .with_min_len(SERIAL_TRIANGLES)
                .map(|t| t.map(|v| onto[v as usize]))
                .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
                .collect();
        }
        made
    }
}

/// Reduces a closed (or partly closed) triangle mesh: collapses edges while
/// `deviation` reports every sample of the changed triangles (their
/// centroids and new edges' midpoints) within `opts.tolerance`. Vertices on
/// boundaries or shared by several fans stay where they are. `cancel` is
/// polled between passes and while choosing collapses.
pub fn reduce_triangles(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    opts: &ReduceOptions,
    deviation: Deviation,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Reduced, Cancelled> {
    if !(PARTS_FROM..PARTS_BELOW).contains(&triangles.len()) {
        return Ok(reduce_whole(positions, triangles, Frozen::None, opts, deviation, cancel)?.0);
    }
    let parts = split_into_parts(positions, triangles);
    // The vertices on a cut (in triangles of two parts) stay where they
    // are and take no collapse until the whole is reduced: a part sees only
    // its side of their fans, and a collapse onto one could make an edge
    // the other part has too.
    let cut = cut_vertices(positions.len(), &parts);
    let reduced = parts
        .par_iter()
        .map(|part| reduce_whole(positions, part, Frozen::Cut(&cut), opts, deviation, cancel))
        .collect::<Result<Vec<_>, Cancelled>>()?;
    let first: usize = reduced.iter().map(|(r, _)| r.collapses).sum();
    // The last reduction tries first the edges at the cuts and those the
    // parts' last passes left to try: each part found every other collapse
    // it could make or was refused.
    let mut seeds = cut;
    for (_, touched) in &reduced {
        for (seed, &hot) in seeds.iter_mut().zip(touched.iter().flatten()) {
            *seed |= hot;
        }
    }
    let joined: Vec<[u32; 3]> = reduced.into_iter().flat_map(|(r, _)| r.triangles).collect();
    let (mut out, _) = reduce_whole(
        positions,
        &joined,
        Frozen::Seeds(seeds),
        opts,
        deviation,
        cancel,
    )?;
    out.collapses += first;
    Ok(out)
}

/// Meshes from this many triangles up to `PARTS_BELOW` are reduced in
/// `PARTS` pieces at once before the whole is: a pass over fewer than
/// `SERIAL_TRIANGLES` runs on one thread, and such a mesh takes thirty
/// passes (colonnade at depth 6: 5,192 triangles, 8 ms, a quarter of its
/// meshing). Each piece's vertices on its cut have open fans there, so
/// they stay (see `State::new`); the last reduction of the whole takes the
/// cuts' strips.
const PARTS_FROM: usize = 1024;
const PARTS_BELOW: usize = 4 * SERIAL_TRIANGLES;
const PARTS: usize = 2;

/// A part stops once a pass collapses under one in this many of its
/// triangles: its last passes find a handful each at a pass's cost, and
/// the whole's passes take them together with the cuts' (colonnade at
/// depth 6: a third of the parts' passes).
const PART_STALL: usize = 32;

/// The triangles in `PARTS` runs of equal count along the longest axis of
/// their centroids' box (ties by index: the split does not depend on
/// threads).
fn split_into_parts(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Vec<[u32; 3]>> {
    let centroid = |t: &[u32; 3]| t.iter().map(|&v| positions[v as usize]).sum::<Vec3>() / 3.0;
    let (lo, hi) = triangles.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), t| {
            let c = centroid(t);
            (lo.min(c), hi.max(c))
        },
    );
    let size = hi - lo;
    let axis = (0..3).fold(0, |a, k| if size[k] > size[a] { k } else { a });
    let mut order: Vec<(f32, u32)> = triangles
        .iter()
        .enumerate()
        .map(|(i, t)| (centroid(t)[axis], i as u32))
        .collect();
    order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    order
        .chunks(order.len().div_ceil(PARTS))
        .map(|run| {
            let mut part: Vec<u32> = run.iter().map(|&(_, i)| i).collect();
            // Each part in the input's order.
            part.sort_unstable();
            part.into_iter().map(|i| triangles[i as usize]).collect()
        })
        .collect()
}

/// The vertices in triangles of more than one part.
fn cut_vertices(vertices: usize, parts: &[Vec<[u32; 3]>]) -> Vec<bool> {
    let mut part_of = vec![usize::MAX; vertices];
    let mut cut = vec![false; vertices];
    for (k, part) in parts.iter().enumerate() {
        for &v in part.iter().flatten() {
            match part_of[v as usize] {
                usize::MAX => part_of[v as usize] = k,
                p if p != k => cut[v as usize] = true,
                _ => {}
            }
        }
    }
    cut
}

/// Vertices a reduction treats apart.
enum Frozen<'a> {
    None,
    /// Vertices on a part's cut: never the end of a collapse (nor its
    /// start: their fans are open).
    Cut(&'a [bool]),
    /// Vertices whose triangles the first pass tries alone.
    Seeds(Vec<bool>),
}

/// Reduces the whole mesh in passes (see [`reduce_triangles`]).
fn reduce_whole(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    frozen: Frozen,
    opts: &ReduceOptions,
    deviation: Deviation,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<(Reduced, Option<Vec<bool>>), Cancelled> {
    let mut state = State::new(positions, triangles);
    // A part hands its last passes to the whole (see `PART_STALL`).
    let part = matches!(frozen, Frozen::Cut(_));
    match frozen {
        Frozen::None => {}
        Frozen::Cut(cut) => state.frozen = Some(cut),
        Frozen::Seeds(seeds) => state.touched = Some(seeds),
    }
    let mut out = Reduced::default();
    let bound = opts.tolerance * opts.tolerance;
    loop {
        if cancel() {
            return Err(Cancelled);
        }
        let incidence = Incidence::build(positions.len(), &state.tris);
        let candidates = by_cost(state.candidates(bound), bound);
        let chosen = state.independent(&candidates, &incidence, opts.min_normal_cos, cancel)?;
        if chosen.is_empty() {
            break;
        }
        let accepted = state.measure(&chosen, &incidence, opts.tolerance, deviation);
        let made = state.apply(&chosen, &accepted);
        out.collapses += made;
        // The last passes of a large mesh find a handful of collapses each
        // among thousands of edges: stop once a pass removes under 1/64 of
        // the vertices (a closed mesh has half as many vertices as
        // triangles); a small mesh's passes cost little, so it goes on,
        // but a part's (see `PART_STALL`).
        let stalled = if part {
            made * PART_STALL < state.tris.len()
        } else {
            made * 128 < state.tris.len().saturating_sub(STALL_FROM)
        };
        if stalled {
            break;
        }
    }
    out.triangles = state.tris;
    Ok((out, state.touched))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cube [-1, 1]^3 as twelve triangles, with a vertex `E` added on
    /// its edge from the corner `C` = (1, 1, 1) towards (-1, 1, 1), `gap`
    /// from `C`: returns the mesh, `C` and `E`.
    fn cube_with_edge_vertex(gap: f32) -> (Vec<Vec3>, Vec<[u32; 3]>, u32, u32) {
        let g =
            crate::ops::triangulate(&crate::primitives::box_mesh(Vec3::splat(2.0), [1; 3]), None);
        let mut positions = g.positions().to_vec();
        let mut tris: Vec<[u32; 3]> = (0..g.num_prims())
            .map(|p| {
                let v = g.prim_points(p);
                [v[0], v[1], v[2]]
            })
            .collect();
        let at = |q: Vec3| positions.iter().position(|&p| p == q).unwrap() as u32;
        let (c, x) = (at(Vec3::ONE), at(Vec3::new(-1.0, 1.0, 1.0)));
        let e = positions.len() as u32;
        positions.push(Vec3::new(1.0 - gap, 1.0, 1.0));
        // Split the two triangles on edge C-X at E.
        let mut split = Vec::new();
        tris.retain(|t| {
            let on = (0..3).find(|&i| {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                (a, b) == (c, x) || (a, b) == (x, c)
            });
            match on {
                Some(i) => {
                    let (a, b, o) = (t[i], t[(i + 1) % 3], t[(i + 2) % 3]);
                    split.push([a, e, o]);
                    split.push([e, b, o]);
                    false
                }
                None => true,
            }
        });
        tris.extend(split);
        (positions, tris, c, e)
    }

    fn box_distance(points: &[Vec3], out: &mut [f32]) {
        for (p, o) in points.iter().zip(out) {
            let q = p.abs() - Vec3::ONE;
            *o = q.max(Vec3::ZERO).length() + q.max_element().min(0.0);
        }
    }

    /// The field sees only the moved triangles' side: sliding the corner
    /// along its edge to a vertex twice the tolerance away keeps every
    /// sample near some face of the cube. The corner must stay; the edge
    /// vertex may still collapse onto the corner.
    #[test]
    fn a_corner_does_not_slide_along_its_edge() {
        let tolerance = 0.01;
        let (positions, tris, c, e) = cube_with_edge_vertex(0.02);
        let state = State::new(&positions, &tris);
        let incidence = Incidence::build(positions.len(), &tris);
        assert!(state.is_corner(c, &incidence));
        assert!(!state.is_corner(e, &incidence));
        let moves = [
            Collapse {
                cost: 0.0,
                from: c,
                to: e,
            },
            Collapse {
                cost: 0.0,
                from: e,
                to: c,
            },
        ];
        let accepted = state.measure(&moves, &incidence, tolerance, &box_distance);
        assert_eq!(accepted, [false, true]);
        // Within the tolerance, the corner may move (the surface it stood
        // for is still covered).
        let (positions, tris, c, e) = cube_with_edge_vertex(0.005);
        let state = State::new(&positions, &tris);
        let incidence = Incidence::build(positions.len(), &tris);
        let near = [Collapse {
            cost: 0.0,
            from: c,
            to: e,
        }];
        assert_eq!(
            state.measure(&near, &incidence, tolerance, &box_distance),
            [true]
        );
    }
}
