//! A brick's samples: the field at the corners of its cells (and of a ring
//! of cells around it, where a feature needs them) and where the surface
//! crosses each sign-changing edge, solved for many edges at once.

use crate::cell::Grid;
use crate::features::Plane;
use geode_frep::eval::{BatchEval, BatchGradEval, Grad, PointEval};

pub(crate) use crate::cell::B;

/// Corners sampled per axis: the brick's B + 1 and one on either side, so
/// the cells around the brick's border cells are known (corner recovery
/// looks one cell beyond its own).
pub(crate) const L: usize = B + 3;

/// The field at the corners of the brick and of a one-cell ring around it,
/// addressed by brick-local corner coordinates -1..=B+1.
pub(crate) struct Lattice {
    pub(crate) base: [isize; 3],
    pub(crate) values: Vec<f32>,
}

impl Lattice {
    /// The brick's own corners (the ring is sampled by [`Lattice::sample_ring`]
    /// only where a feature needs it).
    pub(crate) fn sample(batch: &mut BatchEval, grid: &Grid, base: [usize; 3]) -> Lattice {
        const N: usize = B + 1;
        let mut lattice = Lattice {
            base: base.map(|b| b as isize),
            values: vec![0.0f32; L * L * L],
        };
        // Each axis's coordinates once, the corners in x-fastest order,
        // the values written back row by row.
        let along: [[f32; N]; 3] = std::array::from_fn(|a| {
            std::array::from_fn(|i| grid.coordinate(a, (base[a] + i) as isize) as f32)
        });
        let (mut xs, mut ys, mut zs) = (
            Vec::with_capacity(N * N * N),
            Vec::with_capacity(N * N * N),
            Vec::with_capacity(N * N * N),
        );
        for z in along[2] {
            for y in along[1] {
                xs.extend_from_slice(&along[0]);
                ys.extend_from_slice(&[y; N]);
                zs.extend_from_slice(&[z; N]);
            }
        }
        let mut values = vec![0.0f32; N * N * N];
        batch.eval(&xs, &ys, &zs, &mut values);
        snap_to_surface(&mut values, grid.h);
        for (row, from) in values.chunks_exact(N).enumerate() {
            let (j, k) = (row % N, row / N);
            let at = lattice_index([0, j as isize, k as isize]);
            lattice.values[at..at + N].copy_from_slice(from);
        }
        lattice
    }

    /// Samples the corners of the ring cells `cells` not sampled yet.
    pub(crate) fn sample_cells(
        &mut self,
        batch: &mut BatchEval,
        grid: &Grid,
        cells: &[[isize; 3]],
    ) {
        let mut wanted = vec![false; L * L * L];
        for c in cells {
            for k in 0..8 {
                let p = [c[0] + (k & 1), c[1] + (k >> 1 & 1), c[2] + (k >> 2 & 1)];
                if p.iter().any(|&x| x == -1 || x == B as isize + 1) {
                    wanted[lattice_index(p)] = true;
                }
            }
        }
        self.fill(batch, grid, (-1, B as isize + 1), |p| {
            wanted[lattice_index(p)]
        });
    }

    /// The crossed edges of `cells` that `skip` does not reject, each once.
    pub(crate) fn cell_edges(
        &self,
        grid: &Grid,
        cells: &[[isize; 3]],
        skip: impl Fn(usize) -> bool,
    ) -> Vec<Root> {
        let mut queued = vec![false; 3 * L * L * L];
        let mut roots = Vec::new();
        for c in cells {
            for axis in 0..3 {
                for e in 0..4 {
                    let mut p = *c;
                    p[(axis + 1) % 3] += (e & 1) as isize;
                    p[(axis + 2) % 3] += (e >> 1) as isize;
                    let slot = edge_slot(axis, p);
                    if queued[slot] || skip(slot) {
                        continue;
                    }
                    queued[slot] = true;
                    roots.extend(self.root(grid, axis, p, slot));
                }
            }
        }
        roots
    }

    /// The crossing to solve on the edge along `axis` from local corner `c`,
    /// if its ends differ in sign and lie in the grid.
    pub(crate) fn root(
        &self,
        grid: &Grid,
        axis: usize,
        c: [isize; 3],
        slot: usize,
    ) -> Option<Root> {
        let mut d = c;
        d[axis] += 1;
        let (v0, v1) = (self.at(c), self.at(d));
        if (v0 >= 0.0) == (v1 >= 0.0) {
            return None;
        }
        let (a, b) = (self.global(grid, c)?, self.global(grid, d)?);
        Some(Root {
            slot,
            a: grid.point(a),
            b: grid.point(b),
            t0: 0.0,
            f0: v0 as f64,
            t1: 1.0,
            f1: v1 as f64,
            side: 0,
        })
    }

    /// Evaluates the corners in `lo..=hi` that `which` selects, in one batch.
    pub(crate) fn fill(
        &mut self,
        batch: &mut BatchEval,
        grid: &Grid,
        (lo, hi): (isize, isize),
        which: impl Fn([isize; 3]) -> bool,
    ) {
        let n = ((hi - lo + 1) as usize).pow(3);
        let mut xs = Vec::with_capacity(n);
        let mut ys = Vec::with_capacity(n);
        let mut zs = Vec::with_capacity(n);
        let mut at = Vec::with_capacity(n);
        for k in lo..=hi {
            for j in lo..=hi {
                for i in lo..=hi {
                    if !which([i, j, k]) {
                        continue;
                    }
                    let b = self.base;
                    let p = grid.point_signed([b[0] + i, b[1] + j, b[2] + k]);
                    xs.push(p[0] as f32);
                    ys.push(p[1] as f32);
                    zs.push(p[2] as f32);
                    at.push(lattice_index([i, j, k]));
                }
            }
        }
        let mut values = vec![0.0f32; xs.len()];
        batch.eval(&xs, &ys, &zs, &mut values);
        snap_to_surface(&mut values, grid.h);
        for (i, v) in at.into_iter().zip(values) {
            self.values[i] = v;
        }
    }

    pub(crate) fn at(&self, c: [isize; 3]) -> f32 {
        self.values[lattice_index(c)]
    }

    /// The grid corner of a local corner; None outside the grid (where the
    /// clipped field never has surface).
    pub(crate) fn global(&self, grid: &Grid, c: [isize; 3]) -> Option<[usize; 3]> {
        let g: [isize; 3] = std::array::from_fn(|a| self.base[a] + c[a]);
        (0..3)
            .all(|a| g[a] >= 0 && (g[a] as usize) < grid.corners[a])
            .then(|| g.map(|x| x as usize))
    }

    /// Every crossed edge with both ends in the local range `lo..=hi` that
    /// `wanted` accepts (by axis and lower local corner), ready to be solved.
    pub(crate) fn crossed_edges_where(
        &self,
        grid: &Grid,
        (lo, hi): (isize, isize),
        wanted: impl Fn(usize, [isize; 3]) -> bool,
    ) -> Vec<Root> {
        // Signs compared along each axis by stride, in one pass over the
        // values; only the few crossed edges build their root.
        let strides = [1, L, L * L];
        let mut roots = Vec::new();
        for k in lo..=hi {
            for j in lo..=hi {
                let row = lattice_index([lo, j, k]);
                for (n, i) in (lo..=hi).enumerate() {
                    let (c, at) = ([i, j, k], row + n);
                    let inside = self.values[at] >= 0.0;
                    for axis in 0..3 {
                        if c[axis] < hi
                            && (self.values[at + strides[axis]] >= 0.0) != inside
                            && wanted(axis, c)
                        {
                            roots.extend(self.root(grid, axis, c, edge_slot(axis, c)));
                        }
                    }
                }
            }
        }
        roots
    }
}

/// The solved crossings of a brick's lattice edges, addressed by the
/// edge's axis and lower local corner (a dense table: hashing cost more
/// than all of the QEF work).
pub(crate) struct Crossings {
    pub(crate) slots: Vec<u32>,
    pub(crate) planes: Vec<Plane>,
    /// Edges crossed twice (see `double`): a table like `slots`, allocated
    /// only when a brick has any, and their two crossings in order along the edge.
    double_slots: Vec<u32>,
    doubles: Vec<[Plane; 2]>,
}

impl Crossings {
    pub(crate) fn new() -> Crossings {
        Crossings {
            slots: vec![u32::MAX; 3 * L * L * L],
            planes: Vec::new(),
            double_slots: Vec::new(),
            doubles: Vec::new(),
        }
    }

    /// The two crossings of an edge crossed twice, nearer its lower end first.
    pub(crate) fn get_double(&self, axis: usize, c: [isize; 3]) -> Option<&[Plane; 2]> {
        match self.double_slots.get(edge_slot(axis, c)) {
            None | Some(&u32::MAX) => None,
            Some(&i) => Some(&self.doubles[i as usize]),
        }
    }

    pub(crate) fn has_doubles(&self) -> bool {
        !self.doubles.is_empty()
    }

    /// Solves the brackets of edges crossed twice (in pairs, as
    /// `double::doubly_crossed_edges` gives them) into the table.
    pub(crate) fn add_doubles(
        &mut self,
        batch: &mut BatchEval,
        point: &mut PointEval,
        grads: &mut BatchGradEval,
        mut roots: Vec<Root>,
    ) {
        if roots.is_empty() {
            return;
        }
        solve_roots(batch, &mut roots);
        let points: Vec<[f64; 3]> = roots.iter().map(Root::point).collect();
        let normals = outward_normals(point, grads, &points);
        self.double_slots.resize(3 * L * L * L, u32::MAX);
        for (pair, at) in roots.chunks_exact(2).zip(0..) {
            let plane = |k: usize| (points[2 * at + k], normals[2 * at + k]);
            self.double_slots[pair[0].slot] = self.doubles.len() as u32;
            self.doubles.push([plane(0), plane(1)]);
        }
    }

    pub(crate) fn get(&self, axis: usize, c: [isize; 3]) -> Option<&Plane> {
        match self.slots[edge_slot(axis, c)] {
            u32::MAX => None,
            i => Some(&self.planes[i as usize]),
        }
    }

    pub(crate) fn contains(&self, slot: usize) -> bool {
        self.slots[slot] != u32::MAX
    }

    /// Solves the roots and their normals into the table.
    pub(crate) fn add(
        &mut self,
        batch: &mut BatchEval,
        point: &mut PointEval,
        grads: &mut BatchGradEval,
        mut roots: Vec<Root>,
    ) {
        solve_roots(batch, &mut roots);
        let points: Vec<[f64; 3]> = roots.iter().map(Root::point).collect();
        let normals = outward_normals(point, grads, &points);
        self.planes.reserve(roots.len());
        for ((r, p), n) in roots.iter().zip(points).zip(normals) {
            self.slots[r.slot] = self.planes.len() as u32;
            self.planes.push((p, n));
        }
    }
}

/// Corners closer to the surface than this (fraction of a cell, read on
/// the field) count as on it.
pub(crate) const SNAP: f64 = 0.005;

/// Corner values just outside the surface set to zero, which reads as
/// inside: the surface then passes through such a corner (moved by at
/// most [`SNAP`] of a cell) instead of grazing it, where it would cut a
/// sliver off the cell (a tiny component of its own, folded against its
/// neighbours, or an edge crossed twice within a hair of its end).
pub(crate) fn snap_to_surface(values: &mut [f32], h: f64) {
    let near = -(SNAP * h) as f32;
    for v in values {
        if *v < 0.0 && *v > near {
            *v = 0.0;
        }
    }
}

pub(crate) fn lattice_index(c: [isize; 3]) -> usize {
    let i = c.map(|x| (x + 1) as usize);
    i[0] + L * (i[1] + L * i[2])
}

/// The axis and local lower corner of the lattice edge at `slot` (see
/// [`edge_slot`]).
pub(crate) fn slot_edge(slot: usize) -> (usize, [isize; 3]) {
    let (axis, i) = (slot / (L * L * L), slot % (L * L * L));
    (
        axis,
        [i % L, i / L % L, i / (L * L)].map(|x| x as isize - 1),
    )
}

/// Index of the lattice edge along `axis` from local corner `c`.
pub(crate) fn edge_slot(axis: usize, c: [isize; 3]) -> usize {
    axis * L * L * L + lattice_index(c)
}

/// Where along an edge (0 to 1) a crossing is accurate enough.
const ROOT_TOLERANCE: f64 = 1e-6;

/// A crossed grid edge being bracketed: the surface lies between `t0` and
/// `t1` (parameters along a-b), where the field has values `f0` and `f1`.
#[derive(Clone)]
pub(crate) struct Root {
    pub(crate) slot: usize,
    pub(crate) a: [f64; 3],
    pub(crate) b: [f64; 3],
    pub(crate) t0: f64,
    pub(crate) f0: f64,
    pub(crate) t1: f64,
    pub(crate) f1: f64,
    /// Which end moved last (-1 low, 1 high): Illinois halves the other.
    pub(crate) side: i8,
}

impl Root {
    pub(crate) fn guess(&self) -> f64 {
        let t = self.t0 + (self.t1 - self.t0) * (self.f0 / (self.f0 - self.f1));
        if t.is_finite() && t > self.t0 && t < self.t1 {
            t
        } else {
            0.5 * (self.t0 + self.t1)
        }
    }

    /// Narrows the bracket with the value `ft` at `t`; true once converged:
    /// the bracket closed, or the secant through it puts the root within
    /// `ROOT_TOLERANCE` of `t` (a millionth of an edge misplaces no vertex).
    pub(crate) fn update(&mut self, t: f64, ft: f64) -> bool {
        let slope = (self.f1 - self.f0).abs() / (self.t1 - self.t0);
        if ft == 0.0 || ft.abs() < ROOT_TOLERANCE * slope {
            (self.t0, self.t1) = (t, t);
            return true;
        }
        if (ft >= 0.0) == (self.f0 >= 0.0) {
            (self.t0, self.f0) = (t, ft);
            if self.side == -1 {
                self.f1 *= 0.5;
            }
            self.side = -1;
        } else {
            (self.t1, self.f1) = (t, ft);
            if self.side == 1 {
                self.f0 *= 0.5;
            }
            self.side = 1;
        }
        self.t1 - self.t0 < self.closed_below()
    }

    /// The bracket width (along the edge, 0 to 1) below which it is
    /// closed: `ROOT_TOLERANCE`, or the resolution of the f32 coordinates
    /// the evaluator reads where that is coarser. Below it, steps land on
    /// the same sampled point; a root whose sampled values could not bracket
    /// it any closer took 20 steps to close (330 edges a mesh of colonnade
    /// at depth 6, each step a pass of its brick's tape).
    fn closed_below(&self) -> f64 {
        let reach = self
            .a
            .iter()
            .chain(&self.b)
            .fold(0.0f64, |m, x| m.max(x.abs()));
        let length = (0..3)
            .map(|k| (self.b[k] - self.a[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        ROOT_TOLERANCE.max(2.0 * f64::from(f32::EPSILON) * reach / length)
    }

    /// The points the next steps will try, as many as are known before the
    /// field is read: the guess, and where an end's value is zero (a corner
    /// snapped onto the surface, see `SNAP`) the bisections towards it
    /// that follow while the values keep the other end's sign (false
    /// position cannot leave a zero end, so it bisects, as many as twenty
    /// times: a pass of the brick's tape each, one in every 40 roots of
    /// colonnade at depth 6).
    fn next_guesses(&self, most: usize) -> impl Iterator<Item = f64> {
        let first = self.guess();
        let zero_end = match (self.f0 == 0.0, self.f1 == 0.0) {
            (true, false) => Some(self.t0),
            (false, true) => Some(self.t1),
            _ => None,
        };
        let ahead = if zero_end.is_some() { SPECULATE } else { 1 };
        let near = zero_end.unwrap_or(first);
        std::iter::successors(Some(first), move |&far| Some(0.5 * (near + far)))
            .take(ahead.min(most))
    }

    /// Where along the edge (0 to 1) the crossing is.
    pub(crate) fn parameter(&self) -> f64 {
        if self.t1 - self.t0 < self.closed_below() {
            0.5 * (self.t0 + self.t1)
        } else {
            self.guess()
        }
    }

    pub(crate) fn point(&self) -> [f64; 3] {
        let t = self.parameter();
        std::array::from_fn(|k| self.a[k] + (self.b[k] - self.a[k]) * t)
    }
}

/// Where the surface crosses each edge: Illinois false position (fast on
/// smooth fields, and it cannot stall on the flat stretches of distance
/// fields) run on all edges of a brick at once, one batch per step, on the
/// same f32 evaluator that classified the corners (so brackets agree).
pub(crate) fn solve_roots(batch: &mut BatchEval, roots: &mut [Root]) {
    let mut active: Vec<usize> = (0..roots.len()).collect();
    let mut steps = vec![0usize; roots.len()];
    let mut done = vec![false; roots.len()];
    let n = roots.len();
    let (mut xs, mut ys, mut zs) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    // Each root's points this pass: (root, t), in order.
    let (mut ts, mut values): (Vec<(usize, f64)>, Vec<f32>) =
        (Vec::with_capacity(n), Vec::with_capacity(n));
    while !active.is_empty() {
        xs.clear();
        ys.clear();
        zs.clear();
        ts.clear();
        for &i in &active {
            let r = &roots[i];
            for t in r.next_guesses(STEPS - steps[i]) {
                ts.push((i, t));
                xs.push((r.a[0] + (r.b[0] - r.a[0]) * t) as f32);
                ys.push((r.a[1] + (r.b[1] - r.a[1]) * t) as f32);
                zs.push((r.a[2] + (r.b[2] - r.a[2]) * t) as f32);
            }
        }
        values.resize(xs.len(), 0.0);
        batch.eval(&xs, &ys, &zs, &mut values);
        // Each root takes its points in order while each is still the
        // guess it would make (a step that moved the bracket otherwise
        // ends its run); exactly the steps one point a pass would take.
        let mut stopped = usize::MAX;
        for (&(i, t), &value) in ts.iter().zip(&values) {
            if done[i] || stopped == i {
                continue;
            }
            if roots[i].guess().to_bits() != t.to_bits() {
                stopped = i;
                continue;
            }
            steps[i] += 1;
            done[i] = roots[i].update(t, value as f64);
        }
        active.retain(|&i| !done[i] && steps[i] < STEPS);
    }
}

/// Bisections towards a zero end tried in one pass.
const SPECULATE: usize = 8;

/// False-position steps a root takes at most.
const STEPS: usize = 24;

/// `-grad f / |grad f|`; central differences where the gradient is
/// singular (a kink exactly at the point), the segment direction never.
pub(crate) fn outward_normal(point: &mut PointEval, gradient: [f64; 3], p: [f64; 3]) -> [f64; 3] {
    let unit = |g: [f64; 3]| {
        let len = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
        (len > 0.0 && len.is_finite()).then(|| g.map(|x| -x / len))
    };
    if let Some(n) = unit(gradient) {
        return n;
    }
    let h = 1e-7 * (1.0 + p.iter().fold(0.0f64, |m, x| m.max(x.abs())));
    let g: [f64; 3] = std::array::from_fn(|k| {
        let (mut a, mut b) = (p, p);
        a[k] -= h;
        b[k] += h;
        (point.eval(b) - point.eval(a)) / (2.0 * h)
    });
    unit(g).unwrap_or([0.0, 1.0, 0.0])
}

/// Outward unit normals at many points: exact gradients in one batch, the
/// scalar fallback only where a gradient vanishes.
pub(crate) fn outward_normals(
    point: &mut PointEval,
    grads: &mut BatchGradEval,
    points: &[[f64; 3]],
) -> Vec<[f64; 3]> {
    let mut g = vec![Grad::default(); points.len()];
    grads.eval(points, &mut g);
    points
        .iter()
        .zip(&g)
        .map(|(p, g)| outward_normal(point, g.d, *p))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use geode_frep::field::Field;
    use geode_frep::tape::Tape;

    /// The roots one point a pass finds (the solver before it tried the
    /// bisections towards a zero end together).
    fn one_point_a_pass(batch: &mut BatchEval, roots: &mut [Root]) {
        let mut active: Vec<usize> = (0..roots.len()).collect();
        for _ in 0..STEPS {
            if active.is_empty() {
                break;
            }
            let ts: Vec<f64> = active.iter().map(|&i| roots[i].guess()).collect();
            let along = |k: usize| -> Vec<f32> {
                active
                    .iter()
                    .zip(&ts)
                    .map(|(&i, t)| (roots[i].a[k] + (roots[i].b[k] - roots[i].a[k]) * t) as f32)
                    .collect()
            };
            let (xs, ys, zs) = (along(0), along(1), along(2));
            let mut values = vec![0.0f32; xs.len()];
            batch.eval(&xs, &ys, &zs, &mut values);
            let mut k = 0;
            active.retain(|&i| {
                let done = roots[i].update(ts[k], values[k] as f64);
                k += 1;
                !done
            });
        }
    }

    /// Edges from grid corners, some with an end exactly on the surface
    /// (zero, as a snapped corner reads), some crossing a sphere and a
    /// wavy sheet inside: the speculating solver ends every bracket where
    /// one point a pass does, bit for bit.
    #[test]
    fn trying_bisections_together_finds_the_same_roots() {
        let (x, y, z) = (Field::x(), Field::y(), Field::z());
        let sphere = (&x * &x + &y * &y + &z * &z).sqrt() - 0.5;
        let sheet = &z - (&x * 7.0).sin() * 0.05 - 0.125;
        let tape = Tape::compile(&sphere.min(sheet));
        let mut batch = BatchEval::new(&tape);
        let mut point = PointEval::new(&tape);
        let h = 1.0 / 16.0;
        let mut roots = Vec::new();
        for i in -12..12 {
            for j in -12..12 {
                for k in -12..12 {
                    let a = [i, j, k].map(|c| c as f64 * h);
                    for axis in 0..3 {
                        let mut b = a;
                        b[axis] += h;
                        // Values as the lattice reads them: snapped where
                        // just outside.
                        let snap = |v: f64| if v < 0.0 && v > -SNAP * h { 0.0 } else { v };
                        let (f0, f1) = (snap(point.eval(a)), snap(point.eval(b)));
                        if (f0 >= 0.0) != (f1 >= 0.0) {
                            roots.push(Root {
                                slot: roots.len(),
                                a,
                                b,
                                t0: 0.0,
                                f0,
                                t1: 1.0,
                                f1,
                                side: 0,
                            });
                        }
                    }
                }
            }
        }
        let zero_ends = roots.iter().filter(|r| r.f0 == 0.0 || r.f1 == 0.0).count();
        assert!(
            roots.len() > 500 && zero_ends > 10,
            "{} {zero_ends}",
            roots.len()
        );
        agree(&mut batch, roots);
        // Edges from a zero end into a field that rises again where a
        // bisection lands (a bump at a quarter, an eighth, three eighths
        // of the edge): the tried points past it are not the steps one
        // point a pass takes.
        for bump in [0.25, 0.125, 0.375, 0.3] {
            let f = x.min(Field::constant(0.01) - (&x - bump).abs());
            let tape = Tape::compile(&f);
            let mut batch = BatchEval::new(&tape);
            let roots = (0..8)
                .map(|i| Root {
                    slot: i,
                    a: [0.0, i as f64 * 0.1, 0.0],
                    b: [1.0, i as f64 * 0.1, 0.0],
                    t0: 0.0,
                    f0: 0.0,
                    t1: 1.0,
                    f1: -0.74,
                    side: 0,
                })
                .collect();
            agree(&mut batch, roots);
        }
    }

    /// The speculating solver and one point a pass end every bracket alike.
    fn agree(batch: &mut BatchEval, mut roots: Vec<Root>) {
        let mut sequential = roots.clone();
        one_point_a_pass(batch, &mut sequential);
        solve_roots(batch, &mut roots);
        for (got, want) in roots.iter().zip(&sequential) {
            let bits = |r: &Root| [r.t0, r.t1, r.f0, r.f1].map(f64::to_bits);
            assert_eq!(bits(got), bits(want), "edge {:?} to {:?}", got.a, got.b);
        }
    }
}
