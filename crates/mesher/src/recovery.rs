//! Feature work across a brick's cells: the planes each cell with surface
//! sees, the batch check of proposed edge and corner points against the
//! field, and the recovery of features that a cell sees only in part from
//! the planes of its neighbours (see `features`).

use geode_geo::glam::Vec3;

use crate::cell::Grid;
use crate::cell::B;
use crate::features::{self, CellBox, Plane};
use crate::lattice::{Crossings, Lattice};
use crate::qef::Qef;
use geode_frep::eval::{BatchEval, BatchGradEval, Grad, GradEval, IntervalEval, PointEval};
use geode_frep::interval::Interval;
use geode_frep::tape::Tape;

/// Cells whose QEFs are kept per axis: the brick's and one on either side.
pub(crate) const C: usize = B + 2;

/// The planes of every crossed edge of the cell at local `cell`, summed.
pub(crate) fn cell_qef(cell: [isize; 3], crossings: &Crossings) -> Qef {
    let mut q = Qef::default();
    for axis in 0..3 {
        for c in 0..4 {
            let mut p = [cell[0], cell[1], cell[2]];
            p[(axis + 1) % 3] += (c & 1) as isize;
            p[(axis + 2) % 3] += (c >> 1) as isize;
            if let Some(&(x, n)) = crossings.get(axis, p) {
                q.add(x, n);
            }
        }
    }
    q
}

/// The planes (summed) and rank of each cell with surface in and around a
/// brick, stored compactly: most of the 1000 cells have none.
pub(crate) struct CellTable {
    pub(crate) index: Vec<u32>,
    pub(crate) qefs: Vec<Qef>,
    pub(crate) ranks: Vec<u8>,
}

impl CellTable {
    pub(crate) fn new() -> CellTable {
        CellTable {
            index: vec![u32::MAX; C * C * C],
            qefs: Vec::new(),
            ranks: Vec::new(),
        }
    }

    pub(crate) fn merge(&mut self, slot: usize, q: &Qef, rank: u8) {
        match self.index[slot] {
            u32::MAX => {
                self.index[slot] = self.qefs.len() as u32;
                self.qefs.push(*q);
                self.ranks.push(rank);
            }
            i => {
                self.qefs[i as usize].merge(q);
                self.ranks[i as usize] = self.ranks[i as usize].max(rank);
            }
        }
    }

    pub(crate) fn get(&self, slot: usize) -> Option<&Qef> {
        match self.index[slot] {
            u32::MAX => None,
            i => Some(&self.qefs[i as usize]),
        }
    }

    pub(crate) fn rank(&self, slot: usize) -> u8 {
        match self.index[slot] {
            u32::MAX => 0,
            i => self.ranks[i as usize],
        }
    }
}

pub(crate) fn cell_slot(c: [isize; 3]) -> usize {
    let i = c.map(|x| (x + 1) as usize);
    i[0] + C * (i[1] + C * i[2])
}

/// A single-component cell's vertex that corner recovery may move (its
/// planes are its cell's, in the cell table), with the rank it sits on.
pub(crate) struct Candidate {
    pub(crate) vertex: u32,
    pub(crate) cell: [u8; 3],
    pub(crate) rank: u8,
}

/// An edge or corner point to check: its vertex, its planes (a range of a
/// shared list), its cell and, for a single-component cell, its candidate.
pub(crate) type Check = (usize, std::ops::Range<usize>, CellBox, Option<usize>);

/// Checks the proposed edge and corner points against the field in one
/// batch; each that is off the surface (an edge's line past the edge's end)
/// is placed again on the surface, no longer as a feature.
pub(crate) fn verify_features(
    tape: &Tape,
    grid: &Grid,
    sharpness: f64,
    (checks, planes): (&[Check], &[Plane]),
    candidates: &mut [Candidate],
    (positions, vertex_points): (&mut [Vec3], &mut [[f64; 3]]),
) {
    if checks.is_empty() {
        return;
    }
    let points: Vec<[f64; 3]> = checks.iter().map(|c| vertex_points[c.0]).collect();
    let mut g = vec![Grad::default(); points.len()];
    BatchGradEval::new(tape).eval(&points, &mut g);
    let mut grad = GradEval::new(tape);
    for ((vertex, range, bounds, candidate), g) in checks.iter().zip(&g) {
        if features::verified(g, grid.h) {
            continue;
        }
        let own = &planes[range.clone()];
        let mut qef = Qef::default();
        for &(p, n) in own {
            qef.add(p, n);
        }
        let x = vertex_points[*vertex];
        if let Some(y) = features::onto_curved_crease(&mut grad, x, bounds, grid.h) {
            vertex_points[*vertex] = y;
            positions[*vertex] = Vec3::new(y[0] as f32, y[1] as f32, y[2] as f32);
            continue;
        }
        let x = features::best_on_surface(own, &qef, None, sharpness, bounds, &mut grad, grid.h);
        vertex_points[*vertex] = x;
        positions[*vertex] = Vec3::new(x[0] as f32, x[1] as f32, x[2] as f32);
        if let Some(c) = candidate {
            candidates[*c].rank = 0;
        }
    }
}

/// A feature runs through the brick: the cells one beyond it are sampled
/// too (with `tape`, valid there), then every cell near a feature cell may
/// hold part of a corner or edge its own planes do not see; its vertex
/// moves there when the neighbourhood's planes agree (see `features::recover`).
pub(crate) fn recover_features(
    tape: &Tape,
    grid: &Grid,
    sharpness: f64,
    (lattice, crossings, cells): (&mut Lattice, &mut Crossings, &mut CellTable),
    candidates: &[Candidate],
    (positions, vertex_points): (&mut [Vec3], &mut [[f64; 3]]),
) -> Vec<u32> {
    let base = lattice.base;
    // The parent's tape simplified once more, over this brick and its ring.
    let lo = grid.point_signed(base).map(|x| x - grid.h);
    let hi = grid
        .point_signed(base.map(|b| b + B as isize))
        .map(|x| x + grid.h);
    let mut iv = IntervalEval::new(tape);
    iv.eval(
        Interval::new(lo[0], hi[0]),
        Interval::new(lo[1], hi[1]),
        Interval::new(lo[2], hi[2]),
    );
    let tape = &tape.simplify(iv.choices());
    let mut batch = BatchEval::new(tape);
    let mut point = PointEval::new(tape);
    let mut grads = BatchGradEval::new(tape);
    let mut grad = GradEval::new(tape);
    // Candidates next to a feature cell of the brick, and the ring cells
    // around them: only those are sampled beyond the brick.
    let near: Vec<&Candidate> = candidates
        .iter()
        .filter(|c| {
            let n = neighbourhood(c.cell.map(|x| x as isize));
            n.iter().any(|&s| cells.rank(s) >= 2)
        })
        .collect();
    let mut ring_cells = vec![false; C * C * C];
    for cand in &near {
        for d in 0..27 {
            let c = neighbour(cand.cell.map(|x| x as isize), d);
            if c.iter().any(|&x| x == -1 || x == B as isize) {
                ring_cells[cell_slot(c)] = true;
            }
        }
    }
    let ring: Vec<[isize; 3]> = (0..C * C * C)
        .filter(|&s| ring_cells[s])
        .map(slot_cell)
        .collect();
    lattice.sample_cells(&mut batch, grid, &ring);
    let roots = lattice.cell_edges(grid, &ring, |s| crossings.contains(s));
    crossings.add(&mut batch, &mut point, &mut grads, roots);
    for &c in &ring {
        let q = cell_qef(c, crossings);
        if q.count() > 0 {
            cells.merge(cell_slot(c), &q, q.solver().rank(sharpness) as u8);
        }
    }
    let mut moved = Vec::new();
    for cand in near {
        let local = cand.cell.map(|c| c as isize);
        let near = neighbourhood(local);
        let mut around = Qef::default();
        for &s in &near {
            if let Some(q) = cells.get(s) {
                around.merge(q);
            }
        }
        // The cell and its neighbours: a corner's tip may lie in an
        // empty neighbour (see `owns_point`).
        let cell: [usize; 3] = std::array::from_fn(|a| base[a] as usize + cand.cell[a] as usize);
        let reach = cell_box(grid, cell, 1);
        let Some(own) = cells.get(cell_slot(local)) else {
            continue;
        };
        let own = (own, cand.rank as usize);
        let Some(x) = features::recover(own, &around, sharpness, &reach, grid.h) else {
            continue;
        };
        if owns_point(lattice, grid, local, x) && features::on_surface(&mut grad, x, grid.h) {
            let v = cand.vertex as usize;
            vertex_points[v] = x;
            positions[v] = Vec3::new(x[0] as f32, x[1] as f32, x[2] as f32);
            moved.push(cand.vertex);
        }
    }
    moved
}

/// The box of the cell at grid `cell` grown by `grow` cells on every side,
/// less a margin so no vertex sits on a cell face (two neighbours' vertices
/// at one point would pinch the mesh).
pub(crate) fn cell_box(grid: &Grid, cell: [usize; 3], grow: usize) -> CellBox {
    let margin = 1e-4 * grid.h;
    let g = grow as f64 * grid.h;
    CellBox {
        lo: grid.point(cell).map(|c| c - g + margin),
        hi: grid
            .point([cell[0] + 1, cell[1] + 1, cell[2] + 1])
            .map(|c| c + g - margin),
    }
}

/// Whether the cell at local `cell` takes the recovered feature point `x`:
/// always inside it; in a neighbouring cell only when that cell has no
/// surface of its own (a corner's tip between grid corners) and this is the
/// surface cell around it whose centre is nearest (so one vertex goes there).
pub(crate) fn owns_point(lattice: &Lattice, grid: &Grid, cell: [isize; 3], x: [f64; 3]) -> bool {
    let local: [isize; 3] = std::array::from_fn(|a| {
        ((x[a] - grid.origin[a]) / grid.h).floor() as isize - lattice.base[a]
    });
    if local == cell {
        return true;
    }
    let margin = 1e-4;
    let off_faces = (0..3).all(|a| {
        let f = (x[a] - grid.origin[a]) / grid.h;
        let t = f - f.floor();
        t > margin && t < 1.0 - margin
    });
    let within = |c: [isize; 3]| c.iter().all(|&v| (-1..=B as isize).contains(&v));
    if !off_faces || !within(local) || has_surface(lattice, local) {
        return false;
    }
    let centre_distance = |c: [isize; 3]| -> f64 {
        (0..3)
            .map(|a| {
                let centre = grid.origin[a] + ((lattice.base[a] + c[a]) as f64 + 0.5) * grid.h;
                (centre - x[a]).powi(2)
            })
            .sum()
    };
    let nearest = (0..27)
        .map(|n| {
            let d = [
                (n % 3) as isize - 1,
                (n / 3 % 3) as isize - 1,
                (n / 9) as isize - 1,
            ];
            [local[0] + d[0], local[1] + d[1], local[2] + d[2]]
        })
        .filter(|&c| c != local && within(c) && has_surface(lattice, c))
        .min_by(|&a, &b| centre_distance(a).total_cmp(&centre_distance(b)));
    nearest == Some(cell)
}

pub(crate) fn has_surface(lattice: &Lattice, c: [isize; 3]) -> bool {
    let signs: Vec<bool> = (0..8)
        .map(|k| lattice.at([c[0] + (k & 1), c[1] + (k >> 1 & 1), c[2] + (k >> 2 & 1)]) >= 0.0)
        .collect();
    signs.iter().any(|&s| s) && signs.iter().any(|&s| !s)
}

/// The `n`th (0..27) cell of the 3x3x3 block centred on `cell`.
pub(crate) fn neighbour(cell: [isize; 3], n: usize) -> [isize; 3] {
    let d = [
        (n % 3) as isize - 1,
        (n / 3 % 3) as isize - 1,
        (n / 9) as isize - 1,
    ];
    [cell[0] + d[0], cell[1] + d[1], cell[2] + d[2]]
}

pub(crate) fn slot_cell(s: usize) -> [isize; 3] {
    [
        (s % C) as isize - 1,
        (s / C % C) as isize - 1,
        (s / (C * C)) as isize - 1,
    ]
}

/// Slots of the 27 cells around (and including) a brick cell.
pub(crate) fn neighbourhood(cell: [isize; 3]) -> [usize; 27] {
    std::array::from_fn(|n| {
        let d = [
            (n % 3) as isize - 1,
            (n / 3 % 3) as isize - 1,
            (n / 9) as isize - 1,
        ];
        cell_slot([cell[0] + d[0], cell[1] + d[1], cell[2] + d[2]])
    })
}
