//! A node's boundary as the grid corners on it show it (adaptive output's
//! leaves, `coarse` and `inner_leaves`): its crossed edges, and the loops
//! along which the surface cuts it. A node may stand for its cells as one
//! vertex per loop when each loop crosses every face of the node in one arc
//! at most and each edge of the node at most once: then a neighbour (a
//! leaf, a merged cell or a cell) shares one stretch of a loop at most, so
//! no edge of the mesh gains a third triangle once each loop's disc is a
//! point.

use crate::cell::{find, union, Grid};
use crate::lattice::{snap_to_surface, Lattice};
use geode_frep::eval::BatchEval;
use geode_frep::tape::Tape;

/// A crossed grid edge on a node's boundary.
pub(crate) struct Crossing {
    pub axis: usize,
    /// The edge's lower corner (grid).
    pub corner: [usize; 3],
    /// Where along the edge (0 to 1) the linear interpolation crosses.
    pub at: f32,
    pub lower_inside: bool,
}

/// The signed values of the grid corners on a node's boundary, face by
/// face: face `f` is normal to axis `f / 2`, at the node's near (`f` even)
/// or far side, its corners indexed `i + n j` along the next axis (`i`)
/// and the one after (`j`), `n` corners a side. A corner on an edge of the
/// node is in two faces (three at a corner of the node), with one value.
pub(crate) struct Boundary {
    lo: [usize; 3],
    side: usize,
    values: Vec<f32>,
}

/// The local corner of face `f` at `(i, j)`.
fn face_corner(f: usize, side: usize, i: usize, j: usize) -> [usize; 3] {
    let axis = f / 2;
    let mut c = [0; 3];
    c[axis] = (f % 2) * side;
    c[(axis + 1) % 3] = i;
    c[(axis + 2) % 3] = j;
    c
}

impl Boundary {
    /// The boundary with each corner's value from `value` (local corner),
    /// or None where a face's square has its corners alternating in sign
    /// (its pairing belongs to the neighbour's centre test; such nodes
    /// subdivide).
    fn new(lo: [usize; 3], side: usize, value: impl Fn([usize; 3]) -> f32) -> Option<Boundary> {
        let n = side + 1;
        let mut values = SPARE_VALUES.with(|spare| spare.take());
        values.clear();
        for f in 0..6 {
            for j in 0..n {
                for i in 0..n {
                    values.push(value(face_corner(f, side, i, j)));
                }
            }
        }
        let boundary = Boundary { lo, side, values };
        (!boundary.has_ambiguous_face()).then_some(boundary)
    }

    /// Samples the boundary's corners as a brick's lattice does (same
    /// coordinates in f32, same snapping), so both sides of a face agree.
    pub(crate) fn sample(
        tape: &Tape,
        grid: &Grid,
        lo: [usize; 3],
        side: usize,
    ) -> Option<Boundary> {
        let n = side + 1;
        let mut at = Vec::new();
        let (mut xs, mut ys, mut zs) = (Vec::new(), Vec::new(), Vec::new());
        for_boundary_corners(side, |c| {
            at.push(c[0] + n * (c[1] + n * c[2]));
            let g: [usize; 3] = std::array::from_fn(|k| lo[k] + c[k]);
            xs.push(grid.coordinate(0, g[0] as isize) as f32);
            ys.push(grid.coordinate(1, g[1] as isize) as f32);
            zs.push(grid.coordinate(2, g[2] as isize) as f32);
        });
        let mut sampled = vec![0.0f32; at.len()];
        BatchEval::new(tape).eval(&xs, &ys, &zs, &mut sampled);
        snap_to_surface(&mut sampled, grid.h);
        let mut cube = vec![f32::NAN; n * n * n];
        for (i, v) in at.into_iter().zip(sampled) {
            cube[i] = v;
        }
        Boundary::new(lo, side, |c| cube[c[0] + n * (c[1] + n * c[2])])
    }

    /// The boundary of a node inside a brick from the brick's lattice
    /// (`lo` local to it, `base` the brick's first corner).
    pub(crate) fn from_lattice(
        lattice: &Lattice,
        base: [usize; 3],
        lo: [usize; 3],
        side: usize,
    ) -> Option<Boundary> {
        let global = std::array::from_fn(|k| base[k] + lo[k]);
        Boundary::new(global, side, |c| {
            lattice.at(std::array::from_fn(|k| (lo[k] + c[k]) as isize))
        })
    }

    fn n(&self) -> usize {
        self.side + 1
    }

    /// The slot of local corner `c` on face `f` (which holds it).
    fn slot(&self, f: usize, c: [usize; 3]) -> usize {
        let (n, axis) = (self.n(), f / 2);
        f * n * n + c[(axis + 1) % 3] + n * c[(axis + 2) % 3]
    }

    /// The faces holding local corner `c`.
    fn faces_of(&self, c: [usize; 3]) -> impl Iterator<Item = usize> + '_ {
        (0..6).filter(move |&f| c[f / 2] == (f % 2) * self.side)
    }

    fn inside(&self, c: [usize; 3]) -> bool {
        let f = self.faces_of(c).next().unwrap_or(0);
        self.values[self.slot(f, c)] >= 0.0
    }

    /// Calls `f(axis, lower corner (grid), value there, value at the
    /// other end)` for every grid edge on the boundary, each once: face by
    /// face, along the face's two axes, an edge on an edge of the node taken
    /// from the first face holding it.
    pub(crate) fn for_edges(&self, mut f: impl FnMut(usize, [usize; 3], f32, f32)) {
        let (n, s) = (self.n(), self.side);
        for face in 0..6 {
            let axis = face / 2;
            let values = &self.values[face * n * n..(face + 1) * n * n];
            for (along, step) in [((axis + 1) % 3, 1), ((axis + 2) % 3, n)] {
                // The face's other axis: an edge at its ends lies on an
                // edge of the node, also held by the face normal to it.
                let across = 3 - axis - along;
                let shared = 2 * across;
                for j in 0..n {
                    for i in 0..n {
                        let (along_at, across_at) = if step == 1 { (i, j) } else { (j, i) };
                        if along_at == s {
                            continue;
                        }
                        let on_node_edge = across_at == 0 || across_at == s;
                        let other = shared + (across_at == s) as usize;
                        if on_node_edge && other < face {
                            continue;
                        }
                        let at = i + n * j;
                        let c = face_corner(face, s, i, j);
                        let corner = std::array::from_fn(|k| self.lo[k] + c[k]);
                        f(along, corner, values[at], values[at + step]);
                    }
                }
            }
        }
    }

    /// The crossed grid edges on the boundary, each once (see `for_edges`).
    pub(crate) fn crossings(&self) -> Vec<Crossing> {
        let mut out = Vec::new();
        self.for_edges(|axis, corner, a, b| {
            if (a >= 0.0) != (b >= 0.0) {
                out.push(Crossing {
                    axis,
                    corner,
                    at: (a / (a - b)).clamp(0.0, 1.0),
                    lower_inside: a >= 0.0,
                });
            }
        });
        out
    }

    /// Whether some square of the boundary has its corners alternating in sign.
    fn has_ambiguous_face(&self) -> bool {
        let n = self.n();
        (0..6).any(|f| {
            let inside = |i: usize, j: usize| self.values[f * n * n + i + n * j] >= 0.0;
            (0..n - 1).any(|j| {
                (0..n - 1).any(|i| {
                    let (a, b, c, d) = (
                        inside(i, j),
                        inside(i + 1, j),
                        inside(i + 1, j + 1),
                        inside(i, j + 1),
                    );
                    a == c && b == d && a != b
                })
            })
        })
    }

    /// The loops along which the surface cuts the boundary, as the loop
    /// each of `crossings` (this boundary's, in order) lies on; None where a
    /// loop meets a face in two arcs or more, or an edge of the node twice.
    /// The boundary is a sphere: the connected sets of its corners of one
    /// sign (regions) form a tree whose links are the loops, so a crossing
    /// lies on the loop between its ends' regions. On a face (a disc) the
    /// same holds for arcs and the face's own regions; the boundary's
    /// regions are the faces' glued along the node's edges.
    pub(crate) fn loops_of(&self, crossings: &[Crossing]) -> Option<Loops> {
        SCRATCH.with(|scratch| self.loops_in(crossings, &mut scratch.borrow_mut()))
    }

    fn loops_in(&self, crossings: &[Crossing], scratch: &mut LoopScratch) -> Option<Loops> {
        let LoopScratch {
            local,
            glued,
            links,
            arcs,
            seen,
        } = scratch;
        self.face_regions(local, glued);
        links.clear();
        arcs.clear();
        let mut of = Vec::with_capacity(crossings.len());
        for c in crossings {
            let a: [usize; 3] = std::array::from_fn(|k| c.corner[k] - self.lo[k]);
            let mut b = a;
            b[c.axis] += 1;
            let (inside, outside) = if self.inside(a) { (a, b) } else { (b, a) };
            let mut region = |c: [usize; 3]| {
                let f = self.faces_of(c).next().unwrap_or(0);
                find(glued, self.slot(f, c))
            };
            let link = (region(inside), region(outside));
            let id = links.iter().position(|l| *l == link).unwrap_or_else(|| {
                links.push(link);
                links.len() - 1
            });
            let id = u8::try_from(id).ok()?;
            of.push(id);
            // The arc it lies on, on each face holding it.
            for f in self.faces_of(a).filter(|f| f / 2 != c.axis) {
                let (x, y) = (self.slot(f, inside), self.slot(f, outside));
                arcs.push((f, id, find(local, x), find(local, y)));
            }
        }
        arcs.sort_unstable();
        arcs.dedup();
        if arcs
            .windows(2)
            .any(|w| (w[0].0, w[0].1) == (w[1].0, w[1].1))
        {
            return None;
        }
        let loops = Loops {
            count: links.len(),
            of,
        };
        self.node_edges_once(crossings, &loops, seen)
            .then_some(loops)
    }

    /// Whether each loop crosses each of the node's twelve edges once at most.
    fn node_edges_once(
        &self,
        crossings: &[Crossing],
        loops: &Loops,
        seen: &mut Vec<(usize, usize, usize, u8)>,
    ) -> bool {
        let s = self.side;
        seen.clear();
        seen.extend(crossings.iter().zip(&loops.of).filter_map(|(c, &l)| {
            let (u, w) = ((c.axis + 1) % 3, (c.axis + 2) % 3);
            let local: [usize; 3] = std::array::from_fn(|k| c.corner[k] - self.lo[k]);
            let on_edge = [0, s].contains(&local[u]) && [0, s].contains(&local[w]);
            on_edge.then_some((c.axis, local[u], local[w], l))
        }));
        let all = seen.len();
        seen.sort_unstable();
        seen.dedup();
        seen.len() == all
    }

    /// The regions of each face (corners of one sign joined along the
    /// face's grid edges) as a union-find over the faces' slots in `local`,
    /// and the same glued along the node's edges into the boundary's
    /// regions in `glued`.
    fn face_regions(&self, local: &mut Vec<usize>, glued: &mut Vec<usize>) {
        let (s, n) = (self.side, self.n());
        let inside = |at: usize| self.values[at] >= 0.0;
        local.clear();
        local.extend(0..6 * n * n);
        for f in 0..6 {
            let base = f * n * n;
            for j in 0..n {
                for i in 0..n {
                    let at = base + i + n * j;
                    // A run along i shares its start's root; rows join
                    // where they touch (once per pair of runs that meet).
                    if i > 0 && inside(at - 1) == inside(at) {
                        local[at] = local[at - 1];
                    }
                    let meets_row_below = j > 0 && inside(at - n) == inside(at);
                    let joined_left = meets_row_below
                        && i > 0
                        && inside(at - 1) == inside(at)
                        && inside(at - 1 - n) == inside(at);
                    if meets_row_below && !joined_left {
                        union(local, at, at - n);
                    }
                }
            }
        }
        glued.clear();
        glued.extend_from_slice(local);
        // Each corner on a node edge lies on two faces (three at a node's
        // corner, which two of its edges join).
        for axis in 0..3 {
            let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
            for (p, q) in [(0, 0), (s, 0), (0, s), (s, s)] {
                for t in 0..=s {
                    let mut c = [0; 3];
                    c[axis] = t;
                    c[u] = p;
                    c[w] = q;
                    let (fu, fw) = (2 * u + (p == s) as usize, 2 * w + (q == s) as usize);
                    union(glued, self.slot(fu, c), self.slot(fw, c));
                }
            }
        }
    }
}

/// The loop each crossing of a node's boundary lies on.
#[derive(Clone)]
pub(crate) struct Loops {
    pub count: usize,
    /// Per crossing, its loop (0..count).
    pub of: Vec<u8>,
}

/// Buffers `loops_of` reuses from node to node (a brick tries hundreds;
/// fresh ones were one in nine of the mesher's allocations, colonnade at
/// depth 6).
#[derive(Default)]
struct LoopScratch {
    local: Vec<usize>,
    glued: Vec<usize>,
    links: Vec<(usize, usize)>,
    arcs: Vec<(usize, u8, usize, usize)>,
    seen: Vec<(usize, usize, usize, u8)>,
}

thread_local! {
    static SCRATCH: std::cell::RefCell<LoopScratch> = std::cell::RefCell::default();
    /// A dropped boundary's values, for the next (a brick reads hundreds).
    static SPARE_VALUES: std::cell::Cell<Vec<f32>> = const { std::cell::Cell::new(Vec::new()) };
}

impl Drop for Boundary {
    fn drop(&mut self) {
        SPARE_VALUES.with(|spare| spare.set(std::mem::take(&mut self.values)));
    }
}

/// Calls `f` with each corner on the surface of a node of `side` cells
/// (local, x fastest): whole planes at the ends of z, rows at the ends of
/// y, two corners per row between.
fn for_boundary_corners(side: usize, mut f: impl FnMut([usize; 3])) {
    for k in 0..=side {
        for j in 0..=side {
            let step = if j == 0 || j == side || k == 0 || k == side {
                1
            } else {
                side
            };
            let mut i = 0;
            while i <= side {
                f([i, j, k]);
                i += step;
            }
        }
    }
}

/// The four cells around a grid edge with their slots (counter-clockwise
/// about +axis, as `cell::CELL_EDGES` numbers them); None below the grid.
pub(crate) fn cells_around(axis: usize, c: [usize; 3]) -> impl Iterator<Item = ([usize; 3], u8)> {
    let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
    // (steps down along u and w, slot)
    [((1, 1), 0u8), ((0, 1), 1), ((0, 0), 2), ((1, 0), 3)]
        .into_iter()
        .filter_map(move |((du, dw), slot)| {
            let mut cell = c;
            cell[u] = c[u].checked_sub(du)?;
            cell[w] = c[w].checked_sub(dw)?;
            Some((cell, slot))
        })
}

#[cfg(test)]
mod tests {
    use super::Boundary;

    /// The boundary of a node of 4 cells signed by `inside` at local corners.
    fn boundary(inside: impl Fn([usize; 3]) -> bool) -> Boundary {
        Boundary::new([0; 3], 4, |c| if inside(c) { 1.0 } else { -1.0 }).unwrap()
    }

    /// A tilted plane cuts the boundary in one loop, each face in one arc;
    /// a slab in two loops, each face it crosses in one arc of each; a
    /// surface dipping through the bottom face twice (a ridge standing on
    /// it) in one loop but two arcs there.
    #[test]
    fn loops_and_arcs_on_a_node_s_boundary() {
        let loops = |b: &Boundary| b.loops_of(&b.crossings()).map(|l| l.count);
        let plane = boundary(|c| c[0] + c[1] + 2 * c[2] < 6);
        assert_eq!(loops(&plane), Some(1));
        let slab = boundary(|c| c[2] == 2);
        assert_eq!(loops(&slab), Some(2));
        let of = slab.loops_of(&slab.crossings()).unwrap().of;
        assert!(of.contains(&0) && of.contains(&1));
        let ridge = boundary(|c| c[0] == 2 && c[2] < 3);
        assert_eq!(loops(&ridge), None);
        let crossings = plane.crossings();
        assert!(!crossings.is_empty());
        assert!(crossings.iter().all(|c| (0.0..=1.0).contains(&c.at)));
    }
}
