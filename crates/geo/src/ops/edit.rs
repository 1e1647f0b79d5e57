//! Structural edits: delete points or primitives, drop unused points, reverse winding.

use crate::geometry::{Geometry, PrimKind};
use crate::group::Group;

/// Keeps the primitives whose flag is true; everything stays consistent
/// (vertex and primitive attributes, groups, packed instances).
fn keep_prims(g: &mut Geometry, keep: &[bool]) {
    keep_where(g, keep, None);
}

/// Keeps the flagged primitives and, of those, the flagged vertices.
fn keep_where(g: &mut Geometry, keep: &[bool], keep_vertex: Option<&[bool]>) {
    let mut vertex_keep: Vec<u32> = Vec::new();
    let mut prim_keep: Vec<u32> = Vec::new();
    let mut offsets = vec![0u32];
    let mut kinds = Vec::new();
    let mut packed = Vec::new();
    let mut patches = Vec::new();
    for (prim, &k) in keep.iter().enumerate() {
        if !k {
            continue;
        }
        prim_keep.push(prim as u32);
        vertex_keep.extend(
            g.prim_vertex_range(prim)
                .filter(|&v| keep_vertex.is_none_or(|kv| kv[v]))
                .map(|v| v as u32),
        );
        offsets.push(vertex_keep.len() as u32);
        kinds.push(match g.prim_kinds[prim] {
            PrimKind::Packed(i) => {
                packed.push(g.packed[i as usize].clone());
                PrimKind::Packed(packed.len() as u32 - 1)
            }
            PrimKind::Patch(i) => {
                patches.push(g.patches[i as usize].clone());
                PrimKind::Patch(patches.len() as u32 - 1)
            }
            other => other,
        });
    }
    g.vertex_point = vertex_keep
        .iter()
        .map(|&v| g.vertex_point[v as usize])
        .collect();
    g.vertices = g.vertices.gather(&vertex_keep);
    g.prims = g.prims.gather(&prim_keep);
    g.prim_offsets = offsets.into();
    g.prim_kinds = kinds.into();
    g.packed = packed.into();
    g.patches = patches;
    for grp in g.prim_groups.values_mut() {
        *grp = grp.gather(&prim_keep);
    }
    g.invalidate_topology();
}

/// Deletes the primitives in `group`; with `delete_unused_points`, points no
/// longer referenced by any vertex go too.
pub fn delete_prims(g: &mut Geometry, group: &Group, delete_unused_points: bool) {
    let keep: Vec<bool> = (0..g.num_prims()).map(|i| !group.contains(i)).collect();
    keep_prims(g, &keep);
    if delete_unused_points {
        compact_points(g);
    }
}

/// Removes the points in `group` and their vertices, as VEX's
/// `removepoint` does: a primitive that loses vertices stays unless it is
/// left with none or, when one of the points it lost is in `degenerate`,
/// left degenerate (a polygon with fewer than 3 vertices, a polyline with
/// fewer than 2); packed primitives and spline patches that lose their
/// vertex go.
pub fn remove_points(g: &mut Geometry, group: &Group, degenerate: &Group) {
    let keep_vertex: Vec<bool> = g
        .vertex_point
        .iter()
        .map(|&p| !group.contains(p as usize))
        .collect();
    let keep: Vec<bool> = (0..g.num_prims())
        .map(|prim| {
            let range = g.prim_vertex_range(prim);
            let left = range.clone().filter(|&v| keep_vertex[v]).count();
            if left == range.len() {
                return true;
            }
            let and_degenerate = range.clone().any(|v| {
                let p = g.vertex_point[v] as usize;
                p < degenerate.len() && degenerate.contains(p)
            });
            match g.prim_kinds[prim] {
                PrimKind::Polygon => left >= if and_degenerate { 3 } else { 1 },
                PrimKind::Polyline => left >= if and_degenerate { 2 } else { 1 },
                _ => false,
            }
        })
        .collect();
    keep_where(g, &keep, Some(&keep_vertex));
    let keep_points: Vec<bool> = (0..g.num_points()).map(|p| !group.contains(p)).collect();
    keep_points_where(g, &keep_points);
}

/// Deletes the points in `group` and every primitive that uses one of them.
pub fn delete_points(g: &mut Geometry, group: &Group) {
    let keep: Vec<bool> = (0..g.num_prims())
        .map(|prim| {
            !g.prim_points(prim)
                .iter()
                .any(|&p| group.contains(p as usize))
        })
        .collect();
    keep_prims(g, &keep);
    let keep_points: Vec<bool> = (0..g.num_points()).map(|p| !group.contains(p)).collect();
    keep_points_where(g, &keep_points);
}

/// Removes points no vertex references.
pub fn compact_points(g: &mut Geometry) {
    let mut used = vec![false; g.num_points()];
    for &p in &g.vertex_point {
        used[p as usize] = true;
    }
    if used.iter().all(|&u| u) {
        return;
    }
    keep_points_where(g, &used);
}

/// Keeps flagged points; vertices must only reference kept points.
fn keep_points_where(g: &mut Geometry, keep: &[bool]) {
    let mut remap = vec![u32::MAX; keep.len()];
    let mut kept = Vec::new();
    for (p, &k) in keep.iter().enumerate() {
        if k {
            remap[p] = kept.len() as u32;
            kept.push(p as u32);
        }
    }
    for v in g.vertex_point.make_mut().iter_mut() {
        *v = remap[*v as usize];
        debug_assert!(*v != u32::MAX, "vertex references a deleted point");
    }
    g.points = g.points.gather(&kept);
    for grp in g.point_groups.values_mut() {
        *grp = grp.gather(&kept);
    }
    g.invalidate_topology();
}

/// Reverses the vertex order of polygons and polylines (all, or those in
/// `group`), keeping the first vertex first as Houdini does.
pub fn reverse_prims(g: &mut Geometry, group: Option<&Group>) {
    let mut order: Vec<u32> = (0..g.num_vertices() as u32).collect();
    for prim in 0..g.num_prims() {
        if group.is_some_and(|grp| !grp.contains(prim)) {
            continue;
        }
        let r = g.prim_vertex_range(prim);
        match g.prim_kinds[prim] {
            PrimKind::Polygon => order[r.start + 1..r.end].reverse(),
            PrimKind::Polyline => order[r].reverse(),
            // A patch's grid order is its parameterisation.
            PrimKind::Packed(_) | PrimKind::Patch(_) => {}
        }
    }
    g.vertex_point = order.iter().map(|&v| g.vertex_point[v as usize]).collect();
    g.vertices = g.vertices.gather(&order);
    g.invalidate_topology();
}
