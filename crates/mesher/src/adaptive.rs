//! Adaptive output, in three stages: bricks merge cells whose surface one
//! coarser vertex represents within the tolerance (`cluster`, during
//! meshing); edges where the mesh strays beyond it are flipped or split
//! (`refine`); then half-edge collapses (`geode_geo::ops::reduce_triangles`)
//! remove vertices wherever the field says every changed triangle stays
//! within it. Collapsing onto existing vertices keeps each kept vertex where
//! the QEF put it (on the surface, on its sharp edge or corner) with its
//! normal. The field is read per brick with the brick's simplified tape;
//! the measure is the first-order distance `|f| / |∇f|`, public as
//! [`crate::surface_distances`] so any mesh can be held to it (`surface`).

use geode_geo::glam::Vec3;
use geode_geo::ops::{compact_vertices, reduce_triangles, ReduceOptions};

use crate::refine::refine;
pub(crate) use crate::surface::RegionTapes;
use crate::surface::{field_distances, Mesh};

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
pub(crate) fn compact(
    positions: &mut Vec<Vec3>,
    normals: &mut Vec<Vec3>,
    triangles: &mut [[u32; 3]],
) {
    let kept = compact_vertices(positions.len(), triangles);
    *positions = kept.iter().map(|&v| positions[v as usize]).collect();
    *normals = kept.iter().map(|&v| normals[v as usize]).collect();
}
