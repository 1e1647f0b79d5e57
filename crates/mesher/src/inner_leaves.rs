//! Coarse leaves inside a brick (adaptive output, top-down, below the
//! octree's `coarse` leaves, which cannot see inside a node and so need a
//! proof from interval arithmetic): the brick, or else its octants of 4
//! cells, or else theirs of 2, where the surface the brick's lattice shows
//! is one disc (one loop on the node's boundary; inside, every cell one
//! component and the dual patch connected with Euler characteristic 1)
//! are candidates, and one whose vertex fits its boundary's planes within
//! the tolerance is meshed as that vertex alone: contracting a disc to a
//! point keeps the mesh closed and manifold (Ju et al.'s criterion, read
//! top-down on the signs instead of bottom-up on every cell's vertex).
//! Their inner edges are never solved and their cells never placed; the
//! vertex stands in every slot
//! its cells hold around the crossed edges of its boundary, where the
//! brick's own quads (or the global sort, on the brick's faces) lose its
//! repeated corner. A candidate whose vertex does not fit its planes
//! within the tolerance gives its cells back to the brick, which then
//! solves their edges; cells beside an edge crossed twice are never in one.

use crate::brick::BrickOut;
use crate::cell::{crossing_key, find, union, Grid, Plane, B, FACES};
use crate::coarse::{cells_around, fit_vertex, Boundary, Crossing};
use crate::lattice::{slot_edge, Crossings, Lattice, Root};
use geode_frep::tape::Tape;
use geode_geo::glam::Vec3;

const NONE: u16 = u16::MAX;
/// A cell beside an edge crossed twice.
const DOUBLED: u16 = u16::MAX - 1;

struct InnerLeaf {
    /// First cell, local to the brick.
    lo: [usize; 3],
    side: usize,
    crossings: Vec<Crossing>,
    /// Its vertex once it fits; None for a candidate that gave its cells back.
    vertex: Option<[f64; 3]>,
}

/// The leaves of one brick and the cells they cover.
pub(crate) struct InnerLeaves {
    /// Per cell of the brick (x fastest): the leaf covering it, or NONE.
    leaf_of: Vec<u16>,
    leaves: Vec<InnerLeaf>,
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
        let mut leaves = InnerLeaves {
            leaf_of: vec![NONE; B * B * B],
            leaves: Vec::new(),
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
        let Some(boundary) = Boundary::from_lattice(lattice, base, lo, side) else {
            return false;
        };
        let crossings = boundary.crossings();
        if crossings.is_empty() {
            // Nothing crosses its boundary: whatever it holds its cells mesh
            // (a speck), no leaf would save work.
            return true;
        }
        if boundary.loops() != 1 || !boundary.meets_faces_once() || !disc_at_grid(lattice, lo, side)
        {
            return false;
        }
        let id = self.leaves.len() as u16;
        for_cells(lo, side, |c| self.leaf_of[cell_index(c)] = id);
        self.leaves.push(InnerLeaf {
            lo,
            side,
            crossings,
            vertex: None,
        });
        true
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

    /// Fits every candidate's vertex to the planes the brick solved on its
    /// boundary; those that do not fit give their cells back. Returns
    /// whether any did (their inner edges are then to be solved: see
    /// `given_back_interior`).
    pub(crate) fn fit(
        &mut self,
        tape: &Tape,
        grid: &Grid,
        base: [usize; 3],
        crossings: &Crossings,
        tolerances: (f64, f64),
    ) -> bool {
        let mut any_back = false;
        for leaf in &mut self.leaves {
            let local = |c: [usize; 3]| std::array::from_fn(|k| (c[k] - base[k]) as isize);
            let planes: Option<Vec<Plane>> = leaf
                .crossings
                .iter()
                .map(|c| crossings.get(c.axis, local(c.corner)).copied())
                .collect();
            let global: [usize; 3] = std::array::from_fn(|k| base[k] + leaf.lo[k]);
            let node = (global, leaf.side);
            leaf.vertex = planes.and_then(|planes| {
                fit_vertex(tape, grid, node, &planes, tolerances).map(|(x, _)| x)
            });
            any_back |= leaf.vertex.is_none();
        }
        any_back
    }

    /// Whether an edge lies inside a candidate that gave its cells back.
    pub(crate) fn given_back_interior(&self, axis: usize, c: [isize; 3]) -> bool {
        self.inside_leaf(axis, c, |leaf| leaf.vertex.is_none())
    }

    /// Whether a leaf with a vertex covers local cell `c`.
    pub(crate) fn covers(&self, c: [usize; 3]) -> bool {
        self.leaf_at(c.map(|x| x as isize))
            .is_some_and(|leaf| leaf.vertex.is_some())
    }

    /// Adds each leaf's vertex and its references to the crossed edges of
    /// its boundary, in the slots of its cells.
    pub(crate) fn emit(
        &self,
        base: [usize; 3],
        out: &mut BrickOut,
        vertex_points: &mut Vec<[f64; 3]>,
    ) {
        for leaf in &self.leaves {
            let Some(x) = leaf.vertex else { continue };
            let vertex = out.positions.len() as u32;
            out.leaves += 1;
            out.positions.push(Vec3::from_array(x.map(|c| c as f32)));
            vertex_points.push(x);
            let lo: [usize; 3] = std::array::from_fn(|k| base[k] + leaf.lo[k]);
            for c in &leaf.crossings {
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

/// Whether the dual patch of the node's cells (local first cell `lo`,
/// `side` cells) is one disc at the grid's resolution, given one loop on
/// its boundary: every cell's surface one component, no face with its
/// corners alternating, the cells with surface connected across faces
/// with surface, and vertices - edges + faces = 1.
fn disc_at_grid(lattice: &Lattice, lo: [usize; 3], side: usize) -> bool {
    let inside = |c: [usize; 3]| lattice.at(c.map(|x| x as isize)) >= 0.0;
    let n = side * side * side;
    let local = |c: [usize; 3]| (c[0] - lo[0]) + side * ((c[1] - lo[1]) + side * (c[2] - lo[2]));
    let mut parent: Vec<usize> = (0..n).collect();
    let mut surface = vec![false; n];
    let (mut vertices, mut edges, mut faces) = (0i64, 0i64, 0i64);
    let mut simple = true;
    for_cells(lo, side, |c| {
        let signs: u8 = (0..8).fold(0, |m, k| {
            m | (inside([c[0] + (k & 1), c[1] + (k >> 1 & 1), c[2] + (k >> 2 & 1)]) as u8) << k
        });
        if signs != 0 && signs != 255 {
            simple &= one_component(signs);
            surface[local(c)] = true;
            vertices += 1;
        }
    });
    if !simple {
        return false;
    }
    for_cells(lo, side, |c| {
        if !surface[local(c)] {
            return;
        }
        for axis in 0..3 {
            // The face towards the next cell along `axis`, and the edges
            // along `axis` from this cell's lowest corner.
            let mut next = c;
            next[axis] += 1;
            if next[axis] < lo[axis] + side
                && surface[local(next)]
                && face_crossed(&inside, next, axis)
            {
                edges += 1;
                union(&mut parent, local(c), local(next));
            }
            let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
            let mut far = c;
            far[axis] += 1;
            if c[u] > lo[u] && c[w] > lo[w] && inside(c) != inside(far) {
                faces += 1;
            }
        }
    });
    let roots = (0..n)
        .filter(|&i| surface[i] && find(&mut parent, i) == i)
        .count();
    roots == 1 && vertices - edges + faces == 1
}

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
    use super::one_component;

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
