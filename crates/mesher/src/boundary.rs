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

/// The signed values of the grid corners on a node's boundary.
pub(crate) struct Boundary {
    lo: [usize; 3],
    side: usize,
    /// Over the node's (side + 1)^3 corners; only the boundary's are set.
    values: Vec<f32>,
}

impl Boundary {
    /// Samples the boundary's corners as a brick's lattice does (same
    /// coordinates in f32, same snapping), so both sides of a face agree.
    /// None where a boundary face's corners alternate in sign (its pairing
    /// belongs to the neighbour's centre test; such nodes subdivide).
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
        let mut values = vec![f32::NAN; n * n * n];
        for (i, v) in at.into_iter().zip(sampled) {
            values[i] = v;
        }
        let boundary = Boundary { lo, side, values };
        (!boundary.has_ambiguous_face()).then_some(boundary)
    }

    /// The boundary of a node inside a brick from the brick's lattice
    /// (`lo` local to it, `base` the brick's first corner).
    pub(crate) fn from_lattice(
        lattice: &Lattice,
        base: [usize; 3],
        lo: [usize; 3],
        side: usize,
    ) -> Option<Boundary> {
        let n = side + 1;
        let mut values = vec![f32::NAN; n * n * n];
        for_boundary_corners(side, |c| {
            let at: [isize; 3] = std::array::from_fn(|k| (lo[k] + c[k]) as isize);
            values[c[0] + n * (c[1] + n * c[2])] = lattice.at(at);
        });
        let global = std::array::from_fn(|k| base[k] + lo[k]);
        let boundary = Boundary {
            lo: global,
            side,
            values,
        };
        (!boundary.has_ambiguous_face()).then_some(boundary)
    }

    fn index(&self, c: [usize; 3]) -> usize {
        let n = self.side + 1;
        c[0] + n * (c[1] + n * c[2])
    }

    fn inside(&self, c: [usize; 3]) -> bool {
        self.values[self.index(c)] >= 0.0
    }

    fn on_boundary(&self, c: [usize; 3]) -> bool {
        c.iter().any(|&x| x == 0 || x == self.side)
    }

    /// Calls `f` with every pair of neighbouring boundary corners (local),
    /// each once: the grid edges lying on the boundary, by axis and lower
    /// corner.
    pub(crate) fn for_edges(&self, mut f: impl FnMut(usize, [usize; 3])) {
        for_boundary_corners(self.side, |c| {
            for axis in 0..3 {
                let mut d = c;
                d[axis] += 1;
                if d[axis] <= self.side && self.on_boundary(d) {
                    f(axis, c);
                }
            }
        });
    }

    pub(crate) fn crossings(&self) -> Vec<Crossing> {
        let mut out = Vec::new();
        self.for_edges(|axis, c| {
            let mut d = c;
            d[axis] += 1;
            let (a, b) = (self.values[self.index(c)], self.values[self.index(d)]);
            if (a >= 0.0) != (b >= 0.0) {
                out.push(Crossing {
                    axis,
                    corner: std::array::from_fn(|k| self.lo[k] + c[k]),
                    at: (a / (a - b)).clamp(0.0, 1.0),
                    lower_inside: a >= 0.0,
                });
            }
        });
        out
    }

    /// Whether some square of the boundary has its corners alternating in sign.
    fn has_ambiguous_face(&self) -> bool {
        let s = self.side;
        (0..3).any(|axis| {
            let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
            [0, s].into_iter().any(|plane| {
                (0..s).any(|i| {
                    (0..s).any(|j| {
                        let corner = |di: usize, dj: usize| {
                            let mut c = [0; 3];
                            c[axis] = plane;
                            c[u] = i + di;
                            c[w] = j + dj;
                            self.inside(c)
                        };
                        let (a, b, c, d) = (corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1));
                        a == c && b == d && a != b
                    })
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
        let mut faces = FaceRegions::new(self);
        let mut links: Vec<(usize, usize)> = Vec::new();
        let mut of = Vec::with_capacity(crossings.len());
        let mut arcs: Vec<(usize, u8, usize, usize)> = Vec::new();
        for c in crossings {
            let a: [usize; 3] = std::array::from_fn(|k| c.corner[k] - self.lo[k]);
            let mut b = a;
            b[c.axis] += 1;
            let (inside, outside) = if self.inside(a) { (a, b) } else { (b, a) };
            let link = (faces.region(inside), faces.region(outside));
            let id = links.iter().position(|l| *l == link).unwrap_or_else(|| {
                links.push(link);
                links.len() - 1
            });
            let id = u8::try_from(id).ok()?;
            of.push(id);
            // The arc it lies on, on each face holding it.
            for f in faces.holding(c.axis, a) {
                arcs.push((f, id, faces.local(f, inside), faces.local(f, outside)));
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
        self.node_edges_once(crossings, &loops).then_some(loops)
    }

    /// Whether each loop crosses each of the node's twelve edges once at most.
    fn node_edges_once(&self, crossings: &[Crossing], loops: &Loops) -> bool {
        let s = self.side;
        let mut seen: Vec<(usize, usize, usize, u8)> = crossings
            .iter()
            .zip(&loops.of)
            .filter_map(|(c, &l)| {
                let (u, w) = ((c.axis + 1) % 3, (c.axis + 2) % 3);
                let local: [usize; 3] = std::array::from_fn(|k| c.corner[k] - self.lo[k]);
                let on_edge = [0, s].contains(&local[u]) && [0, s].contains(&local[w]);
                on_edge.then_some((c.axis, local[u], local[w], l))
            })
            .collect();
        let all = seen.len();
        seen.sort_unstable();
        seen.dedup();
        seen.len() == all
    }
}

/// The loop each crossing of a node's boundary lies on.
pub(crate) struct Loops {
    pub count: usize,
    /// Per crossing, its loop (0..count).
    pub of: Vec<u8>,
}

/// The regions of each face of a node's boundary (corners of one sign
/// joined along the face's grid edges), and the same glued along the
/// node's edges into the boundary's.
struct FaceRegions {
    side: usize,
    /// Per face (axis * 2 + far side) and corner of it (u fastest), the
    /// root of its region on that face alone.
    local: Vec<usize>,
    /// The union-find of the faces' corners, glued where faces meet.
    glued: Vec<usize>,
}

impl FaceRegions {
    fn new(b: &Boundary) -> FaceRegions {
        let s = b.side;
        let n = s + 1;
        let mut parent: Vec<usize> = (0..6 * n * n).collect();
        for f in 0..6 {
            let (axis, plane) = (f / 2, (f % 2) * s);
            let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
            let at = |i: usize, j: usize| {
                let mut c = [0; 3];
                c[axis] = plane;
                c[u] = i;
                c[w] = j;
                b.inside(c)
            };
            let base = f * n * n;
            for j in 0..n {
                for i in 0..n {
                    let here = at(i, j);
                    if i + 1 < n && at(i + 1, j) == here {
                        union(&mut parent, base + i + n * j, base + i + 1 + n * j);
                    }
                    if j + 1 < n && at(i, j + 1) == here {
                        union(&mut parent, base + i + n * j, base + i + n * (j + 1));
                    }
                }
            }
        }
        let local: Vec<usize> = (0..6 * n * n).map(|i| find(&mut parent, i)).collect();
        let mut regions = FaceRegions {
            side: s,
            local,
            glued: parent,
        };
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
                    let (x, y) = (regions.slot(fu, c), regions.slot(fw, c));
                    union(&mut regions.glued, x, y);
                }
            }
        }
        regions
    }

    /// Corner `c`'s index on face `f`.
    fn slot(&self, f: usize, c: [usize; 3]) -> usize {
        let n = self.side + 1;
        let axis = f / 2;
        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
        f * n * n + c[u] + n * c[w]
    }

    /// The faces holding the edge along `axis` from corner `c` (both on the boundary).
    fn holding(&self, axis: usize, c: [usize; 3]) -> impl Iterator<Item = usize> + '_ {
        (0..6).filter(move |&f| f / 2 != axis && c[f / 2] == (f % 2) * self.side)
    }

    /// Corner `c`'s region on the boundary.
    fn region(&mut self, c: [usize; 3]) -> usize {
        let f = (0..6)
            .find(|&f| c[f / 2] == (f % 2) * self.side)
            .unwrap_or(0);
        let slot = self.slot(f, c);
        find(&mut self.glued, slot)
    }

    /// Corner `c`'s region on face `f` alone.
    fn local(&self, f: usize, c: [usize; 3]) -> usize {
        self.local[self.slot(f, c)]
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
    use super::{for_boundary_corners, Boundary};

    /// The boundary of a node of 4 cells signed by `inside` at local corners.
    fn boundary(inside: impl Fn([usize; 3]) -> bool) -> Boundary {
        let side = 4;
        let n = side + 1;
        let mut values = vec![f32::NAN; n * n * n];
        for_boundary_corners(side, |c| {
            values[c[0] + n * (c[1] + n * c[2])] = if inside(c) { 1.0 } else { -1.0 };
        });
        Boundary {
            lo: [0; 3],
            side,
            values,
        }
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
