//! Adaptive output, in three stages: bricks merge cells whose surface one
//! coarser vertex represents within the tolerance (`cluster`, during
//! meshing); edges where the mesh strays beyond it are flipped or split
//! (`refine`); then half-edge collapses (`geode_geo::ops::reduce_triangles`)
//! remove vertices wherever the field says every changed triangle stays
//! within it. Collapsing onto existing vertices keeps each kept vertex where
//! the QEF put it (on the surface, on its sharp edge or corner) with its
//! normal. The field is read per brick with the brick's simplified tape;
//! the measure is the first-order distance `|f| / |∇f|`, public as
//! [`surface_distances`] so any mesh can be held to it.

use geode_geo::glam::Vec3;
use geode_geo::ops::{compact_vertices, reduce_triangles, ReduceOptions};
use rayon::prelude::*;

use crate::eval::{BatchGradEval, Grad};
use crate::refine::refine;
use crate::tape::Tape;

/// A mesh being changed: positions, normals, triangles.
pub(crate) type Mesh<'a> = (&'a mut Vec<Vec3>, &'a mut Vec<Vec3>, &'a mut Vec<[u32; 3]>);

/// The tapes the mesher simplified for each brick (each valid inside its
/// brick's box) and the field's whole tape for points outside every brick.
pub(crate) struct RegionTapes<'a> {
    pub root: &'a Tape,
    /// Brick coordinates as (z, y, x), ascending, with their tapes.
    pub bricks: Vec<([usize; 3], &'a Tape)>,
    pub origin: [f64; 3],
    /// A brick's side in model units.
    pub brick_side: f64,
}

impl RegionTapes<'_> {
    /// The index of the brick holding `p`, or `u32::MAX` for the root tape.
    pub(crate) fn brick_of(&self, p: Vec3) -> u32 {
        let c: [f64; 3] =
            std::array::from_fn(|k| ((p[k] as f64 - self.origin[k]) / self.brick_side).floor());
        if c.iter().any(|x| !(*x >= 0.0 && *x < u32::MAX as f64)) {
            return u32::MAX;
        }
        let key = [c[2] as usize, c[1] as usize, c[0] as usize];
        self.bricks
            .binary_search_by(|b| b.0.cmp(&key))
            .map_or(u32::MAX, |i| i as u32)
    }

    fn tape(&self, brick: u32) -> &Tape {
        self.bricks.get(brick as usize).map_or(self.root, |b| b.1)
    }
}

/// Values and gradients at `points`, each evaluated with its brick's
/// simplified tape (points grouped by brick, groups in parallel).
pub(crate) fn grads_at(tapes: &RegionTapes, points: &[Vec3]) -> Vec<Grad> {
    let mut order: Vec<(u32, u32)> = points
        .par_iter()
        .enumerate()
        .map(|(i, p)| (tapes.brick_of(*p), i as u32))
        .collect();
    order.par_sort_unstable();
    let sorted: Vec<Vec<Grad>> = order
        .par_chunk_by(|a, b| a.0 == b.0)
        .map_init(
            // Made for the first group's tape (the root tape's registers
            // would be far more than a brick's needs).
            || (None::<BatchGradEval>, Vec::new()),
            |(eval, at), group| {
                let tape = tapes.tape(group[0].0);
                let eval = match eval {
                    Some(e) => {
                        e.set_tape(tape);
                        e
                    }
                    None => eval.insert(BatchGradEval::new(tape)),
                };
                at.clear();
                at.extend(
                    group
                        .iter()
                        .map(|&(_, i)| points[i as usize].as_dvec3().to_array()),
                );
                let mut grads = vec![Grad::default(); group.len()];
                eval.eval(at, &mut grads);
                grads
            },
        )
        .collect();
    let mut out = vec![Grad::default(); points.len()];
    for ((_, i), g) in order.iter().zip(sorted.into_iter().flatten()) {
        out[*i as usize] = g;
    }
    out
}

/// Newton steps of a walk to the surface.
const WALK_STEPS: usize = 3;

/// Where each point's walk along the gradient reaches the surface (Newton
/// steps `x - f ∇f / |∇f|²`, each evaluated with the tape of the brick it
/// is in), from the points and their values and gradients; returns the
/// feet with theirs.
pub(crate) fn walk_to_surface(
    tapes: &RegionTapes,
    points: &[Vec3],
    at_points: &[Grad],
) -> (Vec<Vec3>, Vec<Grad>) {
    let mut feet = points.to_vec();
    let mut grads = at_points.to_vec();
    for _ in 0..WALK_STEPS {
        feet.par_iter_mut()
            .zip(&grads)
            .for_each(|(x, g)| *x = newton(*x, g));
        grads = grads_at(tapes, &feet);
    }
    (feet, grads)
}

/// One Newton step toward `f = 0` along the gradient (none where it vanishes).
fn newton(x: Vec3, g: &Grad) -> Vec3 {
    let d = geode_geo::glam::DVec3::from_array(g.d);
    let slope = d.length_squared();
    if slope > 0.0 && g.v.is_finite() {
        (x.as_dvec3() - d * (g.v / slope)).as_vec3()
    } else {
        x
    }
}

/// How far each point is from the surface of the field `tape` computes,
/// to first order: `|f| / |∇f|` (exact on a distance field; on others it
/// can read a few times too far or too near where the gradient turns, in
/// smooth blends). The measure adaptive output keeps within its tolerance,
/// public so a mesh from any mesher can be held to the same yardstick.
pub fn surface_distances(tape: &Tape, points: &[Vec3]) -> Vec<f32> {
    let whole = RegionTapes {
        root: tape,
        bricks: Vec::new(),
        origin: [0.0; 3],
        brick_side: 1.0,
    };
    let mut out = vec![0.0; points.len()];
    field_distances(&whole, points, &mut out);
    out
}

/// `|f| / |∇f|` at each point, with its brick's tape.
pub(crate) fn field_distances(tapes: &RegionTapes, points: &[Vec3], out: &mut [f32]) {
    for (o, g) in out.iter_mut().zip(grads_at(tapes, points)) {
        *o = distance_estimate(&g).abs();
    }
}

pub(crate) fn distance_estimate(g: &Grad) -> f32 {
    let slope = (g.d[0] * g.d[0] + g.d[1] * g.d[1] + g.d[2] * g.d[2]).sqrt();
    if slope > 0.0 && g.v.is_finite() {
        (g.v / slope) as f32
    } else {
        f32::INFINITY
    }
}

/// Adaptive output after the mesher merged cells: unused vertices dropped,
/// edges split where the mesh strays beyond `tolerance` (see `refine`),
/// then collapsed wherever the field allows. Returns (splits, collapses,
/// the largest deviation measured after splitting); `None` when cancelled.
pub(crate) fn adapt(
    tapes: &RegionTapes,
    (positions, normals, triangles): Mesh,
    tolerance: f64,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Option<(usize, usize, f64)> {
    compact(positions, normals, triangles);
    let refined = refine(tapes, (positions, normals, triangles), tolerance, cancel)?;
    let measure = |points: &[Vec3], out: &mut [f32]| field_distances(tapes, points, out);
    let reduced = reduce_triangles(
        positions,
        triangles,
        &ReduceOptions::new(tolerance),
        &measure,
        cancel,
    )
    .ok()?;
    *triangles = reduced.triangles;
    compact(positions, normals, triangles);
    Some((refined.splits, reduced.collapses, refined.deviation))
}

/// Drops the vertices no triangle uses, keeping the others' order.
fn compact(positions: &mut Vec<Vec3>, normals: &mut Vec<Vec3>, triangles: &mut [[u32; 3]]) {
    let kept = compact_vertices(positions.len(), triangles);
    *positions = kept.iter().map(|&v| positions[v as usize]).collect();
    *normals = kept.iter().map(|&v| normals[v as usize]).collect();
}
