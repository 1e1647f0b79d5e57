//! A geometry rebuilt from a source geometry, for the cut family (clip,
//! mirror seams, polyfill, revolve): every output point and vertex names
//! the two source elements it blends, every output primitive the source
//! primitive it copies, and one pass carries every attribute and group.
//!
//! A blend `(a, b, t)` is `AttribData::blend`'s: `(1 - t) a + t b` for
//! numbers and vectors, the nearer element for integers, strings and
//! matrices; `(i, i, 0.0)` copies element `i`. Point groups follow the
//! nearer source point; primitive groups follow the source primitive
//! except for new faces (caps, fills), which join none of them. Detail
//! attributes are copied. Elements that average many (a fan's centre) are
//! written afterwards by [`set_means`].

use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, AttribData, Attribute, Geometry, Group, PrimKind, P};
use rayon::prelude::*;

use crate::ModelError;

/// `(a, b, t)`: `(1 - t) a + t b` of two source elements.
pub(crate) type Blend = (u32, u32, f32);

/// The blend that copies element `i`.
pub(crate) fn copy(i: u32) -> Blend {
    (i, i, 0.0)
}

/// Where an output geometry's elements come from.
#[derive(Default)]
pub(crate) struct Plan {
    pub positions: Vec<Vec3>,
    /// Per output point: the source points it blends.
    pub point_sources: Vec<Blend>,
    /// Per output vertex: its output point.
    pub vertex_points: Vec<u32>,
    /// Per output vertex: the source vertices it blends.
    pub vertex_sources: Vec<Blend>,
    /// Per output primitive: its vertex count, kind and source primitive.
    pub prim_counts: Vec<u32>,
    pub prim_kinds: Vec<PrimKind>,
    pub prim_sources: Vec<u32>,
    /// Output primitives from this one on are new faces: they take their
    /// source primitive's attributes but join none of its groups.
    pub first_new_prim: usize,
}

/// Refuses a geometry with primitives other than polygons and polylines
/// (packed primitives and patches cannot be rebuilt from a plan).
pub(crate) fn polygons_and_polylines(g: &Geometry, op: &str) -> Result<(), ModelError> {
    match g
        .prim_kinds()
        .iter()
        .position(|k| !matches!(k, PrimKind::Polygon | PrimKind::Polyline))
    {
        Some(k) => Err(ModelError::Invalid(format!(
            "{op} takes polygons and polylines; primitive {k} is a {}",
            g.prim_kinds()[k].name()
        ))),
        None => Ok(()),
    }
}

/// The output geometry `plan` describes, attributes and groups carried
/// from `src`. `op` names the operation in errors; `cancel` is polled
/// between the columns.
pub(crate) fn build(
    src: &Geometry,
    plan: Plan,
    op: &'static str,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, ModelError> {
    let failed = |why: String| ModelError::Failed { op, why };
    let check = || ModelError::unless_cancelled(cancel);
    check()?;
    let mut out = Geometry::from_prims(
        plan.positions,
        plan.vertex_points,
        &plan.prim_counts,
        plan.prim_kinds,
    )
    .map_err(|e| failed(e.to_string()))?;
    let columns = [
        (AttribClass::Point, &plan.point_sources),
        (AttribClass::Vertex, &plan.vertex_sources),
    ];
    for (class, sources) in columns {
        check()?;
        for (name, attr) in blended(src, class, sources) {
            out.set_attrib(class, &name, attr)
                .map_err(|e| failed(e.to_string()))?;
        }
    }
    for (name, attr) in src.attribs(AttribClass::Primitive).iter() {
        out.set_attrib(
            AttribClass::Primitive,
            name,
            attr.gather(&plan.prim_sources),
        )
        .map_err(|e| failed(e.to_string()))?;
    }
    for (name, attr) in src.attribs(AttribClass::Detail).iter() {
        out.set_attrib(AttribClass::Detail, name, attr.clone())
            .map_err(|e| failed(e.to_string()))?;
    }
    check()?;
    for (name, group) in src.point_groups() {
        let members = plan
            .point_sources
            .iter()
            .map(|&(a, b, t)| group.contains(if t < 0.5 { a } else { b } as usize));
        out.set_point_group(name, Group::from_flags(members))
            .map_err(|e| failed(e.to_string()))?;
    }
    for (name, group) in src.prim_groups() {
        let members = plan
            .prim_sources
            .iter()
            .enumerate()
            .map(|(k, &s)| k < plan.first_new_prim && group.contains(s as usize));
        out.set_prim_group(name, Group::from_flags(members))
            .map_err(|e| failed(e.to_string()))?;
    }
    Ok(out)
}

/// Every attribute of `class` (P aside) blended by `sources`, columns in
/// parallel, in name order.
fn blended(src: &Geometry, class: AttribClass, sources: &[Blend]) -> Vec<(String, Attribute)> {
    let attrs: Vec<(&str, &Attribute)> = src
        .attribs(class)
        .iter()
        .filter(|(name, _)| !(class == AttribClass::Point && *name == P))
        .collect();
    attrs
        .par_iter()
        .map(|(name, attr)| {
            let data = attr.data().blend(sources);
            let column = Attribute::from_data(data, attr.type_info)
                .with_default(attr.default_value().clone())
                .expect("a blend keeps its column's type");
            (name.to_string(), column)
        })
        .collect()
}

/// Sets each `(element, of)` of `targets` to the mean of elements `of`
/// (all of class `class` in `g` itself) for every attribute but P:
/// numbers and vectors averaged (quaternions renormalised), other types
/// taken from the first of `of`.
pub(crate) fn set_means(g: &mut Geometry, class: AttribClass, targets: &[(u32, Vec<u32>)]) {
    if targets.is_empty() {
        return;
    }
    let names: Vec<String> = g
        .attribs(class)
        .names()
        .filter(|n| !(class == AttribClass::Point && *n == P))
        .map(str::to_string)
        .collect();
    for name in names {
        let attr = g.attrib(class, &name).expect("listed above");
        let means = means_of(attr.data(), targets);
        let column = g.attribs_mut(class).get_mut(&name).expect("listed above");
        let mut values = column.values_mut();
        for (k, (element, _)) in targets.iter().enumerate() {
            values
                .set(*element as usize, &means.get(k))
                .expect("a mean keeps its column's type");
        }
    }
}

/// One element per target: the mean of its `of` elements of `data`.
fn means_of(data: &AttribData, targets: &[(u32, Vec<u32>)]) -> AttribData {
    let Some((floats, width)) = data.as_floats() else {
        let firsts: Vec<u32> = targets.iter().map(|(_, of)| of[0]).collect();
        return data.gather(&firsts);
    };
    let mut out = AttribData::zeroed(data.attrib_type(), targets.len());
    let (dst, _) = out.as_floats_mut().expect("same type as a float column");
    for (k, (_, of)) in targets.iter().enumerate() {
        let row = &mut dst[k * width..(k + 1) * width];
        for &i in of {
            let i = i as usize;
            for (d, s) in row.iter_mut().zip(&floats[i * width..(i + 1) * width]) {
                *d += s;
            }
        }
        row.iter_mut().for_each(|d| *d /= of.len() as f32);
    }
    if let AttribData::Quat(q) = &mut out {
        q.iter_mut().for_each(|x| *x = x.normalize());
    }
    out
}
