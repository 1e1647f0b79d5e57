//! Merge several geometries into one (union of attributes, defaults where missing).

use crate::attrib::AttribTable;
use crate::error::GeoError;
use crate::geometry::{checked_u32, Geometry, PrimKind};
use crate::group::Group;

fn append_groups(
    ours: &mut std::collections::BTreeMap<String, Group>,
    theirs: &std::collections::BTreeMap<String, Group>,
    old_len: usize,
    their_len: usize,
) {
    for (name, g) in theirs {
        ours.entry(name.clone())
            .or_insert_with(|| Group::new(old_len));
        ours.get_mut(name).expect("just inserted").append(g);
    }
    for g in ours.values_mut() {
        if g.len() != old_len + their_len {
            g.resize(old_len + their_len);
        }
    }
}

/// Concatenates geometries in order. Attributes present in only some inputs are
/// filled with their defaults elsewhere; groups likewise (non-members). Detail
/// attributes take the first input that has each one. An attribute name with
/// two types is an error naming it.
pub fn merge(inputs: &[&Geometry]) -> Result<Geometry, GeoError> {
    merge_cancellable(inputs, &|| false).map(|g| g.expect("never cancelled"))
}

/// Inputs appended between two polls of `cancel` in [`merge_cancellable`].
const INPUTS_PER_POLL: usize = 256;

/// [`merge`], polling `cancel` as it goes: `None` once it answers true.
pub fn merge_cancellable(
    inputs: &[&Geometry],
    cancel: &dyn Fn() -> bool,
) -> Result<Option<Geometry>, GeoError> {
    let mut out = match inputs.first() {
        Some(first) => (*first).clone(),
        None => return Ok(Some(Geometry::new())),
    };
    let total_points: usize = inputs.iter().map(|g| g.num_points()).sum();
    let total_vertices: usize = inputs.iter().map(|g| g.num_vertices()).sum();
    checked_u32(total_points, "point count")?;
    checked_u32(total_vertices, "vertex count")?;
    if inputs.len() > 1 {
        // Connectivity grown in fresh arrays of the final size (the first
        // input's are shared with it).
        let total_prims: usize = inputs.iter().map(|g| g.num_prims()).sum();
        let grown = |v: &[u32], n: usize| {
            let mut out = Vec::with_capacity(n);
            out.extend_from_slice(v);
            out
        };
        out.vertex_point = grown(&out.vertex_point, total_vertices).into();
        out.prim_offsets = grown(&out.prim_offsets, total_prims + 1).into();
        let mut kinds = Vec::with_capacity(total_prims);
        kinds.extend_from_slice(&out.prim_kinds);
        out.prim_kinds = kinds.into();
    }
    for (k, g) in inputs[1..].iter().enumerate() {
        if k % INPUTS_PER_POLL == 0 && cancel() {
            return Ok(None);
        }
        let point_base = out.num_points() as u32;
        let vertex_base = out.num_vertices() as u32;
        let packed_base = out.packed.len() as u32;
        let patch_base = out.patches.len() as u32;
        let (old_points, old_prims) = (out.num_points(), out.num_prims());
        out.points.append(&g.points)?;
        out.vertices.append(&g.vertices)?;
        out.prims.append(&g.prims)?;
        merge_detail(&mut out.detail, &g.detail)?;
        out.vertex_point
            .make_mut()
            .extend(g.vertex_point.iter().map(|&p| p + point_base));
        out.prim_offsets
            .make_mut()
            .extend(g.prim_offsets[1..].iter().map(|&o| o + vertex_base));
        out.prim_kinds
            .make_mut()
            .extend(g.prim_kinds.iter().map(|k| match k {
                PrimKind::Packed(i) => PrimKind::Packed(i + packed_base),
                PrimKind::Patch(i) => PrimKind::Patch(i + patch_base),
                other => *other,
            }));
        if !g.packed.is_empty() {
            out.packed.make_mut().extend(g.packed.iter().cloned());
        }
        out.patches.extend(g.patches.iter().cloned());
        append_groups(
            &mut out.point_groups,
            &g.point_groups,
            old_points,
            g.num_points(),
        );
        append_groups(
            &mut out.prim_groups,
            &g.prim_groups,
            old_prims,
            g.num_prims(),
        );
    }
    out.invalidate_topology();
    Ok(Some(out))
}

fn merge_detail(ours: &mut AttribTable, theirs: &AttribTable) -> Result<(), GeoError> {
    for (name, a) in theirs.iter() {
        match ours.get(name) {
            Some(o) if o.attrib_type() != a.attrib_type() => {
                return Err(GeoError::AttribType {
                    class: ours.class(),
                    name: name.to_owned(),
                    expected: o.attrib_type(),
                    found: a.attrib_type(),
                })
            }
            Some(_) => {}
            None => ours.insert(name, a.clone())?,
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attrib::{AttribClass, AttribValue, Attribute, TypeInfo};
    use crate::primitives::cube;
    use glam::Vec3;

    #[test]
    fn union_of_attributes_with_defaults() {
        let mut a = cube(1.0);
        let mut b = cube(2.0);
        a.set_attrib(
            AttribClass::Point,
            "Cd",
            Attribute::from_data(crate::AttribData::Vec3(vec![Vec3::X; 8]), TypeInfo::Color),
        )
        .unwrap();
        let w = Attribute::new(AttribValue::Float(0.0), TypeInfo::None, 6)
            .with_default(AttribValue::Float(-1.0))
            .unwrap();
        let mut w = w;
        w.as_f32_mut().unwrap()[0] = 5.0;
        b.set_attrib(AttribClass::Primitive, "w", w).unwrap();
        b.set_prim_group("top", Group::from_members(6, [1]))
            .unwrap();
        let m = merge(&[&a, &b]).unwrap();
        assert_eq!(m.num_points(), 16);
        assert_eq!(m.num_prims(), 12);
        let cd = m
            .attrib(AttribClass::Point, "Cd")
            .unwrap()
            .as_vec3()
            .unwrap();
        assert_eq!(cd[0], Vec3::X);
        assert_eq!(cd[8], Vec3::ZERO, "missing on b: the attribute's default");
        let w = m
            .attrib(AttribClass::Primitive, "w")
            .unwrap()
            .as_f32()
            .unwrap();
        assert_eq!(&w[..7], &[-1.0, -1.0, -1.0, -1.0, -1.0, -1.0, 5.0]);
        assert_eq!(
            m.prim_groups()["top"].members().collect::<Vec<_>>(),
            vec![7]
        );
        assert_eq!(
            m.prim_points(6),
            &[8, 9, 10, 11].map(|i| b.prim_points(0)[i - 8] + 8)
        );
        assert!(crate::ops::validate(&m).is_empty());
    }

    #[test]
    fn conflicting_types_are_an_error() {
        let mut a = cube(1.0);
        let mut b = cube(1.0);
        a.set_attrib(
            AttribClass::Point,
            "x",
            Attribute::new(AttribValue::Float(0.0), TypeInfo::None, 8),
        )
        .unwrap();
        b.set_attrib(
            AttribClass::Point,
            "x",
            Attribute::new(AttribValue::Int(0), TypeInfo::None, 8),
        )
        .unwrap();
        let e = merge(&[&a, &b]).unwrap_err();
        assert_eq!(e.to_string(), "point attribute `x` is int, expected float");
    }
}
