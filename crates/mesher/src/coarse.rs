//! Coarse leaves of the adaptive octree (adaptive output, top-down): an
//! octree node of one or more bricks whose surface one vertex represents
//! within the tolerance is meshed as that vertex alone, without sampling
//! its inside. Three checks make that safe:
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
//!   give an edge of the mesh a third triangle once the disc is a point);
//! - no grid edge on the boundary is crossed twice (each searched as
//!   bricks search theirs, see `double::any_crossed_twice`): a neighbouring
//!   brick would mesh such an edge through quads the node, seeing no
//!   crossing there, leaves open (a cone's rim poking past a grid edge).
//!
//! Its vertex is the QEF's point over the boundary crossings' planes, kept
//! only within the tolerance of every plane and of the surface (so a
//! corner or crease of the node is its vertex); the tolerance of the final
//! mesh is then made good by `refine`, as for every adaptive mesh.
//! The node then stands for all its cells, as a merged cell does inside a
//! brick (`cluster`): it refers its one vertex to every crossed grid edge
//! on its boundary, in the slots of its cells around that edge, and the
//! quads that neighbours make there lose the node's repeated corner.

use crate::boundary::{cells_around, Boundary, Crossing};
use crate::brick::BrickOut;
use crate::cell::{crossing_key, Grid, Plane};
use crate::double::any_crossed_twice;
use crate::features::{smooth_on_surface, CellBox};
use crate::lattice::{outward_normal, outward_normals, SNAP};
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
    if !crossings.is_empty() && boundary.loops_of(&crossings)?.count != 1 {
        return None;
    }
    // A neighbouring brick meshes an edge of this boundary crossed twice
    // through quads that a node meshed whole would leave open (searched
    // last: it costs samples, the checks above none).
    let mut edges = Vec::new();
    boundary.for_edges(|axis, corner, a, b| edges.push((axis, corner, a, b)));
    if any_crossed_twice(&mut BatchEval::new(tape), grid, &edges) {
        return None;
    }
    let mut out = BrickOut::default();
    if crossings.is_empty() {
        return Some(out);
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
    let [x, y, z] = std::array::from_fn(|k| Interval::new(a[k], b[k]));
    // Only pieces that may decide where the field is zero (or within the
    // snap below it, which corners read as on the surface) can cross it;
    // one without a bound on its slope fails the proof, and plain
    // intervals find many such nodes first, at a fifth of the cost (one in
    // three of colonnade's bricks at depth 6, where a brick holds a
    // column's axis; they had cost a third of its octree's time).
    let level = -(SNAP * grid.h);
    let may_cross = |v: Interval| v.lo <= 0.0 && v.hi >= level;
    if eval.unbounded_values(x, y, z).is_some_and(may_cross) {
        return false;
    }
    let g = eval.eval(x, y, z);
    let pieces: Vec<GradBox> = g
        .pieces()
        .iter()
        .filter(|p| may_cross(p.v))
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
