//! Content hash (xxh3-128) of a geometry: equal for equal content whatever its history.
//!
//! Every large array (each attribute column, each connectivity array) enters
//! as its own digest, cached with the array (`shared.rs`): a geometry that
//! shares all but one column with a hashed one hashes that column only.

use rayon::prelude::*;
use xxhash_rust::xxh3::{xxh3_128, Xxh3};

use crate::attrib::{AttribData, AttribTable, AttribValue};
use crate::geometry::{Geometry, PrimKind};

/// Columns larger than this are hashed in parallel chunks of this size; the
/// chunk size is fixed so the result never depends on the thread count.
const CHUNK: usize = 1 << 20;

/// Hashes a byte slice; large slices are split into fixed chunks hashed in
/// parallel and the chunk digests are hashed again.
pub fn hash_bytes(bytes: &[u8]) -> u128 {
    if bytes.len() <= 4 * CHUNK {
        return xxh3_128(bytes);
    }
    let digests: Vec<u128> = bytes.par_chunks(CHUNK).map(xxh3_128).collect();
    let mut h = Xxh3::new();
    h.update(&(bytes.len() as u64).to_le_bytes());
    h.update(bytemuck::cast_slice(&digests));
    h.digest128()
}

fn put_str(h: &mut Xxh3, s: &str) {
    h.update(&(s.len() as u64).to_le_bytes());
    h.update(s.as_bytes());
}

fn put_value(h: &mut Xxh3, v: &AttribValue) {
    match v {
        AttribValue::Float(x) => h.update(&x.to_le_bytes()),
        AttribValue::Int(x) => h.update(&x.to_le_bytes()),
        AttribValue::Vec2(x) => h.update(bytemuck::bytes_of(x)),
        AttribValue::Vec3(x) => h.update(bytemuck::bytes_of(x)),
        AttribValue::Vec4(x) => h.update(bytemuck::bytes_of(x)),
        AttribValue::Quat(x) => h.update(bytemuck::bytes_of(x)),
        AttribValue::Mat4(x) => h.update(bytemuck::bytes_of(x)),
        AttribValue::Mat3(x) => h.update(bytemuck::bytes_of(x)),
        AttribValue::String(s) => put_str(h, s),
        AttribValue::IntArray(a) => put_array(h, bytemuck::cast_slice(a)),
        AttribValue::FloatArray(a) => put_array(h, bytemuck::cast_slice(a)),
        AttribValue::Vec3Array(a) => put_array(h, bytemuck::cast_slice(a)),
        AttribValue::StringArray(a) => {
            h.update(&(a.len() as u64).to_le_bytes());
            a.iter().for_each(|s| put_str(h, s));
        }
    }
}

/// An array value: its length then its bytes, so element boundaries count.
fn put_array(h: &mut Xxh3, bytes: &[u8]) {
    h.update(&(bytes.len() as u64).to_le_bytes());
    h.update(bytes);
}

/// Strings hash by value: indices are renumbered in order of first use so two
/// columns with different tables but the same strings hash equally.
fn strings_digest(table: &[String], indices: &[u32]) -> u128 {
    let mut h = Xxh3::new();
    let mut remap = vec![u32::MAX; table.len()];
    let mut order: Vec<u32> = Vec::new();
    let canonical: Vec<u32> = indices
        .iter()
        .map(|&i| {
            let slot = &mut remap[i as usize];
            if *slot == u32::MAX {
                *slot = order.len() as u32;
                order.push(i);
            }
            *slot
        })
        .collect();
    h.update(&(order.len() as u64).to_le_bytes());
    for &i in &order {
        put_str(&mut h, &table[i as usize]);
    }
    h.update(&hash_bytes(bytemuck::cast_slice(&canonical)).to_le_bytes());
    h.digest128()
}

/// Per-element arrays: each row's length and bytes, in one digest.
fn rows_digest<'a>(rows: impl Iterator<Item = &'a [u8]>) -> u128 {
    let mut r = Xxh3::new();
    rows.for_each(|a| put_array(&mut r, a));
    r.digest128()
}

/// The digest of a column's values (what the column's cache keeps).
fn values_digest(data: &AttribData) -> u128 {
    match data {
        AttribData::String(s) => strings_digest(&s.table, &s.indices),
        AttribData::IntArray(rows) => rows_digest(rows.iter().map(|a| bytemuck::cast_slice(a))),
        AttribData::FloatArray(rows) => rows_digest(rows.iter().map(|a| bytemuck::cast_slice(a))),
        AttribData::Vec3Array(rows) => rows_digest(rows.iter().map(|a| bytemuck::cast_slice(a))),
        AttribData::StringArray(rows) => {
            let mut r = Xxh3::new();
            for row in rows {
                r.update(&(row.len() as u64).to_le_bytes());
                row.iter().for_each(|s| put_str(&mut r, s));
            }
            r.digest128()
        }
        d => hash_bytes(d.as_bytes().expect("numeric column")),
    }
}

fn put_table(h: &mut Xxh3, t: &AttribTable) {
    h.update(&(t.len() as u64).to_le_bytes());
    h.update(&(t.num_attribs() as u64).to_le_bytes());
    for (name, a) in t.iter() {
        put_str(h, name);
        put_str(h, &a.attrib_type().to_string());
        put_str(h, &a.type_info.to_string());
        put_value(h, a.default_value());
        h.update(&a.values_hash(values_digest).to_le_bytes());
    }
}

/// Primitives whose instances and patches one parallel task hashes.
const PRIMS_PER_CHUNK: usize = 1 << 14;

/// A packed instance by its source's content and its transform, a patch by
/// its bases; nothing for a polygon or a polyline (their vertices are
/// hashed with the connectivity).
fn put_instance_or_patch(h: &mut Vec<u8>, g: &Geometry, kind: &PrimKind) {
    match kind {
        PrimKind::Packed(i) => {
            let inst = &g.packed[*i as usize];
            h.extend_from_slice(&inst.source.content_hash().to_le_bytes());
            h.extend_from_slice(bytemuck::bytes_of(&inst.transform));
        }
        PrimKind::Patch(i) => {
            let basis = &g.patches[*i as usize];
            for side in [&basis.u, &basis.v] {
                h.extend_from_slice(&side.order.to_le_bytes());
                h.extend_from_slice(&(side.knots.len() as u64).to_le_bytes());
                h.extend_from_slice(bytemuck::cast_slice(&side.knots));
            }
        }
        PrimKind::Polygon | PrimKind::Polyline => {}
    }
}

pub(crate) fn compute(g: &Geometry) -> u128 {
    let mut h = Xxh3::new();
    // v2: a string column enters as one digest.
    h.update(b"geode-geometry-v2");
    put_table(&mut h, &g.points);
    put_table(&mut h, &g.vertices);
    put_table(&mut h, &g.prims);
    put_table(&mut h, &g.detail);
    let words = |v: &Vec<u32>| hash_bytes(bytemuck::cast_slice(v));
    h.update(&g.vertex_point.hash_with(words).to_le_bytes());
    h.update(&g.prim_offsets.hash_with(words).to_le_bytes());
    // Kinds as bytes; packed instances by their source's content and transform,
    // in primitive order, so the instance table's internal order does not matter.
    let kinds = g.prim_kinds.hash_with(|kinds| {
        let bytes: Vec<u8> = kinds
            .par_iter()
            .with_min_len(PRIMS_PER_CHUNK)
            .map(|k| match k {
                PrimKind::Polygon => 0u8,
                PrimKind::Polyline => 1,
                PrimKind::Packed(_) => 2,
                PrimKind::Patch(_) => 3,
            })
            .collect();
        hash_bytes(&bytes)
    });
    h.update(&kinds.to_le_bytes());
    // Fixed chunks of primitives hashed in parallel, digests in order.
    let chunks = g.prim_kinds.len().div_ceil(PRIMS_PER_CHUNK);
    if g.packed.is_empty() && g.patches.is_empty() {
        // No primitive is an instance or a patch: every chunk's bytes are
        // empty (the same digests, without the walk).
        let empty = xxh3_128(&[]).to_le_bytes();
        (0..chunks).for_each(|_| h.update(&empty));
    } else {
        let digests: Vec<u128> = g
            .prim_kinds
            .par_chunks(PRIMS_PER_CHUNK)
            .map(|kinds| {
                // Gathered into one buffer: xxh3 is many times faster on one
                // long input than on a million short updates.
                let mut bytes = Vec::new();
                for k in kinds {
                    put_instance_or_patch(&mut bytes, g, k);
                }
                xxh3_128(&bytes)
            })
            .collect();
        h.update(bytemuck::cast_slice(&digests));
    }
    put_str(&mut h, "payloads");
    h.update(&(g.payloads.len() as u64).to_le_bytes());
    for (name, p) in &g.payloads {
        put_str(&mut h, name);
        h.update(&p.identity().to_le_bytes());
    }
    for (kind, groups) in [("point", &g.point_groups), ("prim", &g.prim_groups)] {
        put_str(&mut h, kind);
        h.update(&(groups.len() as u64).to_le_bytes());
        for (name, grp) in groups {
            put_str(&mut h, name);
            h.update(&(grp.len() as u64).to_le_bytes());
            h.update(&hash_bytes(bytemuck::cast_slice(grp.words())).to_le_bytes());
        }
    }
    h.digest128()
}

impl Geometry {
    /// xxh3-128 of everything observable: attributes (names, types, tags,
    /// defaults, values), connectivity, groups and packed instances (by their
    /// sources' content). Cached until the geometry is mutated.
    pub fn content_hash(&self) -> u128 {
        *self.content_hash.get_or_init(|| compute(self))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attrib::{AttribClass, Attribute, TypeInfo};
    use glam::Vec3;

    fn quad() -> Geometry {
        Geometry::from_polygons(
            vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            vec![0, 1, 2, 3],
            &[4],
        )
        .unwrap()
    }

    #[test]
    fn vector_and_string_array_columns_hash_by_value() {
        let with = |rows: Vec<Vec<String>>, vecs: Vec<Vec<Vec3>>| {
            let mut g = quad();
            let data = crate::AttribData::StringArray(rows);
            g.set_attrib(
                AttribClass::Point,
                "tags",
                Attribute::from_data(data, TypeInfo::None),
            )
            .unwrap();
            let data = crate::AttribData::Vec3Array(vecs);
            g.set_attrib(
                AttribClass::Point,
                "dirs",
                Attribute::from_data(data, TypeInfo::None),
            )
            .unwrap();
            g.content_hash()
        };
        let rows = |last: &str| {
            vec![
                vec![],
                vec!["a".into()],
                vec!["b".into(), last.into()],
                vec![],
            ]
        };
        let vecs = |y: f32| vec![vec![Vec3::X], vec![], vec![Vec3::new(0.0, y, 0.0)], vec![]];
        assert_eq!(with(rows("c"), vecs(1.0)), with(rows("c"), vecs(1.0)));
        assert_ne!(with(rows("c"), vecs(1.0)), with(rows("d"), vecs(1.0)));
        assert_ne!(with(rows("c"), vecs(1.0)), with(rows("c"), vecs(2.0)));
    }

    #[test]
    fn equal_content_equal_hash_whatever_history() {
        let a = quad();
        // Built point by point instead of in bulk.
        let mut b = Geometry::new();
        for p in a.positions() {
            b.add_point(*p);
        }
        b.add_polygon(&[0, 1, 2, 3]).unwrap();
        assert_eq!(a.content_hash(), b.content_hash());

        // String tables in different orders but the same per-element strings.
        let mut c = a.clone();
        let mut d = a.clone();
        let mut s1 = Attribute::new(AttribValue::String("x".into()), TypeInfo::None, 4);
        s1.values_mut()
            .set(1, &AttribValue::String("y".into()))
            .unwrap();
        let mut s2 = Attribute::new(AttribValue::String("y".into()), TypeInfo::None, 4);
        s2.values_mut()
            .set(0, &AttribValue::String("x".into()))
            .unwrap();
        for i in [2, 3] {
            s2.values_mut()
                .set(i, &AttribValue::String("x".into()))
                .unwrap();
        }
        let s2 = s2.with_default(AttribValue::String("x".into())).unwrap();
        c.set_attrib(AttribClass::Point, "name", s1).unwrap();
        d.set_attrib(AttribClass::Point, "name", s2).unwrap();
        assert_eq!(c.content_hash(), d.content_hash());
    }

    #[test]
    fn any_change_changes_hash() {
        let a = quad();
        let mut b = a.clone();
        b.positions_mut()[2].x += 1e-6;
        assert_ne!(a.content_hash(), b.content_hash());
        let mut c = a.clone();
        c.add_point(Vec3::ZERO);
        assert_ne!(a.content_hash(), c.content_hash());
        let mut d = a.clone();
        d.set_point_group("g", crate::Group::new(4)).unwrap();
        assert_ne!(a.content_hash(), d.content_hash());
    }

    #[test]
    fn chunked_hash_is_stable() {
        let data: Vec<u8> = (0..(9 * CHUNK + 17))
            .map(|i| (i * 31 % 251) as u8)
            .collect();
        let a = hash_bytes(&data);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let b = pool.install(|| hash_bytes(&data));
        assert_eq!(a, b);
    }
}
