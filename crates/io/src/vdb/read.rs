//! Reads the float grids of a `.vdb` file as sparse volumes: header,
//! descriptors, metadata, transform, the tree's topology, then its leaf
//! buffers, every value array in whichever encoding the grid's flags name.
//! Every length is checked against the bytes left before it is used, and
//! the voxels held against a memory budget before they are allocated.

use geode_geo::volume::{Leaf, SparseVolume, Tile, VolumeClass, VoxelTransform, LEAF_VOXELS};

use super::tree::{Inactive, Level, Mask, ALL_VALUES, LEAF, LOWER, UPPER};
use super::{
    blosc, VdbError, COMPRESS_ACTIVE_MASK, COMPRESS_BLOSC, COMPRESS_ZIP, FLOAT_TREE, MAGIC,
    OLDEST_VERSION,
};

/// Bytes a leaf costs once read.
const LEAF_BYTES: u64 = (std::mem::size_of::<Leaf>() + 4 * LEAF_VOXELS + 32) as u64;

/// Every float grid of the file, in order. Grids of other value types
/// and instances of grids are skipped; a file without a float grid is an
/// error naming what it holds.
pub fn read_vdb(
    bytes: &[u8],
    memory_budget: u64,
    cancelled: &dyn Fn() -> bool,
) -> Result<Vec<SparseVolume>, VdbError> {
    let mut r = Cursor {
        bytes,
        at: 0,
        leaves: 0,
        budget: memory_budget,
        cancelled,
    };
    let offsets = r.header()?;
    r.skip_metadata()?;
    let grids = r.i32()?;
    if grids < 0 {
        return Err(r.error(format!("{grids} grids")));
    }
    let mut volumes = Vec::new();
    let mut skipped = Vec::new();
    for _ in 0..grids {
        let name = r.string()?;
        let tree_type = r.string()?;
        let parent = r.string()?;
        let ends = if offsets {
            let [_, _, end] = [r.i64()?, r.i64()?, r.i64()?];
            Some(end)
        } else {
            None
        };
        let base = tree_type.strip_suffix("_HalfFloat").unwrap_or(&tree_type);
        if base != FLOAT_TREE || !parent.is_empty() {
            let Some(end) = ends else {
                return Err(r.error(format!(
                    "grid {name:?} holds {tree_type}, which geode does not read, in a file without grid offsets to skip it by"
                )));
            };
            skipped.push(format!("{name:?} ({tree_type})"));
            r.seek(end)?;
            continue;
        }
        volumes.push(r.grid(&name, tree_type.ends_with("_HalfFloat"))?);
        if let Some(end) = ends {
            r.seek(end)?;
        }
    }
    if volumes.is_empty() {
        return Err(r.error(if skipped.is_empty() {
            "the file holds no grid".to_string()
        } else {
            format!("the file holds no float grid, only {}", skipped.join(", "))
        }));
    }
    Ok(volumes)
}

/// The grid's metadata that reading needs.
struct GridMeta {
    name: Option<String>,
    class: VolumeClass,
    half: Option<bool>,
}

/// A tree's topology before its leaf values are read.
struct Topology {
    background: f32,
    leaves: Vec<Leaf>,
    tiles: Vec<Tile>,
}

struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
    leaves: u64,
    budget: u64,
    cancelled: &'a dyn Fn() -> bool,
}

impl Cursor<'_> {
    fn error(&self, message: impl Into<String>) -> VdbError {
        VdbError::Malformed {
            offset: self.at as u64,
            message: message.into(),
        }
    }

    fn take(&mut self, n: usize) -> Result<&[u8], VdbError> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let Some(end) = end else {
            return Err(self.error(format!(
                "{n} bytes expected, {} left in the file",
                self.bytes.len() - self.at
            )));
        };
        let s = &self.bytes[self.at..end];
        self.at = end;
        Ok(s)
    }

    fn array<const N: usize>(&mut self) -> Result<[u8; N], VdbError> {
        Ok(self.take(N)?.try_into().expect("N bytes"))
    }

    fn u8(&mut self) -> Result<u8, VdbError> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Result<u32, VdbError> {
        self.array().map(u32::from_le_bytes)
    }
    fn i32(&mut self) -> Result<i32, VdbError> {
        self.array().map(i32::from_le_bytes)
    }
    fn i64(&mut self) -> Result<i64, VdbError> {
        self.array().map(i64::from_le_bytes)
    }
    fn f32(&mut self) -> Result<f32, VdbError> {
        self.array().map(f32::from_le_bytes)
    }
    fn f64(&mut self) -> Result<f64, VdbError> {
        self.array().map(f64::from_le_bytes)
    }
    fn vec3d(&mut self) -> Result<[f64; 3], VdbError> {
        Ok([self.f64()?, self.f64()?, self.f64()?])
    }
    fn coord(&mut self) -> Result<[i32; 3], VdbError> {
        Ok([self.i32()?, self.i32()?, self.i32()?])
    }

    fn string(&mut self) -> Result<String, VdbError> {
        let n = self.u32()? as usize;
        let at = self.at;
        let s = self.take(n)?;
        String::from_utf8(s.to_vec()).map_err(|_| VdbError::Malformed {
            offset: at as u64,
            message: "a name that is not UTF-8".into(),
        })
    }

    fn seek(&mut self, to: i64) -> Result<(), VdbError> {
        match usize::try_from(to) {
            Ok(to) if to >= self.at && to <= self.bytes.len() => {
                self.at = to;
                Ok(())
            }
            _ => Err(self.error(format!("a grid's end at byte {to}, outside the file"))),
        }
    }

    fn mask(&mut self, slots: usize) -> Result<Mask, VdbError> {
        let bytes = self.take(slots / 8)?;
        Ok(Mask(
            bytes
                .chunks_exact(8)
                .map(|w| u64::from_le_bytes(w.try_into().expect("eight bytes")))
                .collect(),
        ))
    }

    /// The header; whether grids carry their offsets.
    fn header(&mut self) -> Result<bool, VdbError> {
        if self.i64()? != MAGIC {
            self.at = 0;
            return Err(self.error("not an OpenVDB file (its magic number is missing)"));
        }
        let version = self.u32()?;
        if version < OLDEST_VERSION {
            return Err(self.error(format!(
                "file format version {version}; geode reads {OLDEST_VERSION} and later (OpenVDB 3 onwards)"
            )));
        }
        self.take(8)?; // the library's version
        let offsets = self.u8()? != 0;
        self.take(36)?; // the file's UUID
        Ok(offsets)
    }

    /// Skips a metadata map.
    fn skip_metadata(&mut self) -> Result<(), VdbError> {
        for _ in 0..self.u32()? {
            self.string()?;
            self.string()?;
            let n = self.u32()? as usize;
            self.take(n)?;
        }
        Ok(())
    }

    fn grid_metadata(&mut self) -> Result<GridMeta, VdbError> {
        let mut meta = GridMeta {
            name: None,
            class: VolumeClass::Unknown,
            half: None,
        };
        for _ in 0..self.u32()? {
            let name = self.string()?;
            let ty = self.string()?;
            let n = self.u32()? as usize;
            let value = self.take(n)?;
            match (name.as_str(), ty.as_str()) {
                ("name", "string") => meta.name = Some(String::from_utf8_lossy(value).into()),
                ("class", "string") => {
                    meta.class = match value {
                        b"level set" => VolumeClass::LevelSet,
                        b"fog volume" => VolumeClass::FogVolume,
                        _ => VolumeClass::Unknown,
                    }
                }
                ("is_saved_as_half_float", "bool") => meta.half = value.first().map(|&b| b != 0),
                _ => {}
            }
        }
        Ok(meta)
    }

    /// The map from index to world; rotations and shears are refused.
    fn transform(&mut self) -> Result<VoxelTransform, VdbError> {
        let kind = self.string()?;
        let (scale, translation) = match kind.as_str() {
            "UniformScaleTranslateMap" | "ScaleTranslateMap" => {
                let t = self.vec3d()?;
                let s = self.vec3d()?;
                self.take(4 * 24)?;
                (s, t)
            }
            "UniformScaleMap" | "ScaleMap" => {
                let s = self.vec3d()?;
                self.take(4 * 24)?;
                (s, [0.0; 3])
            }
            "TranslationMap" => ([1.0; 3], self.vec3d()?),
            "AffineMap" => {
                let m: Vec<f64> = (0..16).map(|_| self.f64()).collect::<Result<_, _>>()?;
                let off_diagonal = [1, 2, 4, 6, 8, 9, 3, 7, 11];
                if off_diagonal.iter().any(|&k| m[k] != 0.0) || m[15] != 1.0 {
                    return Err(self.error(
                        "a rotated, sheared or projective voxel transform; geode reads scales and translations",
                    ));
                }
                ([m[0], m[5], m[10]], [m[12], m[13], m[14]])
            }
            other => {
                return Err(self.error(format!(
                    "a voxel transform of kind {other:?}; geode reads scales and translations"
                )))
            }
        };
        if !(scale.iter().all(|s| s.is_finite() && *s != 0.0)
            && translation.iter().all(|t| t.is_finite()))
        {
            return Err(self.error("a voxel transform with a zero or non-finite scale"));
        }
        Ok(VoxelTransform { scale, translation })
    }

    fn grid(&mut self, descriptor_name: &str, half_type: bool) -> Result<SparseVolume, VdbError> {
        let flags = self.u32()?;
        let meta = self.grid_metadata()?;
        let half = meta.half.unwrap_or(half_type);
        let transform = self.transform()?;
        let codec = Codec { flags, half };
        let mut topology = self.topology(codec)?;
        for (n, leaf) in topology.leaves.iter_mut().enumerate() {
            if n % 1024 == 0 && (self.cancelled)() {
                return Err(VdbError::Cancelled);
            }
            // The buffer repeats the leaf's mask; a file reader keeps the
            // topology's copy, as OpenVDB's does.
            self.take(LEAF.slots() / 8)?;
            let active = Mask(leaf.active.to_vec());
            let values = self.values(LEAF, &active, codec, topology.background)?;
            leaf.values.copy_from_slice(&values);
        }
        let name = meta.name.unwrap_or_else(|| {
            descriptor_name
                .split('\u{1e}')
                .next()
                .unwrap_or_default()
                .to_string()
        });
        SparseVolume::new(
            name,
            meta.class,
            transform,
            topology.background,
            topology.leaves,
            topology.tiles,
        )
        .map_err(|e| self.error(format!("the grid's tree: {e}")))
    }

    fn topology(&mut self, codec: Codec) -> Result<Topology, VdbError> {
        let buffers = self.i32()?;
        if buffers != 1 {
            return Err(self.error(format!("{buffers} buffers per leaf (expected 1)")));
        }
        let background = self.f32()?;
        let (n_tiles, n_children) = (self.u32()?, self.u32()?);
        let mut t = Topology {
            background,
            leaves: Vec::new(),
            tiles: Vec::new(),
        };
        for _ in 0..n_tiles {
            let origin = self.coord()?;
            let value = self.f32()?;
            let active = self.u8()? != 0;
            t.tiles.push(Tile {
                origin: UPPER.origin_of(origin),
                log2: 12,
                value,
                active,
            });
        }
        for _ in 0..n_children {
            let origin = self.coord()?;
            if UPPER.origin_of(origin) != origin {
                return Err(self.error(format!(
                    "a root child at {origin:?}, not a multiple of 4096"
                )));
            }
            self.internal(UPPER, origin, codec, &mut t)?;
        }
        Ok(t)
    }

    /// An internal node's topology and its children's, recorded in `t`.
    fn internal(
        &mut self,
        level: Level,
        origin: [i32; 3],
        codec: Codec,
        t: &mut Topology,
    ) -> Result<(), VdbError> {
        let children = self.mask(level.slots())?;
        let active = self.mask(level.slots())?;
        // Child slots take whatever value is stored: the children replace them.
        let values = self.values(level, &active, codec, t.background)?;
        for (n, &value) in values.iter().enumerate() {
            let is_active = active.get(n);
            if !children.get(n) && (is_active || value.to_bits() != t.background.to_bits()) {
                t.tiles.push(Tile {
                    origin: level.slot_origin(origin, n),
                    log2: level.child_log2,
                    value,
                    active: is_active,
                });
            }
        }
        for n in (0..level.slots()).filter(|&n| children.get(n)) {
            let at = level.slot_origin(origin, n);
            if level.child_log2 == UPPER.child_log2 {
                self.internal(LOWER, at, codec, t)?;
            } else {
                self.leaves += 1;
                let bytes = self.leaves * LEAF_BYTES;
                if bytes > self.budget {
                    return Err(VdbError::TooLarge {
                        leaves: self.leaves,
                        bytes,
                        budget: self.budget,
                    });
                }
                let mask = self.mask(LEAF.slots())?;
                t.leaves.push(Leaf {
                    origin: at,
                    active: mask.0.try_into().expect("eight words"),
                    values: Box::new([t.background; LEAF_VOXELS]),
                });
            }
        }
        Ok(())
    }

    /// A node's value array: the metadata byte and what it calls for, then
    /// the stored values, with inactive slots restored.
    fn values(
        &mut self,
        level: Level,
        active: &Mask,
        codec: Codec,
        bg: f32,
    ) -> Result<Vec<f32>, VdbError> {
        let slots = level.slots();
        let metadata = self.u8()?;
        if metadata > ALL_VALUES {
            return Err(self.error(format!("value compression {metadata} (expected 0 to 6)")));
        }
        let mut inactive = Inactive::defaults(metadata, bg);
        let (val0, val1, selection) = Inactive::stores(metadata);
        if val0 {
            inactive.val0 = self.f32()?;
        }
        if val1 {
            inactive.val1 = self.f32()?;
        }
        if selection {
            inactive.selection = Some(self.mask(slots)?);
        }
        let every = codec.flags & COMPRESS_ACTIVE_MASK == 0 || metadata == ALL_VALUES;
        let count = if every { slots } else { active.count() };
        let stored = self.chunk(count, codec)?;
        if every {
            return Ok(stored);
        }
        let mut stored = stored.into_iter();
        Ok((0..slots)
            .map(|n| {
                if active.get(n) {
                    stored.next().unwrap_or(bg)
                } else {
                    inactive.value(n)
                }
            })
            .collect())
    }

    /// `count` values in the grid's encoding.
    fn chunk(&mut self, count: usize, codec: Codec) -> Result<Vec<f32>, VdbError> {
        let size = if codec.half { 2 } else { 4 };
        if codec.half && count == 0 {
            return Ok(Vec::new());
        }
        let expected = count * size;
        let raw: Vec<u8> = if codec.flags & (COMPRESS_BLOSC | COMPRESS_ZIP) != 0 {
            let n = self.i64()?;
            if n <= 0 {
                if n.unsigned_abs() != expected as u64 {
                    return Err(self.error(format!(
                        "{} stored bytes where {expected} were expected",
                        n.unsigned_abs()
                    )));
                }
                self.take(expected)?.to_vec()
            } else {
                let n = usize::try_from(n).map_err(|_| self.error("a chunk too large"))?;
                let at = self.at;
                let packed = self.take(n)?;
                let unpacked = if codec.flags & COMPRESS_BLOSC != 0 {
                    blosc::decompress(packed, expected)
                } else {
                    inflate(packed, expected)
                };
                unpacked.map_err(|message| VdbError::Malformed {
                    offset: at as u64,
                    message,
                })?
            }
        } else {
            self.take(expected)?.to_vec()
        };
        Ok(if codec.half {
            raw.chunks_exact(2)
                .map(|b| half_to_f32(u16::from_le_bytes([b[0], b[1]])))
                .collect()
        } else {
            raw.chunks_exact(4)
                .map(|b| f32::from_le_bytes(b.try_into().expect("four bytes")))
                .collect()
        })
    }
}

/// How a grid's values are stored.
#[derive(Clone, Copy)]
struct Codec {
    flags: u32,
    half: bool,
}

/// A zlib stream that must inflate to exactly `expected` bytes.
fn inflate(packed: &[u8], expected: usize) -> Result<Vec<u8>, String> {
    let out = miniz_oxide::inflate::decompress_to_vec_zlib_with_limit(packed, expected)
        .map_err(|e| format!("zlib data: {:?}", e.status))?;
    if out.len() != expected {
        return Err(format!(
            "zlib data of {} bytes where {expected} were expected",
            out.len()
        ));
    }
    Ok(out)
}

/// An IEEE binary16 value as f32.
fn half_to_f32(h: u16) -> f32 {
    let sign = ((h >> 15) as u32) << 31;
    let exponent = ((h >> 10) & 0x1f) as u32;
    let mantissa = (h & 0x3ff) as u32;
    let bits = match exponent {
        0 if mantissa == 0 => sign,
        0 => {
            // Subnormal: value = mantissa * 2^-24.
            let v = mantissa as f32 * (1.0 / 16_777_216.0);
            return if sign != 0 { -v } else { v };
        }
        31 => sign | 0x7f80_0000 | (mantissa << 13),
        e => sign | ((e + 112) << 23) | (mantissa << 13),
    };
    f32::from_bits(bits)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halves_convert_exactly() {
        assert_eq!(half_to_f32(0x3c00), 1.0);
        assert_eq!(half_to_f32(0xc000), -2.0);
        assert_eq!(half_to_f32(0x3555), 0.333_251_95);
        assert_eq!(half_to_f32(0x0001), 5.960_464_5e-8);
        assert_eq!(half_to_f32(0x7c00), f32::INFINITY);
        assert!(half_to_f32(0x7e00).is_nan());
        assert_eq!(half_to_f32(0x8000).to_bits(), (-0.0f32).to_bits());
    }
}
