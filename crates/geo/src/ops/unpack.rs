//! Expand packed instances into real geometry.

use std::collections::HashMap;
use std::sync::Arc;

use crate::error::GeoError;
use crate::geometry::Geometry;
use crate::group::Group;

/// Replaces every packed primitive by a transformed copy of its source
/// (recursively: nested packs are unpacked too). The packed primitives' own
/// points are removed when nothing else uses them.
pub fn unpack(g: &Geometry) -> Result<Geometry, GeoError> {
    unpack_with(g, &|| false)
}

/// [`unpack`], polling `cancel` per instance ([`GeoError::Cancelled`]).
pub fn unpack_with(g: &Geometry, cancel: &dyn Fn() -> bool) -> Result<Geometry, GeoError> {
    let packed = g.prims_where(Geometry::is_packed);
    if packed.is_empty() {
        return Ok(g.clone());
    }
    let mut pieces = Vec::with_capacity(packed.len());
    for &prim in &packed {
        if cancel() {
            return Err(GeoError::Cancelled);
        }
        let inst = g.packed_instance(prim).expect("packed primitive");
        let mut piece = unpack_with(&inst.source, cancel)?;
        let m = g
            .packed_world_transform(prim)
            .expect("packed primitive has a point");
        super::transform(&mut piece, m);
        pieces.push(piece);
    }
    let mut rest = g.clone();
    super::delete_prims(
        &mut rest,
        &Group::from_members(g.num_prims(), packed.iter().copied()),
        false,
    );
    // Only the points that served as instance anchors and nothing else go.
    let mut used = vec![false; rest.num_points()];
    for &p in rest.vertex_points() {
        used[p as usize] = true;
    }
    let mut anchors = Group::new(rest.num_points());
    for &prim in &packed {
        let p = g.prim_points(prim)[0] as usize;
        if !used[p] {
            anchors.set(p, true);
        }
    }
    super::delete_points(&mut rest, &anchors);
    if cancel() {
        return Err(GeoError::Cancelled);
    }
    let mut all: Vec<&Geometry> = vec![&rest];
    all.extend(pieces.iter());
    super::merge(&all)
}

/// The bytes [`unpack`] would produce (its result and the pieces it merges,
/// so about twice the unpacked geometry), without unpacking: sources are
/// measured once each, however many instances share them.
pub fn unpacked_bytes(g: &Geometry) -> f64 {
    fn walk(g: &Geometry, memo: &mut HashMap<*const Geometry, f64>) -> f64 {
        let mut total = g.memory_bytes() as f64;
        for inst in g.packed_instances() {
            let key = Arc::as_ptr(&inst.source);
            let b = match memo.get(&key) {
                Some(b) => *b,
                None => {
                    let b = walk(&inst.source, memo);
                    memo.insert(key, b);
                    b
                }
            };
            total += b;
        }
        total
    }
    if !g.has_packed() {
        return g.memory_bytes() as f64;
    }
    2.0 * walk(g, &mut HashMap::new())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives::cube;
    use glam::{Mat4, Vec3};
    use std::sync::Arc;

    #[test]
    fn unpacks_recursively_with_transforms() {
        let src = Arc::new(cube(1.0));
        let mut inner = Geometry::new();
        inner
            .add_packed_many(&src, &[Vec3::ZERO, Vec3::X * 2.0], &[Mat4::IDENTITY; 2])
            .unwrap();
        let inner = Arc::new(inner);
        let mut outer = Geometry::new();
        let p = outer.add_point(Vec3::Y * 10.0);
        outer
            .add_packed(p, inner, Mat4::from_scale(Vec3::splat(2.0)))
            .unwrap();
        let flat = unpack(&outer).unwrap();
        assert_eq!(flat.num_points(), 16);
        assert_eq!(flat.num_prims(), 12);
        let b = crate::ops::bounds(&flat).unwrap();
        assert_eq!(b.min, Vec3::new(-1.0, 9.0, -1.0));
        assert_eq!(b.max, Vec3::new(5.0, 11.0, 1.0));
        assert_eq!(
            crate::ops::bounds(&outer).unwrap(),
            b,
            "packed bounds match unpacked"
        );
    }
}
