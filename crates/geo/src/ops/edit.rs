//! Structural edits: delete points or primitives, drop unused points, reverse winding, add vertices to existing primitives.

use crate::error::GeoError;
use crate::geometry::{checked_u32, Geometry, PrimKind};
use crate::group::Group;

/// Keeps the primitives whose flag is true; everything stays consistent
/// (vertex and primitive attributes, groups, packed instances).
fn keep_prims(g: &mut Geometry, keep: &[bool]) {
    keep_where(g, keep, None);
}

/// Primitives picked out of a geometry: the old vertices they keep (in
/// order), their offsets, kinds, and packed instances and patches
/// renumbered to follow them.
pub(crate) struct GatheredPrims {
    pub vertices: Vec<u32>,
    pub offsets: Vec<u32>,
    pub kinds: Vec<PrimKind>,
    pub packed: Vec<crate::geometry::PackedInstance>,
    pub patches: Vec<crate::patch::PatchBasis>,
}

/// The primitives `prims` of `g`, in that order, with the vertices
/// `keep_vertex` keeps (all when None): the one rule for deleting,
/// reordering and cutting out primitives.
pub(crate) fn gather_prims(
    g: &Geometry,
    prims: impl IntoIterator<Item = u32>,
    keep_vertex: Option<&[bool]>,
) -> GatheredPrims {
    let mut out = GatheredPrims {
        vertices: Vec::new(),
        offsets: vec![0u32],
        kinds: Vec::new(),
        packed: Vec::new(),
        patches: Vec::new(),
    };
    for prim in prims {
        let prim = prim as usize;
        out.vertices.extend(
            g.prim_vertex_range(prim)
                .filter(|&v| keep_vertex.is_none_or(|kv| kv[v]))
                .map(|v| v as u32),
        );
        out.offsets.push(out.vertices.len() as u32);
        out.kinds.push(match g.prim_kinds[prim] {
            PrimKind::Packed(i) => {
                out.packed.push(g.packed[i as usize].clone());
                PrimKind::Packed(out.packed.len() as u32 - 1)
            }
            PrimKind::Patch(i) => {
                out.patches.push(g.patches[i as usize].clone());
                PrimKind::Patch(out.patches.len() as u32 - 1)
            }
            other => other,
        });
    }
    out
}

/// Makes `picked` (gathered from `g` itself) `g`'s primitives: vertex
/// references, vertex and primitive attributes, kinds, packed instances,
/// patches and primitive groups follow.
pub(crate) fn set_prims(g: &mut Geometry, prims: &[u32], picked: GatheredPrims) {
    g.vertex_point = picked
        .vertices
        .iter()
        .map(|&v| g.vertex_point[v as usize])
        .collect::<Vec<_>>()
        .into();
    g.vertices = g.vertices.gather(&picked.vertices);
    g.prims = g.prims.gather(prims);
    g.prim_offsets = picked.offsets.into();
    g.prim_kinds = picked.kinds.into();
    g.packed = picked.packed.into();
    g.patches = picked.patches;
    for grp in g.prim_groups.values_mut() {
        *grp = grp.gather(prims);
    }
    g.invalidate_topology();
}

/// Keeps the flagged primitives and, of those, the flagged vertices.
fn keep_where(g: &mut Geometry, keep: &[bool], keep_vertex: Option<&[bool]>) {
    let prims: Vec<u32> = (0..keep.len() as u32)
        .filter(|&p| keep[p as usize])
        .collect();
    let picked = gather_prims(g, prims.iter().copied(), keep_vertex);
    set_prims(g, &prims, picked);
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

/// Appends vertices to existing polygons and polylines, as VEX's
/// `addvertex` on a primitive that exists: each `(prim, point)` of `added`
/// adds a vertex on `point` after `prim`'s last, in the order given.
/// Existing vertices keep their attribute values; new ones take each
/// attribute's default. Vertices after the first primitive that grows are
/// renumbered. Nothing changes on an error (a primitive or point that does
/// not exist, a packed primitive or patch).
pub fn append_vertices(g: &mut Geometry, added: &[(u32, u32)]) -> Result<(), GeoError> {
    if added.is_empty() {
        return Ok(());
    }
    check_appended(g, added)?;
    // The added points by primitive, in the order given (a counting sort).
    let n = g.num_prims();
    let mut starts = vec![0usize; n + 1];
    for &(prim, _) in added {
        starts[prim as usize + 1] += 1;
    }
    for k in 0..n {
        starts[k + 1] += starts[k];
    }
    let mut next = starts.clone();
    let mut by_prim = vec![0u32; added.len()];
    for &(prim, point) in added {
        by_prim[next[prim as usize]] = point;
        next[prim as usize] += 1;
    }
    // The new vertex lists, and the old vertex each new vertex copies: the
    // slot past the old vertices (a default) for the added ones.
    let old = g.num_vertices();
    checked_u32(old + added.len(), "vertex count")?;
    let mut source = Vec::with_capacity(old + added.len());
    let mut points = Vec::with_capacity(old + added.len());
    let mut offsets = Vec::with_capacity(n + 1);
    offsets.push(0u32);
    for (prim, more) in starts.windows(2).enumerate() {
        for v in g.prim_vertex_range(prim) {
            source.push(v as u32);
            points.push(g.vertex_point[v]);
        }
        source.extend(std::iter::repeat_n(old as u32, more[1] - more[0]));
        points.extend_from_slice(&by_prim[more[0]..more[1]]);
        offsets.push(points.len() as u32);
    }
    let mut vertices = g.vertices.clone();
    vertices.resize(old + 1);
    g.vertices = vertices.gather(&source);
    g.vertex_point = points.into();
    g.prim_offsets = offsets.into();
    g.invalidate_topology();
    Ok(())
}

/// Every `(prim, point)` names a polygon or polyline and a point there are.
fn check_appended(g: &Geometry, added: &[(u32, u32)]) -> Result<(), GeoError> {
    for &(prim, point) in added {
        if point as usize >= g.num_points() {
            return Err(GeoError::PointOutOfRange {
                index: point,
                count: g.num_points(),
            });
        }
        let Some(kind) = g.prim_kinds.get(prim as usize) else {
            return Err(GeoError::Invalid(format!(
                "primitive {prim} does not exist (geometry has {} primitives)",
                g.num_prims()
            )));
        };
        if !matches!(kind, PrimKind::Polygon | PrimKind::Polyline) {
            return Err(GeoError::Invalid(format!(
                "primitive {prim} is a {} primitive: only polygons and polylines take added vertices",
                kind.name()
            )));
        }
    }
    Ok(())
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attrib::{AttribClass, AttribData, Attribute, TypeInfo};

    /// A triangle (0, 1, 2) and a polyline (2, 3), vertex attribute `w`
    /// 1..5.
    fn tri_and_line() -> Geometry {
        let p = |x: f32| glam::Vec3::new(x, 0.0, 0.0);
        let mut g = Geometry::from_prims(
            vec![p(0.0), p(1.0), p(2.0), p(3.0), p(4.0)],
            vec![0, 1, 2, 2, 3],
            &[3, 2],
            vec![PrimKind::Polygon, PrimKind::Polyline],
        )
        .unwrap();
        let w = AttribData::Float(vec![1.0, 2.0, 3.0, 4.0, 5.0]);
        g.set_attrib(
            AttribClass::Vertex,
            "w",
            Attribute::from_data(w, TypeInfo::None),
        )
        .unwrap();
        g
    }

    #[test]
    fn appended_vertices_follow_each_primitives_own_in_the_order_given() {
        let mut g = tri_and_line();
        assert_eq!(g.topology().point_prims(3), &[1]);
        append_vertices(&mut g, &[(1, 4), (0, 3), (1, 0)]).unwrap();
        assert_eq!(g.prim_points(0), &[0, 1, 2, 3]);
        assert_eq!(g.prim_points(1), &[2, 3, 4, 0]);
        let w = g
            .attrib(AttribClass::Vertex, "w")
            .unwrap()
            .as_f32()
            .unwrap();
        assert_eq!(w, &[1.0, 2.0, 3.0, 0.0, 4.0, 5.0, 0.0, 0.0]);
        // The cached topology was dropped with the old connectivity.
        assert_eq!(g.topology().point_prims(3), &[0, 1]);
    }

    #[test]
    fn nothing_changes_on_a_bad_primitive_or_point() {
        let g = tri_and_line();
        for bad in [[(0, 1), (2, 0)], [(0, 1), (0, 9)]] {
            let mut h = g.clone();
            assert!(append_vertices(&mut h, &bad).is_err());
            assert_eq!(h, g);
        }
    }
}
