//! A versioned binary form of a `Geometry` (the disk cache's): every column written whole, little-endian; packed sources named by content hash.
//!
//! Layout (version 1): magic `GEOG`, version, the three counts, the vertex
//! and offset columns, each primitive's kind, the instances (source hash
//! and transform), the patch bases, the four attribute tables (each
//! attribute's name, type, type info, default and column) and the point
//! and primitive groups. Everything observable is kept, so a decoded
//! geometry has the content hash of the one encoded. Payloads are typed
//! Rust values with no byte form: a geometry carrying one is refused.
//! Decoding checks every count and index against the bytes present before
//! allocating, so a damaged entry is an error, never a panic.

use std::collections::BTreeMap;
use std::sync::{Arc, OnceLock};

use glam::{Mat3, Mat4, Quat, Vec2, Vec3, Vec4};

use crate::attrib::{
    AttribClass, AttribData, AttribTable, AttribType, AttribValue, Attribute, StringColumn,
    TypeInfo,
};
use crate::geometry::{Geometry, PackedInstance, PrimKind};
use crate::group::Group;
use crate::patch::{KnotVector, PatchBasis};

const MAGIC: &[u8; 4] = b"GEOG";
/// Bumped whenever the layout changes: older entries then read as misses.
pub const CODEC_VERSION: u32 = 1;

/// Why a geometry has no byte form.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EncodeError {
    #[error("the geometry carries the payload `{0}`, which has no byte form")]
    Payload(String),
}

/// Why bytes are not a geometry.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DecodeError {
    #[error("truncated at byte {0}")]
    Truncated(usize),
    #[error("not an encoded geometry")]
    Magic,
    #[error("encoded by codec version {0}, this is {CODEC_VERSION}")]
    Version(u32),
    #[error("inconsistent: {0}")]
    Invalid(String),
    #[error("the packed source {0:032x} is not available")]
    MissingSource(u128),
}

/// Appends `g` to `out`; `source` is told of every distinct packed source
/// (by which it will be found again: its content hash).
pub fn encode(
    g: &Geometry,
    out: &mut Vec<u8>,
    source: &mut dyn FnMut(&Arc<Geometry>),
) -> Result<(), EncodeError> {
    if let Some(name) = g.payloads.keys().next() {
        return Err(EncodeError::Payload(name.clone()));
    }
    let mut w = Writer(out);
    w.bytes(MAGIC);
    w.u32(CODEC_VERSION);
    for n in [g.num_points(), g.num_vertices(), g.num_prims()] {
        w.u64(n as u64);
    }
    w.pod(&g.vertex_point);
    w.pod(&g.prim_offsets);
    for kind in &g.prim_kinds {
        let (tag, index) = match *kind {
            PrimKind::Polygon => (0u8, 0),
            PrimKind::Polyline => (1, 0),
            PrimKind::Packed(i) => (2, i),
            PrimKind::Patch(i) => (3, i),
        };
        w.0.push(tag);
        w.u32(index);
    }
    w.u64(g.packed.len() as u64);
    let mut seen = std::collections::HashSet::new();
    for inst in &g.packed {
        let hash = inst.source.content_hash();
        w.0.extend_from_slice(&hash.to_le_bytes());
        w.pod(&inst.transform.to_cols_array());
        if seen.insert(hash) {
            source(&inst.source);
        }
    }
    w.u64(g.patches.len() as u64);
    for b in &g.patches {
        for k in [&b.u, &b.v] {
            w.u32(k.order);
            w.u64(k.knots.len() as u64);
            w.pod(&k.knots);
        }
    }
    for table in [&g.points, &g.vertices, &g.prims, &g.detail] {
        w.table(table);
    }
    for groups in [&g.point_groups, &g.prim_groups] {
        w.u64(groups.len() as u64);
        for (name, grp) in groups {
            w.str(name);
            w.u64(grp.len() as u64);
            w.pod(grp.words());
        }
    }
    Ok(())
}

struct Writer<'a>(&'a mut Vec<u8>);

impl Writer<'_> {
    fn bytes(&mut self, b: &[u8]) {
        self.0.extend_from_slice(b);
    }
    fn u32(&mut self, x: u32) {
        self.bytes(&x.to_le_bytes());
    }
    fn u64(&mut self, x: u64) {
        self.bytes(&x.to_le_bytes());
    }
    fn str(&mut self, s: &str) {
        self.u64(s.len() as u64);
        self.bytes(s.as_bytes());
    }
    /// A column: its length is known to the reader from the counts.
    fn pod<T: bytemuck::Pod>(&mut self, v: &[T]) {
        self.bytes(bytemuck::cast_slice(v));
    }
    fn strings(&mut self, v: &[String]) {
        self.u64(v.len() as u64);
        v.iter().for_each(|s| self.str(s));
    }
    fn table(&mut self, t: &AttribTable) {
        self.u64(t.len() as u64);
        self.u64(t.num_attribs() as u64);
        for (name, a) in t.iter() {
            self.str(name);
            self.0.push(type_tag(a.attrib_type()));
            self.0.push(info_tag(a.type_info));
            self.data(&AttribData::filled(a.default_value(), 1));
            self.data(a.data());
        }
    }
    /// A column of the table's length: raw values, or rows with their lengths first.
    fn data(&mut self, d: &AttribData) {
        match d {
            AttribData::String(s) => {
                self.strings(&s.table);
                self.pod(&s.indices);
            }
            AttribData::IntArray(rows) => self.rows(rows),
            AttribData::FloatArray(rows) => self.rows(rows),
            AttribData::Vec3Array(rows) => self.rows(rows),
            AttribData::StringArray(rows) => {
                let lens: Vec<u32> = rows.iter().map(|r| r.len() as u32).collect();
                self.pod(&lens);
                rows.iter().flatten().for_each(|s| self.str(s));
            }
            numeric => self.bytes(numeric.as_bytes().expect("numeric column")),
        }
    }
    fn rows<T: bytemuck::Pod>(&mut self, rows: &[Vec<T>]) {
        let lens: Vec<u32> = rows.iter().map(|r| r.len() as u32).collect();
        self.pod(&lens);
        rows.iter().for_each(|r| self.pod(r));
    }
}

fn type_tag(t: AttribType) -> u8 {
    AttribType::ALL
        .iter()
        .position(|x| *x == t)
        .expect("every type listed") as u8
}

fn info_tag(t: TypeInfo) -> u8 {
    TypeInfo::ALL
        .iter()
        .position(|x| *x == t)
        .expect("every type info listed") as u8
}

/// Reads a geometry encoded by [`encode`]; `source` finds a packed source by its content hash.
pub fn decode(
    bytes: &[u8],
    source: &dyn Fn(u128) -> Option<Arc<Geometry>>,
) -> Result<Geometry, DecodeError> {
    let mut r = Reader { bytes, at: 0 };
    if r.take(4)? != MAGIC {
        return Err(DecodeError::Magic);
    }
    let version = r.u32()?;
    if version != CODEC_VERSION {
        return Err(DecodeError::Version(version));
    }
    let points = r.len()?;
    let vertices = r.len()?;
    let prims = r.len()?;
    let vertex_point: Vec<u32> = r.pod(vertices)?;
    let prim_offsets: Vec<u32> = r.pod(prims + 1)?;
    let mut prim_kinds = Vec::with_capacity(prims.min(r.left() / 5));
    for _ in 0..prims {
        let tag = r.take(1)?[0];
        let index = r.u32()?;
        prim_kinds.push(match tag {
            0 => PrimKind::Polygon,
            1 => PrimKind::Polyline,
            2 => PrimKind::Packed(index),
            3 => PrimKind::Patch(index),
            t => return Err(invalid(format!("primitive kind {t}"))),
        });
    }
    let n_packed = r.count()?;
    let mut packed = Vec::with_capacity(n_packed.min(r.left() / 80));
    for _ in 0..n_packed {
        let hash = u128::from_le_bytes(r.array()?);
        let m: Vec<f32> = r.pod(16)?;
        let source = source(hash).ok_or(DecodeError::MissingSource(hash))?;
        packed.push(PackedInstance {
            source,
            transform: Mat4::from_cols_slice(&m),
        });
    }
    let n_patches = r.count()?;
    let mut patches = Vec::with_capacity(n_patches.min(r.left() / 24));
    for _ in 0..n_patches {
        let mut knots = || -> Result<KnotVector, DecodeError> {
            let order = r.u32()?;
            let n = r.count()?;
            Ok(KnotVector {
                order,
                knots: r.pod(n)?,
            })
        };
        let (u, v) = (knots()?, knots()?);
        patches.push(PatchBasis { u, v });
    }
    let tables: Vec<AttribTable> = [
        AttribClass::Point,
        AttribClass::Vertex,
        AttribClass::Primitive,
        AttribClass::Detail,
    ]
    .into_iter()
    .map(|class| r.table(class))
    .collect::<Result<_, _>>()?;
    let mut groups: Vec<BTreeMap<String, Group>> = Vec::new();
    for len in [points, prims] {
        let n = r.count()?;
        let mut map = BTreeMap::new();
        for _ in 0..n {
            let name = r.str()?;
            let count = r.len()?;
            if count != len {
                return Err(invalid(format!(
                    "group `{name}` of {count} flags for {len} elements"
                )));
            }
            let words: Vec<u64> = r.pod(count.div_ceil(64))?;
            map.insert(name, Group::from_words(words, count));
        }
        groups.push(map);
    }
    if r.at != bytes.len() {
        return Err(invalid(format!(
            "{} bytes after the geometry",
            bytes.len() - r.at
        )));
    }
    let [pts, verts, prs, detail]: [AttribTable; 4] = tables.try_into().expect("four tables");
    let prim_groups = groups.pop().expect("two maps");
    let point_groups = groups.pop().expect("two maps");
    let g = Geometry {
        points: pts,
        vertices: verts,
        prims: prs,
        detail,
        vertex_point: vertex_point.into(),
        prim_offsets: prim_offsets.into(),
        prim_kinds: prim_kinds.into(),
        packed: packed.into(),
        patches,
        point_groups,
        prim_groups,
        payloads: BTreeMap::new(),
        topology: OnceLock::new(),
        content_hash: OnceLock::new(),
    };
    check(&g, points)?;
    Ok(g)
}

fn invalid(m: String) -> DecodeError {
    DecodeError::Invalid(m)
}

/// The structural promises every other geode function relies on.
fn check(g: &Geometry, points: usize) -> Result<(), DecodeError> {
    let lens = [
        (g.points.len(), points, "point"),
        (g.vertices.len(), g.vertex_point.len(), "vertex"),
        (g.prims.len(), g.prim_kinds.len(), "primitive"),
        (g.detail.len(), 1, "detail"),
    ];
    if let Some((found, want, class)) = lens.iter().find(|(a, b, _)| a != b) {
        return Err(invalid(format!(
            "{class} table of {found} elements, expected {want}"
        )));
    }
    if g.points.get(crate::geometry::P).map(|a| a.attrib_type()) != Some(AttribType::Vec3) {
        return Err(invalid("no vector3 `P`".into()));
    }
    let offsets = &g.prim_offsets;
    if offsets.first() != Some(&0)
        || offsets.windows(2).any(|w| w[0] > w[1])
        || offsets.last().map(|&o| o as usize) != Some(g.vertex_point.len())
    {
        return Err(invalid("primitive offsets".into()));
    }
    if g.vertex_point.iter().any(|&p| p as usize >= points) {
        return Err(invalid("a vertex refers to a missing point".into()));
    }
    for kind in &g.prim_kinds {
        let ok = match *kind {
            PrimKind::Packed(i) => (i as usize) < g.packed.len(),
            PrimKind::Patch(i) => (i as usize) < g.patches.len(),
            _ => true,
        };
        if !ok {
            return Err(invalid(
                "a primitive refers to a missing instance or patch".into(),
            ));
        }
    }
    Ok(())
}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn left(&self) -> usize {
        self.bytes.len() - self.at
    }
    fn take(&mut self, n: usize) -> Result<&'a [u8], DecodeError> {
        if n > self.left() {
            return Err(DecodeError::Truncated(self.at));
        }
        self.at += n;
        Ok(&self.bytes[self.at - n..self.at])
    }
    fn array<const N: usize>(&mut self) -> Result<[u8; N], DecodeError> {
        let mut a = [0; N];
        a.copy_from_slice(self.take(N)?);
        Ok(a)
    }
    fn u32(&mut self) -> Result<u32, DecodeError> {
        Ok(u32::from_le_bytes(self.array()?))
    }
    /// A number of elements (a table's may exceed the bytes: a table
    /// without attributes stores none); nothing is allocated from it alone.
    fn len(&mut self) -> Result<usize, DecodeError> {
        let n = u64::from_le_bytes(self.array()?);
        usize::try_from(n)
            .ok()
            .filter(|&n| n <= u32::MAX as usize)
            .ok_or(DecodeError::Truncated(self.at))
    }
    /// A count of items each stored in at least one byte: refused when the
    /// bytes left could not hold that many.
    fn count(&mut self) -> Result<usize, DecodeError> {
        let n = u64::from_le_bytes(self.array()?);
        if n > self.left() as u64 {
            return Err(DecodeError::Truncated(self.at));
        }
        Ok(n as usize)
    }
    fn str(&mut self) -> Result<String, DecodeError> {
        let n = self.count()?;
        String::from_utf8(self.take(n)?.to_vec()).map_err(|_| invalid("a name is not UTF-8".into()))
    }
    fn pod<T: bytemuck::Pod>(&mut self, n: usize) -> Result<Vec<T>, DecodeError> {
        let size = n
            .checked_mul(std::mem::size_of::<T>())
            .ok_or(DecodeError::Truncated(self.at))?;
        let bytes = self.take(size)?;
        // Copied into an aligned column (the entry's bytes need not be aligned).
        let mut v = vec![T::zeroed(); n];
        bytemuck::cast_slice_mut::<T, u8>(&mut v).copy_from_slice(bytes);
        Ok(v)
    }
    fn strings(&mut self) -> Result<Vec<String>, DecodeError> {
        let n = self.count()?;
        (0..n).map(|_| self.str()).collect()
    }
    fn rows<T: bytemuck::Pod>(&mut self, n: usize) -> Result<Vec<Vec<T>>, DecodeError> {
        let lens: Vec<u32> = self.pod(n)?;
        lens.iter().map(|&l| self.pod(l as usize)).collect()
    }
    fn data(&mut self, ty: AttribType, n: usize) -> Result<AttribData, DecodeError> {
        Ok(match ty {
            AttribType::Float => AttribData::Float(self.pod(n)?),
            AttribType::Int => AttribData::Int(self.pod(n)?),
            AttribType::Vec2 => AttribData::Vec2(self.pod::<Vec2>(n)?),
            AttribType::Vec3 => AttribData::Vec3(self.pod::<Vec3>(n)?),
            AttribType::Vec4 => AttribData::Vec4(self.pod::<Vec4>(n)?),
            AttribType::Quat => AttribData::Quat(self.pod::<Quat>(n)?),
            AttribType::Mat4 => AttribData::Mat4(self.pod::<Mat4>(n)?),
            AttribType::Mat3 => AttribData::Mat3(self.pod::<Mat3>(n)?),
            AttribType::String => {
                let table = self.strings()?;
                let indices: Vec<u32> = self.pod(n)?;
                if indices.iter().any(|&i| i as usize >= table.len()) {
                    return Err(invalid("a string index beyond its table".into()));
                }
                AttribData::String(StringColumn { table, indices })
            }
            AttribType::IntArray => AttribData::IntArray(self.rows(n)?),
            AttribType::FloatArray => AttribData::FloatArray(self.rows(n)?),
            AttribType::Vec3Array => AttribData::Vec3Array(self.rows(n)?),
            AttribType::StringArray => {
                let lens: Vec<u32> = self.pod(n)?;
                let rows = lens
                    .iter()
                    .map(|&l| (0..l).map(|_| self.str()).collect::<Result<Vec<_>, _>>())
                    .collect::<Result<_, _>>()?;
                AttribData::StringArray(rows)
            }
        })
    }
    fn table(&mut self, class: AttribClass) -> Result<AttribTable, DecodeError> {
        let len = self.len()?;
        let n = self.count()?;
        let mut t = AttribTable::new(class, len);
        for _ in 0..n {
            let name = self.str()?;
            let tag = self.take(2)?;
            let ty = *AttribType::ALL
                .get(tag[0] as usize)
                .ok_or_else(|| invalid(format!("attribute type {}", tag[0])))?;
            let info = *TypeInfo::ALL
                .get(tag[1] as usize)
                .ok_or_else(|| invalid(format!("type info {}", tag[1])))?;
            let default: AttribValue = self.data(ty, 1)?.get(0);
            let data = self.data(ty, len)?;
            let a = Attribute::from_data(data, info)
                .with_default(default)
                .map_err(|_| invalid(format!("`{name}`: default of another type")))?;
            t.insert(&name, a).map_err(|e| invalid(e.to_string()))?;
        }
        Ok(t)
    }
}
