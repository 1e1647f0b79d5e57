//! Adaptive output, in stages: bricks merge cells whose surface one
//! coarser vertex represents within the tolerance (`coarse`,
//! `inner_leaves`, `cluster`, during meshing); then half-edge collapses
//! (`geode_geo::ops::reduce_triangles`) remove vertices wherever the field
//! says every changed triangle stays within it, and refinement flips or
//! splits the edges where the mesh strays beyond it (`refine`), measuring
//! every edge and triangle it is given. Collapsing onto existing vertices
//! keeps each kept vertex where the QEF put it (on the surface, on its
//! sharp edge or corner) with its normal.
//!
//! The order depends on the tolerance (see `REDUCE_FIRST`): from half a
//! cell, vertices off the surface move onto it, the mesh is reduced, and
//! the reduced mesh (a tenth of the triangles: colonnade at depth 6,
//! 5,192 in, 340 out) is refined, so every edge and triangle of the output
//! is measured at a tenth of the cost; below, or where refining the reduced
//! mesh cannot bring it within the tolerance, creases are straightened
//! (`crease`) and the grid's mesh refined first, then reduced. The field is
//! read per brick with the brick's simplified tape; the measure is the
//! first-order distance `|f| / |∇f|`, public as
//! [`crate::surface_distances`] so any mesh can be held to it (`surface`).

use geode_geo::glam::Vec3;
use geode_geo::ops::{compact_vertices, reduce_triangles, ReduceOptions};

use crate::crease::straighten_creases;
use crate::refine::{onto_surface, refine};
pub(crate) use crate::surface::RegionTapes;
use crate::surface::{field_distances, Mesh};

/// What adapting a mesh did.
pub(crate) struct Adapted {
    pub splits: usize,
    pub collapses: usize,
    pub crease_flips: usize,
    /// The largest deviation measured on the final mesh.
    pub deviation: f64,
}

/// Tolerances (in cells) from which the mesh is reduced before it is
/// refined: dual contouring's own error is a few hundredths of a cell (a
/// zig-zag across a curved crease a few tenths), so the mesh the bricks
/// give rarely strays that far and refinement has little to mend once
/// reduced (colonnade at depths 6 and 7: nothing; the bear: a few edges).
/// Below, the grid's mesh is straightened and refined first (flips across
/// creases free the collapses a box needs to come out as twelve triangles
/// at a thousandth of a cell).
const REDUCE_FIRST: f64 = 0.5;

/// Adaptive output after the mesher merged cells (see the module doc):
/// at tolerances of half a cell and more, reduced first and refined after
/// where the reduced mesh strays; otherwise, or where that cannot bring it
/// within `tolerance`, the mesh as the bricks gave it is straightened and
/// refined first and reduced after. `None` when cancelled.
pub(crate) fn adapt(
    tapes: &RegionTapes,
    (positions, normals, triangles): Mesh,
    (tolerance, cell): (f64, f64),
    cancel: &(dyn Fn() -> bool + Sync),
) -> Option<Adapted> {
    compact(positions, normals, triangles);
    if tolerance >= REDUCE_FIRST * cell {
        let fine = (positions.clone(), normals.clone(), triangles.clone());
        let reduced_first =
            reduce_then_refine(tapes, (positions, normals, triangles), tolerance, cancel)?;
        if reduced_first.deviation <= tolerance {
            return Some(reduced_first);
        }
        (*positions, *normals, *triangles) = fine;
    }
    let crease_flips = straighten_creases(tapes, positions, triangles, cell, cancel);
    let refined = refine(tapes, (positions, normals, triangles), tolerance, cancel)?;
    let collapses = reduce(tapes, (positions, normals, triangles), tolerance, cancel)?;
    Some(Adapted {
        splits: refined.splits,
        collapses,
        crease_flips,
        deviation: refined.deviation,
    })
}

/// The fast order: vertices onto the surface, collapses, then refinement
/// of what the reduced mesh (a tenth of the triangles) leaves beyond the
/// tolerance, measuring every edge and triangle of the output. Its
/// `deviation` exceeds the tolerance where refinement could not mend it (a
/// wall thinner than a coarse triangle, whose splits land on the far
/// side).
fn reduce_then_refine(
    tapes: &RegionTapes,
    (positions, normals, triangles): Mesh,
    tolerance: f64,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Option<Adapted> {
    onto_surface(tapes, positions, normals, triangles, tolerance);
    let collapses = reduce(tapes, (positions, normals, triangles), tolerance, cancel)?;
    let refined = refine(tapes, (positions, normals, triangles), tolerance, cancel)?;
    Some(Adapted {
        splits: refined.splits,
        collapses,
        crease_flips: 0,
        deviation: refined.deviation,
    })
}

/// Collapses wherever the field allows (see the module doc); returns how
/// many.
fn reduce(
    tapes: &RegionTapes,
    (positions, normals, triangles): Mesh,
    tolerance: f64,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Option<usize> {
    let measure = |points: &[Vec3], out: &mut [f32]| field_distances(tapes, points, out);
    let options = ReduceOptions::new(tolerance);
    let reduced = reduce_triangles(positions, triangles, &options, &measure, cancel).ok()?;
    *triangles = reduced.triangles;
    compact(positions, normals, triangles);
    Some(reduced.collapses)
}

/// Drops the vertices no triangle uses, keeping the others' order.
pub(crate) fn compact(
    positions: &mut Vec<Vec3>,
    normals: &mut Vec<Vec3>,
    triangles: &mut [[u32; 3]],
) {
    let kept = compact_vertices(positions.len(), triangles);
    *positions = kept.iter().map(|&v| positions[v as usize]).collect();
    *normals = kept.iter().map(|&v| normals[v as usize]).collect();
}
