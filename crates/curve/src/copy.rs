//! Copy to points: a copy of the source on every template point, placed by
//! Houdini's instance attributes (`geode_geo::ops::instance_transforms`),
//! either as packed instances (one shared geometry, a transform per copy)
//! or as real geometry; template point attributes travel with the copies;
//! an integer point attribute can pick which piece of the source each
//! point gets.

use std::sync::Arc;

use geode_geo::{ops, AttribClass, GeoError, Geometry, Group};
use rayon::prelude::*;

/// Attributes that place copies: consumed, never carried onto them
/// (Houdini's Copy to Points leaves these out of the attributes it copies
/// by default, `v` included).
const PLACEMENT: [&str; 11] = [
    "P",
    "N",
    "v",
    "up",
    "orient",
    "rot",
    "pscale",
    "scale",
    "trans",
    "pivot",
    "transform",
];

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CopyOptions {
    /// Packed instances (memory per copy is a transform) or real geometry.
    pub packed: bool,
    /// A primitive attribute (integer or string) splitting the source into
    /// pieces, in order of first appearance; empty: the whole source.
    pub piece_attrib: String,
    /// An integer template point attribute choosing the piece per point
    /// (wrapped into range); absent: piece `point % pieces`.
    pub variant_attrib: String,
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CopyError {
    #[error(
        "the piece attribute `{0}` is not an integer or string primitive attribute of the source"
    )]
    BadPieceAttrib(String),
    #[error("the variant attribute `{0}` on the template points is not an integer")]
    BadVariantAttrib(String),
    #[error(transparent)]
    Geo(#[from] GeoError),
    #[error("cancelled")]
    Cancelled,
}

/// The source split into pieces by `attrib` (primitive values in order of
/// first appearance).
fn pieces(source: &Geometry, attrib: &str) -> Result<Vec<Arc<Geometry>>, CopyError> {
    if attrib.is_empty() {
        return Ok(vec![Arc::new(source.clone())]);
    }
    let a = source
        .attrib(AttribClass::Primitive, attrib)
        .ok_or_else(|| CopyError::BadPieceAttrib(attrib.into()))?;
    let keys: Vec<i64> = if let Some(v) = a.as_i32() {
        v.iter().map(|&x| x as i64).collect()
    } else if let Some(s) = a.as_strings() {
        s.indices.iter().map(|&x| x as i64).collect()
    } else {
        return Err(CopyError::BadPieceAttrib(attrib.into()));
    };
    let mut order: Vec<i64> = Vec::new();
    for k in &keys {
        if !order.contains(k) {
            order.push(*k);
        }
    }
    Ok(order
        .par_iter()
        .map(|key| {
            let mut g = source.clone();
            let others = Group::from_flags(keys.iter().map(|k| k != key));
            ops::delete_prims(&mut g, &others, true);
            Arc::new(g)
        })
        .collect())
}

/// Copies `source` onto every point of `template`; `cancel` is polled per
/// copy and between phases. An instance attribute of a type that cannot
/// mean what its name does is an error (see `ops::InstanceAttribs`).
pub fn copy_to_points(
    source: &Geometry,
    template: &Geometry,
    opts: &CopyOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, CopyError> {
    let pieces = pieces(source, &opts.piece_attrib)?;
    let n = template.num_points();
    let choice: Vec<usize> = if opts.variant_attrib.is_empty() || pieces.len() == 1 {
        vec![0; n]
    } else {
        match template.attrib(AttribClass::Point, &opts.variant_attrib) {
            None => (0..n).map(|i| i % pieces.len()).collect(),
            Some(a) => a
                .as_i32()
                .ok_or_else(|| CopyError::BadVariantAttrib(opts.variant_attrib.clone()))?
                .iter()
                .map(|&v| v.rem_euclid(pieces.len() as i32) as usize)
                .collect(),
        }
    };
    let instances = ops::InstanceAttribs::new(template)?;
    let carried: Vec<&str> = template
        .attribs(AttribClass::Point)
        .names()
        .filter(|name| !PLACEMENT.contains(name))
        .collect();
    if opts.packed {
        let mut out = Geometry::new();
        for (k, piece) in pieces.iter().enumerate() {
            let members: Vec<usize> = (0..n).filter(|&i| choice[i] == k).collect();
            if members.is_empty() {
                continue;
            }
            let world = |k: usize| instances.at(members[k]);
            let first = out.num_points();
            out.add_packed_with(piece, members.len(), world)?;
            let indices: Vec<u32> = members.iter().map(|&i| i as u32).collect();
            carry(template, &carried, &indices, &mut out, first)?;
        }
        return Ok(out);
    }
    let copies: Option<Vec<Geometry>> = (0..n)
        .into_par_iter()
        .map(|i| {
            if cancel() {
                return None;
            }
            Some(ops::transformed(&pieces[choice[i]], instances.at(i)))
        })
        .collect();
    let copies = copies.ok_or(CopyError::Cancelled)?;
    let mut out = ops::merge_cancellable(&copies.iter().collect::<Vec<_>>(), cancel)?
        .ok_or(CopyError::Cancelled)?;
    // Each copy's points get its template point's values.
    let indices: Vec<u32> = copies
        .iter()
        .enumerate()
        .flat_map(|(i, g)| std::iter::repeat_n(i as u32, g.num_points()))
        .collect();
    carry(template, &carried, &indices, &mut out, 0)?;
    Ok(out)
}

/// Sets point attributes `names` of `out` from `from`'s points: output point
/// `first + k` takes template point `indices[k]` (others keep defaults).
fn carry(
    from: &Geometry,
    names: &[&str],
    indices: &[u32],
    out: &mut Geometry,
    first: usize,
) -> Result<(), GeoError> {
    for name in names {
        let Some(a) = from.attrib(AttribClass::Point, name) else {
            continue;
        };
        let values = a.data().gather(indices);
        let column = out.attribs_mut(AttribClass::Point).get_or_create(
            name,
            a.default_value().clone(),
            a.type_info,
        )?;
        column
            .values_mut()
            .write(first, &values)
            .map_err(|found| GeoError::AttribType {
                class: AttribClass::Point,
                name: (*name).into(),
                expected: a.attrib_type(),
                found,
            })?;
    }
    Ok(())
}
