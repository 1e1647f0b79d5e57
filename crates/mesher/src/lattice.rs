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
        self.t1 - self.t0 < ROOT_TOLERANCE
    }

    /// Where along the edge (0 to 1) the crossing is.
    pub(crate) fn parameter(&self) -> f64 {
        if self.t1 - self.t0 < ROOT_TOLERANCE {
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
    let n = roots.len();
    let (mut xs, mut ys, mut zs) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    let (mut ts, mut values) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for _ in 0..24 {
        if active.is_empty() {
            break;
        }
        xs.clear();
        ys.clear();
        zs.clear();
        ts.clear();
        for &i in &active {
            let r = &roots[i];
            let t = r.guess();
            ts.push(t);
            xs.push((r.a[0] + (r.b[0] - r.a[0]) * t) as f32);
            ys.push((r.a[1] + (r.b[1] - r.a[1]) * t) as f32);
            zs.push((r.a[2] + (r.b[2] - r.a[2]) * t) as f32);
        }
        values.resize(xs.len(), 0.0);
        batch.eval(&xs, &ys, &zs, &mut values);
        let mut k = 0;
        active.retain(|&i| {
            let done = roots[i].update(ts[k], values[k] as f64);
            k += 1;
            !done
        });
    }
}

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
