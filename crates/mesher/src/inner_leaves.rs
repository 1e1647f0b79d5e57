//! Coarse leaves inside a brick (adaptive output, top-down, below the
//! octree's `coarse` leaves, which cannot see inside a node and so need a
//! proof from interval arithmetic): the brick, or else its octants of 4
//! cells, or else theirs of 2, where the surface the brick's lattice shows
//! is one disc per loop on the node's boundary (each loop one arc a face,
//! once an edge; inside, every cell one component and the dual patch one
//! connected piece per loop, each with Euler characteristic 1) are
//! candidates, and one whose vertices (one a sheet: a plate thinner than
//! the node keeps both sides) fit their loops' planes within the
//! tolerance is meshed as those vertices alone: contracting each disc to
//! a point keeps the mesh closed and manifold (Ju et al.'s criterion, read
//! top-down on the signs instead of bottom-up on every cell's vertex).
//! Their inner edges are never solved and their cells never placed; each
//! vertex stands in every slot its cells hold around the crossed edges of
//! its loop, where the brick's own quads (or the global sort, on the
//! brick's faces) lose its repeated corner. A candidate whose vertices do
//! not fit gives its cells to its octants, each a candidate in turn (or
//! below 4 cells to the brick), and the edges it held that none of them
//! holds are solved then; cells beside an edge crossed twice are never in
//! one.

use crate::boundary::{cells_around, Boundary, Crossing, Loops};
use crate::brick::BrickOut;
use crate::cell::{crossing_key, find, union, Grid, Plane, B, FACES};
use crate::coarse::fit_vertex;
#[cfg(test)]
use crate::lattice::{lattice_index, L};
use crate::lattice::{slot_edge, Crossings, Lattice, Root};
use crate::node_memo::{node_signs, recall, remember, Topology};
use geode_frep::tape::Tape;
use geode_geo::glam::Vec3;

const NONE: u16 = u16::MAX;
/// A cell beside an edge crossed twice.
const DOUBLED: u16 = u16::MAX - 1;

/// The most sheets one leaf holds (a plate thinner than the node: two).
const MOST_SHEETS: usize = 4;

struct InnerLeaf {
    /// First cell, local to the brick.
    lo: [usize; 3],
    side: usize,
    /// The boundary's crossings, by the loop (sheet) they lie on.
    sheets: Vec<Vec<Crossing>>,
    /// A vertex per sheet once each fits; None before fitting, and for a
    /// candidate that gave its cells back (to its octants, or the brick).
    vertices: Option<Vec<[f64; 3]>>,
    fitted: bool,
    split: bool,
}

impl InnerLeaf {
    fn failed(&self) -> bool {
        self.fitted && self.vertices.is_none()
    }
}

/// The leaves of one brick and the cells they cover.
pub(crate) struct InnerLeaves {
    /// Per cell of the brick (x fastest): the leaf covering it, or NONE.
    leaf_of: Vec<u16>,
    leaves: Vec<InnerLeaf>,
    /// Per cell of the brick (x fastest): its corners inside (bit k:
    /// corner k, x fastest), read once for the brick and its octants.
    signs: Vec<u8>,
}

fn cell_index(c: [usize; 3]) -> usize {
    c[0] + B * (c[1] + B * c[2])
}

fn octant(lo: [usize; 3], side: usize, n: usize) -> [usize; 3] {
    [
        lo[0] + (n & 1) * side,
        lo[1] + (n >> 1 & 1) * side,
        lo[2] + (n >> 2 & 1) * side,
    ]
}

impl InnerLeaves {
    pub(crate) fn none() -> InnerLeaves {
        InnerLeaves {
            leaf_of: Vec::new(),
            leaves: Vec::new(),
            signs: Vec::new(),
        }
    }

    /// The candidates of a brick, top-down: the brick, or else each octant
    /// of 4 cells, or else each of its octants of 2.
    pub(crate) fn candidates(
        grid: &Grid,
        base: [usize; 3],
        lattice: &Lattice,
        doubles: &[Root],
    ) -> InnerLeaves {
        let mut signs = vec![0u8; B * B * B];
        for_cells([0; 3], B, |c| signs[cell_index(c)] = cell_signs(lattice, c));
        let mut leaves = InnerLeaves {
            leaf_of: vec![NONE; B * B * B],
            leaves: Vec::new(),
            signs,
        };
        // Cells around an edge crossed twice (a wall thinner than a cell,
        // its two sheets shown by no sign) are never part of a leaf.
        for r in doubles {
            let (axis, c) = slot_edge(r.slot);
            let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
            for (du, dw) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let mut cell = c;
                cell[u] -= du;
                cell[w] -= dw;
                if cell.iter().all(|&x| (0..B as isize).contains(&x)) {
                    leaves.leaf_of[cell_index(cell.map(|x| x as usize))] = DOUBLED;
                }
            }
        }
        if leaves.try_candidate(grid, (base, lattice), ([0; 3], B)) {
            return leaves;
        }
        let half = B / 2;
        for n in 0..8 {
            let lo = octant([0; 3], half, n);
            if !leaves.try_candidate(grid, (base, lattice), (lo, half)) {
                for m in 0..8 {
                    let child = (octant(lo, half / 2, m), half / 2);
                    leaves.try_candidate(grid, (base, lattice), child);
                }
            }
        }
        leaves
    }

    /// Whether the node is settled (one sheet, or no surface at all); a
    /// node with surface becomes a candidate.
    fn try_candidate(
        &mut self,
        grid: &Grid,
        (base, lattice): ([usize; 3], &Lattice),
        (lo, side): ([usize; 3], usize),
    ) -> bool {
        let global: [usize; 3] = std::array::from_fn(|k| base[k] + lo[k]);
        if (0..3).any(|k| global[k] + side >= grid.corners[k]) {
            return false;
        }
        let mut doubled = false;
        for_cells(lo, side, |c| {
            doubled |= self.leaf_of[cell_index(c)] == DOUBLED
        });
        if doubled {
            return false;
        }
        // No cell with surface (read off the brick's signs): settled
        // without building its boundary.
        let (mut masks, mut filled, mut simple) = (0u8, 0xffu8, true);
        for_cells(lo, side, |c| {
            let signs = self.signs[cell_index(c)];
            masks |= signs;
            filled &= signs;
            simple &= signs == 0 || signs == 0xff || ONE_COMPONENT[signs as usize];
        });
        if masks == 0 || filled == 0xff {
            return true;
        }
        if !simple {
            // A cell holding two sheets: never inside a leaf.
            return false;
        }
        let signs = (side, node_signs(lattice, lo, side));
        let known = recall(grid.mesh, &signs);
        let (crossings, loops) = match known {
            Some(Topology::Refused) => return false,
            Some(Topology::Uncrossed) => return true,
            Some(Topology::Sheets(loops)) => {
                // The same signs cross the same edges; where along them is
                // this node's own.
                let Some(boundary) = Boundary::from_lattice(lattice, base, lo, side) else {
                    return false;
                };
                (boundary.crossings(), loops)
            }
            None => {
                let (topology, crossings) = self.topology((base, lattice), (lo, side));
                remember(grid.mesh, signs, topology.clone());
                match topology {
                    Topology::Refused => return false,
                    Topology::Uncrossed => return true,
                    Topology::Sheets(loops) => (crossings, loops),
                }
            }
        };
        let mut sheets: Vec<Vec<Crossing>> = (0..loops.count).map(|_| Vec::new()).collect();
        for (c, &l) in crossings.into_iter().zip(&loops.of) {
            sheets[l as usize].push(c);
        }
        let id = self.leaves.len() as u16;
        for_cells(lo, side, |c| self.leaf_of[cell_index(c)] = id);
        self.leaves.push(InnerLeaf {
            lo,
            side,
            sheets,
            vertices: None,
            fitted: false,
            split: false,
        });
        true
    }

    /// What the signs at a node's corners decide (every cell's surface one
    /// component, see `try_candidate`), with the boundary's crossings.
    fn topology(
        &self,
        (base, lattice): ([usize; 3], &Lattice),
        (lo, side): ([usize; 3], usize),
    ) -> (Topology, Vec<Crossing>) {
        let Some(boundary) = Boundary::from_lattice(lattice, base, lo, side) else {
            return (Topology::Refused, Vec::new());
        };
        let crossings = boundary.crossings();
        if crossings.is_empty() {
            // Nothing crosses its boundary: whatever it holds its cells mesh
            // (a speck), no leaf would save work.
            return (Topology::Uncrossed, crossings);
        }
        let topology = match boundary.loops_of(&crossings) {
            Some(loops)
                if loops.count <= MOST_SHEETS
                    && discs_at_grid(
                        (lattice, &self.signs),
                        (base, lo, side),
                        &crossings,
                        &loops,
                    ) =>
            {
                Topology::Sheets(loops)
            }
            _ => Topology::Refused,
        };
        (topology, crossings)
    }

    /// The leaf whose cell `c` (local) is, where a leaf covers it.
    fn leaf_at(&self, c: [isize; 3]) -> Option<&InnerLeaf> {
        if self.leaves.is_empty() || c.iter().any(|&x| x < 0 || x >= B as isize) {
            return None;
        }
        match self.leaf_of[cell_index(c.map(|x| x as usize))] {
            NONE | DOUBLED => None,
            id => Some(&self.leaves[id as usize]),
        }
    }

    /// Whether the edge along `axis` from local corner `c` lies inside a
    /// leaf (all four of its cells in it), among the leaves `which` picks.
    fn inside_leaf(&self, axis: usize, c: [isize; 3], which: impl Fn(&InnerLeaf) -> bool) -> bool {
        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
        self.leaf_at(c).is_some_and(|leaf| {
            which(leaf) && c[u] > leaf.lo[u] as isize && c[w] > leaf.lo[w] as isize
        })
    }

    /// Whether an edge lies inside some candidate: left unsolved.
    pub(crate) fn interior(&self, axis: usize, c: [isize; 3]) -> bool {
        self.inside_leaf(axis, c, |_| true)
    }

    /// Fits the vertices (one per sheet) of every candidate not yet fitted
    /// to the planes the brick solved on its boundary. Returns whether any
    /// does not fit (see `split_failed`).
    pub(crate) fn fit(
        &mut self,
        tape: &Tape,
        grid: &Grid,
        base: [usize; 3],
        crossings: &Crossings,
        tolerances: (f64, f64),
    ) -> bool {
        let mut any_failed = false;
        // One buffer of planes for every sheet (a brick fits hundreds).
        let mut planes: Vec<Plane> = Vec::new();
        for leaf in self.leaves.iter_mut().filter(|leaf| !leaf.fitted) {
            let local = |c: [usize; 3]| std::array::from_fn(|k| (c[k] - base[k]) as isize);
            let global: [usize; 3] = std::array::from_fn(|k| base[k] + leaf.lo[k]);
            let node = (global, leaf.side);
            leaf.fitted = true;
            leaf.vertices = leaf
                .sheets
                .iter()
                .map(|sheet| {
                    planes.clear();
                    for c in sheet {
                        planes.push(*crossings.get(c.axis, local(c.corner))?);
                    }
                    fit_vertex(tape, grid, node, &planes, tolerances).map(|(x, _)| x)
                })
                .collect();
            any_failed |= leaf.vertices.is_none();
        }
        any_failed
    }

    /// Candidates that did not fit give their cells to their octants (each
    /// tried as a candidate in turn), or to the brick below 4 cells. Returns
    /// their nodes: the edges inside them that no candidate now holds are
    /// to be solved (see `exposed`).
    pub(crate) fn split_failed(
        &mut self,
        grid: &Grid,
        base: [usize; 3],
        lattice: &Lattice,
    ) -> Vec<([usize; 3], usize)> {
        let failed: Vec<usize> = (0..self.leaves.len())
            .filter(|&i| self.leaves[i].failed() && !self.leaves[i].split)
            .collect();
        let mut nodes = Vec::with_capacity(failed.len());
        for i in failed {
            self.leaves[i].split = true;
            let (lo, side) = (self.leaves[i].lo, self.leaves[i].side);
            nodes.push((lo, side));
            if side > 2 {
                for n in 0..8 {
                    self.try_candidate(grid, (base, lattice), (octant(lo, side / 2, n), side / 2));
                }
            }
        }
        nodes
    }

    /// Whether the edge along `axis` from local corner `c` lies inside one
    /// of `nodes` (all four of its cells in it) and inside no candidate that
    /// may still fit: left unsolved until now, it is to be solved.
    pub(crate) fn exposed(
        &self,
        nodes: &[([usize; 3], usize)],
        axis: usize,
        c: [isize; 3],
    ) -> bool {
        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
        let inside = |&(lo, side): &([usize; 3], usize)| {
            let (lo, hi) = (lo.map(|x| x as isize), lo.map(|x| (x + side) as isize));
            (0..3).all(|k| c[k] >= lo[k] && c[k] < hi[k]) && c[u] > lo[u] && c[w] > lo[w]
        };
        nodes.iter().any(inside) && !self.inside_leaf(axis, c, |leaf| !leaf.failed())
    }

    /// Whether a leaf with vertices covers local cell `c`.
    pub(crate) fn covers(&self, c: [usize; 3]) -> bool {
        self.leaf_at(c.map(|x| x as isize))
            .is_some_and(|leaf| leaf.vertices.is_some())
    }

    /// Adds each leaf's vertices and their references to the crossed edges
    /// of their sheet's loop on its boundary, in the slots of its cells.
    pub(crate) fn emit(
        &self,
        base: [usize; 3],
        out: &mut BrickOut,
        vertex_points: &mut Vec<[f64; 3]>,
    ) {
        for leaf in &self.leaves {
            let Some(vertices) = &leaf.vertices else {
                continue;
            };
            out.leaves += 1;
            let lo: [usize; 3] = std::array::from_fn(|k| base[k] + leaf.lo[k]);
            for (sheet, x) in leaf.sheets.iter().zip(vertices) {
                let vertex = out.positions.len() as u32;
                out.positions.push(Vec3::from_array(x.map(|c| c as f32)));
                vertex_points.push(*x);
                for c in sheet {
                    for (cell, slot) in cells_around(c.axis, c.corner) {
                        if (0..3).all(|a| cell[a] >= lo[a] && cell[a] < lo[a] + leaf.side) {
                            out.refs.push((
                                crossing_key(c.axis, c.corner, false),
                                slot,
                                vertex,
                                c.lower_inside,
                            ));
                        }
                    }
                }
            }
        }
    }
}

/// Whether the dual patch of the node's cells (local first cell `lo`,
/// `side` cells, in the brick from grid corner `base`; every cell's surface
/// one component, see `try_candidate`) is one disc per loop of its
/// boundary at the grid's resolution: the cells with surface connected
/// across faces with surface into one piece per loop (the cells beside
/// each loop's crossings in its piece), each with vertices - edges + faces
/// = 1.
fn discs_at_grid(
    (lattice, signs): (&Lattice, &[u8]),
    (base, lo, side): ([usize; 3], [usize; 3], usize),
    crossings: &[Crossing],
    loops: &Loops,
) -> bool {
    PATCH.with(|patch| {
        let patch = &mut patch.borrow_mut();
        patch.build((lattice, signs), lo, side);
        patch.one_piece_per_loop(base, crossings, loops) && patch.pieces_are_discs()
    })
}

thread_local! {
    /// A patch's buffers, reused from node to node (a brick tries
    /// hundreds; fresh ones were one in ten of the mesher's allocations,
    /// colonnade at depth 6).
    static PATCH: std::cell::RefCell<Patch> = std::cell::RefCell::default();
}

/// The dual patch of a node's cells: its vertices (cells with surface),
/// edges (crossed faces between them) and faces (crossed edges inside the
/// node), and its connected pieces.
#[derive(Default)]
struct Patch {
    lo: [usize; 3],
    side: usize,
    surface: Vec<bool>,
    parent: Vec<usize>,
    /// A cell of each edge and of each face of the patch.
    edges: Vec<usize>,
    faces: Vec<usize>,
    /// Each piece's Euler characteristic, at its root.
    euler: Vec<i64>,
    piece_of_loop: Vec<usize>,
}

impl Patch {
    fn build(&mut self, (lattice, signs): (&Lattice, &[u8]), lo: [usize; 3], side: usize) {
        let inside = |c: [usize; 3]| lattice.at(c.map(|x| x as isize)) >= 0.0;
        let n = side * side * side;
        let patch = self;
        (patch.lo, patch.side) = (lo, side);
        patch.surface.clear();
        patch.surface.resize(n, false);
        patch.parent.clear();
        patch.parent.extend(0..n);
        patch.edges.clear();
        patch.faces.clear();
        patch.euler.clear();
        patch.euler.resize(n, 0);
        for_cells(lo, side, |c| {
            let signs = signs[cell_index(c)];
            let at = patch.local(c);
            patch.surface[at] = signs != 0 && signs != 0xff;
        });
        for_cells(lo, side, |c| {
            let here = patch.local(c);
            if !patch.surface[here] {
                return;
            }
            for axis in 0..3 {
                // The face towards the next cell along `axis`, and the edge
                // along `axis` from this cell's lowest corner.
                let mut next = c;
                next[axis] += 1;
                if next[axis] < lo[axis] + side
                    && patch.surface[patch.local(next)]
                    && face_crossed(&inside, next, axis)
                {
                    let there = patch.local(next);
                    patch.edges.push(here);
                    union(&mut patch.parent, here, there);
                }
                let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
                if c[u] > lo[u] && c[w] > lo[w] && inside(c) != inside(next) {
                    patch.faces.push(here);
                }
            }
        });
    }

    fn local(&self, c: [usize; 3]) -> usize {
        let (lo, side) = (self.lo, self.side);
        (c[0] - lo[0]) + side * ((c[1] - lo[1]) + side * (c[2] - lo[2]))
    }

    /// Whether each loop's crossings lie beside cells of one piece, and
    /// each piece is one loop's.
    fn one_piece_per_loop(
        &mut self,
        base: [usize; 3],
        crossings: &[Crossing],
        loops: &Loops,
    ) -> bool {
        let mut piece_of_loop = std::mem::take(&mut self.piece_of_loop);
        piece_of_loop.clear();
        piece_of_loop.resize(loops.count, usize::MAX);
        let one_each = self.pieces_of_loops(&mut piece_of_loop, base, crossings, loops);
        self.piece_of_loop = piece_of_loop;
        one_each
    }

    /// `one_piece_per_loop` with its buffer: each loop's piece in
    /// `piece_of_loop` (all `usize::MAX` on entry).
    fn pieces_of_loops(
        &mut self,
        piece_of_loop: &mut Vec<usize>,
        base: [usize; 3],
        crossings: &[Crossing],
        loops: &Loops,
    ) -> bool {
        let (lo, side) = (self.lo, self.side);
        for (c, &l) in crossings.iter().zip(&loops.of) {
            let Some(cell) = cells_around(c.axis, c.corner).find_map(|(cell, _)| {
                let at: [usize; 3] = std::array::from_fn(|k| cell[k].wrapping_sub(base[k]));
                (0..3)
                    .all(|k| at[k] >= lo[k] && at[k] < lo[k] + side)
                    .then_some(at)
            }) else {
                return false;
            };
            let at = self.local(cell);
            let piece = find(&mut self.parent, at);
            match piece_of_loop[l as usize] {
                usize::MAX => piece_of_loop[l as usize] = piece,
                p if p != piece => return false,
                _ => {}
            }
        }
        let pieces = (0..self.surface.len())
            .filter(|&i| self.surface[i] && find(&mut self.parent, i) == i)
            .count();
        piece_of_loop.sort_unstable();
        piece_of_loop.dedup();
        piece_of_loop.len() == loops.count && pieces == loops.count
    }

    /// Whether every piece has Euler characteristic 1 (a disc).
    fn pieces_are_discs(&mut self) -> bool {
        let euler = &mut self.euler;
        for i in 0..self.surface.len() {
            if self.surface[i] {
                euler[find(&mut self.parent, i)] += 1;
            }
        }
        for &i in &self.edges {
            euler[find(&mut self.parent, i)] -= 1;
        }
        for &i in &self.faces {
            euler[find(&mut self.parent, i)] += 1;
        }
        (0..self.surface.len())
            .filter(|&i| self.surface[i] && self.parent[i] == i)
            .all(|i| euler[i] == 1)
    }
}

/// The corners of local cell `c` inside (bit k: corner k, x fastest).
fn cell_signs(lattice: &Lattice, c: [usize; 3]) -> u8 {
    (0..8).fold(0, |m, k| {
        let corner = [c[0] + (k & 1), c[1] + (k >> 1 & 1), c[2] + (k >> 2 & 1)];
        m | ((lattice.at(corner.map(|x| x as isize)) >= 0.0) as u8) << k
    })
}

/// [`one_component`] of every sign pattern.
static ONE_COMPONENT: std::sync::LazyLock<[bool; 256]> =
    std::sync::LazyLock::new(|| std::array::from_fn(|s| one_component(s as u8)));

/// Whether the face of the cube at corner `c` normal to `axis` has both
/// signs at its corners.
fn face_crossed(inside: &impl Fn([usize; 3]) -> bool, c: [usize; 3], axis: usize) -> bool {
    let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
    let at = |du: usize, dw: usize| {
        let mut p = c;
        p[u] += du;
        p[w] += dw;
        inside(p)
    };
    let first = at(0, 0);
    [at(1, 0), at(1, 1), at(0, 1)].iter().any(|&s| s != first)
}

/// Whether a cell's corner signs (bit k: corner k, x fastest) make one
/// surface component: no face with alternating corners, and one connected
/// set of inside corners and one of outside corners along the cube's
/// edges (on the cube's surface, a sphere, loops = regions - 1).
fn one_component(signs: u8) -> bool {
    let at = |k: usize| signs >> k & 1;
    if FACES
        .iter()
        .any(|(f, _)| at(f[0]) == at(f[2]) && at(f[1]) == at(f[3]) && at(f[0]) != at(f[1]))
    {
        return false;
    }
    let mut parent: [usize; 8] = std::array::from_fn(|k| k);
    for k in 0..8 {
        for bit in [1, 2, 4] {
            let m = k | bit;
            if m != k && at(k) == at(m) {
                union(&mut parent, k, m);
            }
        }
    }
    let regions = (0..8).filter(|&k| find(&mut parent, k) == k).count();
    regions == 2
}

fn for_cells(lo: [usize; 3], side: usize, mut f: impl FnMut([usize; 3])) {
    for k in lo[2]..lo[2] + side {
        for j in lo[1]..lo[1] + side {
            for i in lo[0]..lo[0] + side {
                f([i, j, k]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geode_frep::eval::BatchEval;
    use geode_frep::field::Field;

    /// A leaf as its node and its sheets' crossed edges (and, with
    /// `positions`, where along them), for comparing candidates.
    type LeafShape = ([usize; 3], usize, Vec<Vec<(usize, [usize; 3], bool, u32)>>);

    fn shapes(leaves: &InnerLeaves, positions: bool) -> Vec<LeafShape> {
        let edge = |c: &Crossing| {
            let at = if positions { c.at.to_bits() } else { 0 };
            (c.axis, c.corner, c.lower_inside, at)
        };
        let sheets = |l: &InnerLeaf| {
            l.sheets
                .iter()
                .map(|s| s.iter().map(edge).collect())
                .collect()
        };
        leaves
            .leaves
            .iter()
            .map(|l| (l.lo, l.side, sheets(l)))
            .collect()
    }

    /// The bricks of a 4 x 4 x 4 grid of bricks over [-1, 1]^3, each with
    /// its lattice, for `field`.
    fn bricks(field: &Field, mesh: u64) -> (Grid, Vec<([usize; 3], Lattice)>) {
        let h = 2.0 / (4 * B) as f64;
        let grid = Grid {
            origin: [-1.0; 3],
            h,
            corners: [4 * B + 1; 3],
            bricks: [4; 3],
            mesh,
        };
        let tape = Tape::compile(field);
        let mut batch = BatchEval::new(&tape);
        let mut out = Vec::new();
        for n in 0..64 {
            let base = [n % 4, n / 4 % 4, n / 16].map(|b| b * B);
            out.push((base, Lattice::sample(&mut batch, &grid, base)));
        }
        (grid, out)
    }

    /// A topology as comparable parts: refused, uncrossed, or the loop of
    /// each crossing.
    fn describe(t: &Topology) -> (u8, Vec<u8>) {
        match t {
            Topology::Refused => (0, Vec::new()),
            Topology::Uncrossed => (1, Vec::new()),
            Topology::Sheets(loops) => (2 + loops.count as u8, loops.of.clone()),
        }
    }

    /// Candidates with the memo of node topologies (nodes whose signs were
    /// met before, in this brick, in earlier bricks, or in the same brick
    /// read again) are those read afresh; every remembered topology is the
    /// one worked out from a lattice of nothing but its signs (the memo's
    /// premise); and the lattice's values scaled by a varying positive
    /// factor give the same nodes crossed on the same edges.
    #[test]
    fn remembered_node_topologies_give_the_same_candidates() {
        let (x, y, z) = (Field::x(), Field::y(), Field::z());
        let ball = Field::constant(0.7) - (&x * &x + &y * &y + &z * &z).sqrt();
        let waves = (&x * 5.0).sin() + (&y * 4.0).sin() * 0.8 - &z * 2.0;
        let column = Field::constant(0.3) - (&x * &x + &y * &y).sqrt();
        let (mut leaves, mut remembered) = (0, 0);
        for (k, field) in [ball, waves, column].iter().enumerate() {
            let (grid, bricks) = bricks(field, u64::MAX - k as u64);
            for (base, lattice) in &bricks {
                let first = InnerLeaves::candidates(&grid, *base, lattice, &[]);
                let again = InnerLeaves::candidates(&grid, *base, lattice, &[]);
                assert_eq!(shapes(&again, true), shapes(&first, true), "brick {base:?}");
                leaves += first.leaves.len();
                let mut scaled = Lattice {
                    base: lattice.base,
                    values: lattice.values.clone(),
                };
                for (i, v) in scaled.values.iter_mut().enumerate() {
                    *v *= 1.0 + 0.9 * ((i * 7919) % 13) as f32 / 13.0;
                }
                let other = InnerLeaves::candidates(&grid, *base, &scaled, &[]);
                assert_eq!(shapes(&other, false), shapes(&first, false));
            }
            let known = crate::node_memo::remembered();
            remembered += known.len();
            for ((side, words), topology) in known {
                let mut lattice = Lattice {
                    base: [0; 3],
                    values: vec![-1.0; L * L * L],
                };
                let mut bit = 0;
                for_cells([0; 3], side + 1, |c| {
                    let inside = words[bit / 64] >> (bit % 64) & 1 == 1;
                    lattice.values[lattice_index(c.map(|x| x as isize))] =
                        if inside { 1.0 } else { -1.0 };
                    bit += 1;
                });
                let mut signs = vec![0u8; B * B * B];
                for_cells([0; 3], B, |c| {
                    signs[cell_index(c)] = cell_signs(&lattice, c)
                });
                let afresh = InnerLeaves {
                    leaf_of: vec![NONE; B * B * B],
                    leaves: Vec::new(),
                    signs,
                };
                let (want, _) = afresh.topology(([0; 3], &lattice), ([0; 3], side));
                assert_eq!(describe(&topology), describe(&want), "side {side}");
            }
        }
        assert!(leaves > 100 && remembered > 100, "{leaves} {remembered}");
    }

    fn signs(inside: &[usize]) -> u8 {
        inside.iter().fold(0, |m, &k| m | 1 << k)
    }

    /// One corner, an edge, a face and all but one corner inside are one
    /// sheet each; corners alternating on a face, or opposite across the
    /// cell, are two.
    #[test]
    fn one_component_tells_one_sheet_from_two() {
        for one in [
            &[0][..],
            &[0, 1],
            &[0, 1, 2, 3],
            &[0, 1, 2, 3, 4, 5, 6],
            &[0, 1, 3],
        ] {
            assert!(one_component(signs(one)), "{one:?}");
        }
        for two in [&[0, 3][..], &[0, 7], &[0, 5], &[1, 2, 4, 7]] {
            assert!(!one_component(signs(two)), "{two:?}");
        }
    }
}
