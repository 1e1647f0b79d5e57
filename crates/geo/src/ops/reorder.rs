//! New element orders: points or primitives renumbered by a permutation,
//! every attribute, group, vertex reference and packed instance following
//! (the sort node's kernel).

use crate::error::GeoError;
use crate::geometry::Geometry;

/// Checks that `order` holds each of `0..n` once.
fn check(order: &[u32], n: usize, what: &str) -> Result<(), GeoError> {
    let mut seen = vec![false; n];
    let ok = order.len() == n
        && order.iter().all(|&i| {
            let i = i as usize;
            i < n && !std::mem::replace(&mut seen[i], true)
        });
    if ok {
        Ok(())
    } else {
        Err(GeoError::Invalid(format!(
            "a new {what} order must name each of the {n} {what}s once"
        )))
    }
}

/// Points renumbered: new point `i` is old point `order[i]`.
pub fn reorder_points(g: &mut Geometry, order: &[u32]) -> Result<(), GeoError> {
    check(order, g.num_points(), "point")?;
    let mut new_of_old = vec![0u32; order.len()];
    for (new, &old) in order.iter().enumerate() {
        new_of_old[old as usize] = new as u32;
    }
    g.points = g.points.gather(order);
    for grp in g.point_groups.values_mut() {
        *grp = grp.gather(order);
    }
    for v in g.vertex_point.make_mut().iter_mut() {
        *v = new_of_old[*v as usize];
    }
    g.invalidate_topology();
    Ok(())
}

/// Primitives renumbered: new primitive `i` is old primitive `order[i]`,
/// its vertices moving with it.
pub fn reorder_prims(g: &mut Geometry, order: &[u32]) -> Result<(), GeoError> {
    check(order, g.num_prims(), "primitive")?;
    let picked = super::edit::gather_prims(g, order.iter().copied(), None);
    super::edit::set_prims(g, order, picked);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives::box_mesh;
    use glam::Vec3;

    #[test]
    fn reordering_keeps_the_shape_and_reversing_twice_restores_it() {
        let b = box_mesh(Vec3::ONE, [2, 1, 1]);
        let mut g = b.clone();
        let rev: Vec<u32> = (0..g.num_points() as u32).rev().collect();
        reorder_points(&mut g, &rev).unwrap();
        assert_eq!(g.positions()[0], b.positions()[b.num_points() - 1]);
        for prim in 0..g.num_prims() {
            let a: Vec<Vec3> = g
                .prim_points(prim)
                .iter()
                .map(|&p| g.positions()[p as usize])
                .collect();
            let c: Vec<Vec3> = b
                .prim_points(prim)
                .iter()
                .map(|&p| b.positions()[p as usize])
                .collect();
            assert_eq!(a, c);
        }
        let prims: Vec<u32> = (0..g.num_prims() as u32).rev().collect();
        reorder_prims(&mut g, &prims).unwrap();
        reorder_prims(&mut g, &prims).unwrap();
        reorder_points(&mut g, &rev).unwrap();
        assert_eq!(g.content_hash(), b.content_hash());
        assert!(reorder_points(&mut g, &[0, 0]).is_err());
    }
}
