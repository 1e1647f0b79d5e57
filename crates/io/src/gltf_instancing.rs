//! glTF's `EXT_mesh_gpu_instancing` both ways. Writing: each packed
//! instance's world transform split into translation, rotation and scale
//! (in parallel), grouped by source in order of first appearance; those a
//! TRS cannot hold (shears) or whose source instances further (nested
//! packing) are left to a node each. Reading: the extension accepted as
//! required, and a node's instance transforms read from its accessors.

use std::sync::Arc;

use geode_geo::glam::{Mat4, Quat, Vec3};
use geode_geo::Geometry;
use rayon::prelude::*;

use crate::error::{ParseError, ParseResult};
use crate::gltf_read::check_accessor;

/// The extension's name.
pub const EXTENSION: &str = "EXT_mesh_gpu_instancing";

/// The instances of one source on one instancing node.
pub struct Group {
    /// A primitive of the group (its source is the group's).
    pub first_prim: usize,
    pub translations: Vec<Vec3>,
    /// Unit quaternions as x, y, z, w.
    pub rotations: Vec<Quat>,
    pub scales: Vec<Vec3>,
}

/// Packed primitives, as groups and as the ones placed one by one.
pub struct Placed {
    pub groups: Vec<Group>,
    pub one_by_one: Vec<usize>,
}

/// Instances per parallel task (and per cancellation poll).
const PER_TASK: usize = 1 << 14;

/// How far a rebuilt transform may differ from the original, relative to
/// its largest entry: float round-off, not a shear.
const TRS_TOLERANCE: f32 = 1e-5;

/// `m` as translation, rotation and scale, when those rebuild it.
fn as_trs(m: &Mat4) -> Option<(Vec3, Quat, Vec3)> {
    let (s, r, t) = m.to_scale_rotation_translation();
    let rebuilt = Mat4::from_scale_rotation_translation(s, r, t);
    let size = m.to_cols_array().iter().fold(0.0f32, |a, x| a.max(x.abs()));
    let worst = m
        .to_cols_array()
        .iter()
        .zip(rebuilt.to_cols_array())
        .fold(0.0f32, |a, (x, y)| a.max((x - y).abs()));
    (worst <= TRS_TOLERANCE * size.max(1.0) && r.is_finite() && s.is_finite()).then_some((
        t,
        r.normalize(),
        s,
    ))
}

/// Splits `prims` (packed primitives of `g`) into instancing groups and
/// the rest; `None` when `cancelled` says so.
pub fn place(
    g: &Geometry,
    prims: &[usize],
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Option<Placed> {
    type Row = Option<(Vec3, Quat, Vec3)>;
    let rows: Vec<Vec<Row>> = prims
        .par_chunks(PER_TASK)
        .map(|chunk| {
            if cancelled() {
                return None;
            }
            Some(
                chunk
                    .iter()
                    .map(|&prim| {
                        let inst = g.packed_instance(prim)?;
                        if inst.source.has_packed() {
                            return None;
                        }
                        as_trs(&g.packed_world_transform(prim)?)
                    })
                    .collect(),
            )
        })
        .collect::<Option<_>>()?;
    let mut placed = Placed {
        groups: Vec::new(),
        one_by_one: Vec::new(),
    };
    // Sources by pointer; runs of one source are the rule, so the last one
    // found is tried first.
    let mut sources: Vec<*const Geometry> = Vec::new();
    let mut last = usize::MAX;
    for (&prim, row) in prims.iter().zip(rows.into_iter().flatten()) {
        let Some((t, r, s)) = row else {
            placed.one_by_one.push(prim);
            continue;
        };
        let source = g.packed_instance(prim).map(|i| Arc::as_ptr(&i.source))?;
        if sources.get(last) != Some(&source) {
            last = match sources.iter().position(|&x| x == source) {
                Some(i) => i,
                None => {
                    sources.push(source);
                    placed.groups.push(Group {
                        first_prim: prim,
                        translations: Vec::new(),
                        rotations: Vec::new(),
                        scales: Vec::new(),
                    });
                    sources.len() - 1
                }
            };
        }
        let group = &mut placed.groups[last];
        group.translations.push(t);
        group.rotations.push(r);
        group.scales.push(s);
    }
    Some(placed)
}

/// Parses glTF JSON or GLB, validated, accepting this extension among the
/// required ones (the `gltf` crate refuses extensions it does not know).
pub fn parse(bytes: &[u8]) -> ParseResult<gltf::Gltf> {
    let invalid = |e: gltf::Error| ParseError::whole(format!("invalid glTF: {e}"));
    let raw = gltf::Gltf::from_slice_without_validation(bytes).map_err(invalid)?;
    let mut root = raw.document.into_json();
    root.extensions_required.retain(|e| e != EXTENSION);
    let document = gltf::Document::from_json(root).map_err(invalid)?;
    Ok(gltf::Gltf {
        document,
        blob: raw.blob,
    })
}

/// The local transforms of a node's instances (`None`: the node has no
/// `EXT_mesh_gpu_instancing`): translation, rotation and scale, each
/// optional, float accessors of one count.
pub fn read_instances(
    node: &gltf::Node,
    doc: &gltf::Document,
    buffers: &[Vec<u8>],
) -> ParseResult<Option<Vec<Mat4>>> {
    use gltf::accessor::{DataType, Dimensions};
    let Some(ext) = node.extension_value(EXTENSION) else {
        return Ok(None);
    };
    let bad =
        |what: String| ParseError::whole(format!("node {}: {EXTENSION}: {what}", node.index()));
    let attributes = ext
        .get("attributes")
        .and_then(|a| a.as_object())
        .ok_or_else(|| bad("no attributes".into()))?;
    let mut count = None;
    let mut column = |name: &str, dims: Dimensions| -> ParseResult<Option<Vec<f32>>> {
        let Some(index) = attributes.get(name) else {
            return Ok(None);
        };
        let accessor = index
            .as_u64()
            .and_then(|i| doc.accessors().nth(i as usize))
            .ok_or_else(|| bad(format!("{name} refers to no accessor")))?;
        if accessor.dimensions() != dims || accessor.data_type() != DataType::F32 {
            return Err(bad(format!(
                "{name} is {:?} {:?}; geode reads {dims:?} floats",
                accessor.dimensions(),
                accessor.data_type()
            )));
        }
        if *count.get_or_insert(accessor.count()) != accessor.count() {
            return Err(bad("its attributes differ in count".into()));
        }
        check_accessor(&accessor, buffers)?;
        let get = |b: gltf::Buffer| buffers.get(b.index()).map(|v| v.as_slice());
        let values: Vec<f32> = match dims {
            Dimensions::Vec4 => gltf::accessor::Iter::<[f32; 4]>::new(accessor, get)
                .map(|it| it.flatten().collect())
                .unwrap_or_default(),
            _ => gltf::accessor::Iter::<[f32; 3]>::new(accessor, get)
                .map(|it| it.flatten().collect())
                .unwrap_or_default(),
        };
        Ok(Some(values))
    };
    let t = column("TRANSLATION", Dimensions::Vec3)?;
    let r = column("ROTATION", Dimensions::Vec4)?;
    let s = column("SCALE", Dimensions::Vec3)?;
    let n = count.unwrap_or(0);
    let at3 = |c: &Option<Vec<f32>>, i: usize, or: Vec3| {
        c.as_ref()
            .and_then(|v| v.get(3 * i..3 * i + 3))
            .map_or(or, Vec3::from_slice)
    };
    Ok(Some(
        (0..n)
            .map(|i| {
                let rot = r
                    .as_ref()
                    .and_then(|v| v.get(4 * i..4 * i + 4))
                    .map_or(Quat::IDENTITY, |q| Quat::from_slice(q).normalize());
                Mat4::from_scale_rotation_translation(
                    at3(&s, i, Vec3::ONE),
                    rot,
                    at3(&t, i, Vec3::ZERO),
                )
            })
            .collect(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trs_holds_rotations_and_scales_but_not_shears() {
        let m = Mat4::from_scale_rotation_translation(
            Vec3::new(2.0, 0.5, 3.0),
            Quat::from_euler(geode_geo::glam::EulerRot::XYZ, 0.3, -1.2, 2.0),
            Vec3::new(1.0, -2.0, 5.0),
        );
        let (t, r, s) = as_trs(&m).expect("a TRS");
        let back = Mat4::from_scale_rotation_translation(s, r, t);
        assert!(back.abs_diff_eq(m, 1e-5));
        let mut shear = Mat4::IDENTITY;
        shear.y_axis.x = 0.5;
        assert!(as_trs(&shear).is_none());
        // A mirror is a negative scale.
        assert!(as_trs(&Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0))).is_some());
    }
}
