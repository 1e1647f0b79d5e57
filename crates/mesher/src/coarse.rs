//! Coarse leaves of the adaptive octree (adaptive output, top-down): an
//! octree node of one or more bricks whose surface one vertex represents
//! within the tolerance is meshed as that vertex alone, without sampling
//! its inside. Two proofs make that safe:
//! - the node's gradient bounds (interval arithmetic, see
//!   `geode_frep::IntervalGradEval`, one box per smooth piece where a
//!   `min` or `max` may go either way) leave some direction along which
//!   the field rises everywhere, so each line along it crosses the surface
//!   at most once: the surface is a graph over a plane (no bubble, fold or
//!   second sheet), creases and corners included;
//! - the grid corners on the node's boundary, signed as every brick signs
//!   them, cut it along exactly one loop, so the graph is one disc; that
//!   loop crosses each face in one arc at most and each edge of the node
//!   once at most, so no neighbour shares two stretches of it (which would
//!   give an edge of the mesh a third triangle once the disc is a point).
//!
//! Its vertex is the QEF's point over the boundary crossings' planes, kept
//! only within the tolerance of every plane and of the surface (so a
//! corner or crease of the node is its vertex); the tolerance of the final
//! mesh is then made good by `refine`, as for every adaptive mesh.
//! The node then stands for all its cells, as a merged cell does inside a
//! brick (`cluster`): it refers its one vertex to every crossed grid edge
//! on its boundary, in the slots of its cells around that edge, and the
//! quads that neighbours make there lose the node's repeated corner.

use crate::brick::BrickOut;
use crate::cell::{crossing_key, find, union, Grid, Plane};
use crate::features::{smooth_on_surface, CellBox};
use crate::lattice::{outward_normal, outward_normals, snap_to_surface, Lattice, SNAP};
use crate::qef::Qef;
use geode_frep::eval::{BatchEval, BatchGradEval, GradEval, PointEval};
use geode_frep::interval::Interval;
use geode_frep::interval_grad::{GradBox, IntervalGradEval};
use geode_frep::tape::Tape;
use geode_geo::glam::Vec3;

/// The largest leaf, in cells a side.
pub(crate) const LARGEST: usize = 32;

/// The node of `side` cells from cell `lo` as one vertex, or None where
/// the proofs above fail or no vertex fits every crossing's plane within
/// `tolerance` (the caller subdivides). An empty output where the boundary
/// shows no crossing: a graph surface cannot close inside.
pub(crate) fn coarse_leaf(
    tape: &Tape,
    grid: &Grid,
    (lo, side): ([usize; 3], usize),
    (sharpness, tolerance): (f64, f64),
) -> Option<BrickOut> {
    if (0..3).any(|a| lo[a] + side >= grid.corners[a])
        || !one_sheet(&mut IntervalGradEval::new(tape), grid, (lo, side))
    {
        return None;
    }
    let boundary = Boundary::sample(tape, grid, lo, side)?;
    let crossings = boundary.crossings();
    let mut out = BrickOut::default();
    if crossings.is_empty() {
        return Some(out);
    }
    if boundary.loops() != 1 || !boundary.meets_faces_once() {
        return None;
    }
    let planes = interpolated_planes(tape, grid, &crossings);
    let (vertex, normal) = fit_vertex(tape, grid, (lo, side), &planes, (sharpness, tolerance))?;
    for c in &crossings {
        for (cell, slot) in cells_around(c.axis, c.corner) {
            if (0..3).all(|a| cell[a] >= lo[a] && cell[a] < lo[a] + side) {
                let key = crossing_key(c.axis, c.corner, false);
                out.refs.push((key, slot, 0, c.lower_inside));
            }
        }
    }
    out.positions
        .push(Vec3::from_array(vertex.map(|x| x as f32)));
    out.normals.push(Vec3::from_array(normal.map(|x| x as f32)));
    out.leaves = 1;
    Some(out)
}

/// Whether some direction has a positive slope everywhere in the node, on
/// every smooth piece of the field that may decide where it is zero: then
/// at every zero along a line in that direction the field rises, so the
/// line crosses the surface at most once. Tried: the mean of the pieces' directions,
/// then each piece's own.
pub(crate) fn one_sheet(
    eval: &mut IntervalGradEval,
    grid: &Grid,
    (lo, side): ([usize; 3], usize),
) -> bool {
    let (a, b) = (grid.point(lo), grid.point(lo.map(|x| x + side)));
    let g = eval.eval(
        Interval::new(a[0], b[0]),
        Interval::new(a[1], b[1]),
        Interval::new(a[2], b[2]),
    );
    // Only pieces that may decide where the field is zero (or within the
    // snap below it, which corners read as on the surface) can cross it.
    let level = -(SNAP * grid.h);
    let pieces: Vec<GradBox> = g
        .pieces()
        .iter()
        .filter(|p| p.v.lo <= 0.0 && p.v.hi >= level)
        .map(|p| p.d)
        .collect();
    if pieces
        .iter()
        .flatten()
        .any(|d| !(d.lo.is_finite() && d.hi.is_finite()))
    {
        return false;
    }
    let unit = |v: [f64; 3]| {
        let len = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        (len > 0.0).then(|| v.map(|x| x / len))
    };
    let centres: Vec<[f64; 3]> = pieces
        .iter()
        .filter_map(|p| unit(p.map(|d| 0.5 * (d.lo + d.hi))))
        .collect();
    let mean = unit(std::array::from_fn(|k| centres.iter().map(|c| c[k]).sum()));
    // The least slope along n over a piece's box.
    let rises = |n: [f64; 3]| {
        pieces.iter().all(|p| {
            (0..3)
                .map(|k| (n[k] * p[k].lo).min(n[k] * p[k].hi))
                .sum::<f64>()
                > 0.0
        })
    };
    mean.into_iter().chain(centres.iter().copied()).any(rises)
}

/// The planes of a node's boundary crossings, placed by linear
/// interpolation along their edges (exact on planar faces).
fn interpolated_planes(tape: &Tape, grid: &Grid, crossings: &[Crossing]) -> Vec<Plane> {
    let points: Vec<[f64; 3]> = crossings
        .iter()
        .map(|c| {
            let mut p = grid.point(c.corner);
            p[c.axis] += c.at as f64 * grid.h;
            p
        })
        .collect();
    let normals = outward_normals(
        &mut PointEval::new(tape),
        &mut BatchGradEval::new(tape),
        &points,
    );
    points.into_iter().zip(normals).collect()
}

/// A node's vertex: the QEF's point over its boundary crossings' planes
/// (on the node's crease or corner where it has one), taken onto the
/// surface where the planes show no feature; None unless it lies in the
/// node, within `tolerance` of every plane and of the surface.
pub(crate) fn fit_vertex(
    tape: &Tape,
    grid: &Grid,
    (lo, side): ([usize; 3], usize),
    planes: &[Plane],
    (sharpness, tolerance): (f64, f64),
) -> Option<([f64; 3], [f64; 3])> {
    let mut qef = Qef::default();
    for (p, n) in planes {
        qef.add(*p, *n);
    }
    let solver = qef.solver();
    let rank = solver.rank(sharpness);
    let mut x = solver.solve(rank);
    let node = CellBox {
        lo: grid.point(lo),
        hi: grid.point(lo.map(|x| x + side)),
    };
    if !node.contains(&x) {
        return None;
    }
    let mut grad = GradEval::new(tape);
    if rank <= 1 {
        x = smooth_on_surface(&qef, Some(x), &node, &mut grad, grid.h);
    }
    let g = grad.eval(x);
    let slope = g.d.iter().map(|d| d * d).sum::<f64>().sqrt();
    let off_plane =
        |(p, n): &Plane| -> f64 { (0..3).map(|k| n[k] * (x[k] - p[k])).sum::<f64>().abs() };
    let fits = planes.iter().all(|pn| off_plane(pn) <= tolerance);
    (fits && slope > 0.0 && (g.v / slope).abs() <= tolerance)
        .then(|| (x, outward_normal(&mut PointEval::new(tape), g.d, x)))
}

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
    fn sample(tape: &Tape, grid: &Grid, lo: [usize; 3], side: usize) -> Option<Boundary> {
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

    /// Whether the surface meets each face in at most one arc and each of
    /// the node's edges at most once: then a neighbour (a leaf, a merged
    /// cell or a cell) shares one stretch of the node's loop at most, so
    /// no edge of the mesh gains a third triangle when the node becomes
    /// one vertex. On a face (a disc), arcs = sign regions - 1.
    pub(crate) fn meets_faces_once(&self) -> bool {
        let s = self.side;
        let n = s + 1;
        let mut parent: Vec<usize> = Vec::with_capacity(n * n);
        for axis in 0..3 {
            let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
            for plane in [0, s] {
                let at = |i: usize, j: usize| {
                    let mut c = [0; 3];
                    c[axis] = plane;
                    c[u] = i;
                    c[w] = j;
                    self.inside(c)
                };
                parent.clear();
                parent.extend(0..n * n);
                for j in 0..n {
                    for i in 0..n {
                        let here = at(i, j);
                        if i + 1 < n && at(i + 1, j) == here {
                            union(&mut parent, i + n * j, i + 1 + n * j);
                        }
                        if j + 1 < n && at(i, j + 1) == here {
                            union(&mut parent, i + n * j, i + n * (j + 1));
                        }
                    }
                }
                let regions = (0..n * n).filter(|&i| find(&mut parent, i) == i).count();
                if regions > 2 {
                    return false;
                }
            }
            // The four edges of the node along `axis`.
            for (a, b) in [(0, 0), (s, 0), (0, s), (s, s)] {
                let at = |t: usize| {
                    let mut c = [0; 3];
                    c[axis] = t;
                    c[u] = a;
                    c[w] = b;
                    self.inside(c)
                };
                if (0..s).filter(|&t| at(t) != at(t + 1)).count() > 1 {
                    return false;
                }
            }
        }
        true
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

    /// The loops along which the surface cuts the boundary: on a sphere,
    /// disjoint loops leave one more region than loops, and the regions
    /// are the connected sets of boundary corners of one sign.
    pub(crate) fn loops(&self) -> usize {
        let n = self.side + 1;
        let mut parent: Vec<usize> = (0..n * n * n).collect();
        self.for_edges(|axis, c| {
            let mut d = c;
            d[axis] += 1;
            if self.inside(c) == self.inside(d) {
                union(&mut parent, self.index(c), self.index(d));
            }
        });
        let mut regions = 0usize;
        for_boundary_corners(self.side, |c| {
            let i = self.index(c);
            if find(&mut parent, i) == i {
                regions += 1;
            }
        });
        regions.saturating_sub(1)
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
    /// a slab in two loops; a surface dipping through the bottom face
    /// twice (a ridge standing on it) in one loop but two arcs there.
    #[test]
    fn loops_and_arcs_on_a_node_s_boundary() {
        let plane = boundary(|c| c[0] + c[1] + 2 * c[2] < 6);
        assert_eq!(plane.loops(), 1);
        assert!(plane.meets_faces_once());
        let slab = boundary(|c| c[2] == 2);
        assert_eq!(slab.loops(), 2);
        let ridge = boundary(|c| c[0] == 2 && c[2] < 3);
        assert_eq!(ridge.loops(), 1);
        assert!(!ridge.meets_faces_once());
        let crossings = plane.crossings();
        assert!(!crossings.is_empty());
        assert!(crossings.iter().all(|c| (0.0..=1.0).contains(&c.at)));
    }
}
