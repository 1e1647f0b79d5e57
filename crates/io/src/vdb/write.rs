//! Writes sparse volumes as a `.vdb` file: one float grid per volume, its
//! values uncompressed behind active-value masks (flags 2), its tree
//! grouped from the volume's leaves and tiles.

use std::collections::BTreeMap;

use rayon::prelude::*;

use geode_geo::volume::{Leaf, SparseVolume, VolumeClass};

use super::tree::{Inactive, Level, Mask, ALL_VALUES, LOWER, UPPER};
use super::{COMPRESS_ACTIVE_MASK, COMPRESS_ZIP, FILE_VERSION, FLOAT_TREE, MAGIC};

/// How value arrays are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VdbCompression {
    /// Raw values (what OpenVDB writes for level sets without Blosc).
    None,
    /// zlib streams, where they are smaller than the raw values.
    Zip,
}

/// A `.vdb` file holding `volumes` as float grids, in order. The file's
/// identifier is derived from its content, so equal volumes give equal
/// bytes.
pub fn write_vdb(volumes: &[&SparseVolume], compression: VdbCompression) -> Vec<u8> {
    let grids: Vec<Vec<u8>> = volumes
        .iter()
        .map(|v| {
            grid_body(
                v,
                Encoding {
                    bg: v.background,
                    zip: compression == VdbCompression::Zip,
                },
            )
        })
        .collect();
    let mut out = Vec::new();
    out.extend_from_slice(&MAGIC.to_le_bytes());
    out.extend_from_slice(&FILE_VERSION.to_le_bytes());
    out.extend_from_slice(&10u32.to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    out.push(1); // grid offsets present
    out.extend_from_slice(uuid(&grids).as_bytes());
    out.extend_from_slice(&0u32.to_le_bytes()); // no file metadata
    out.extend_from_slice(&(volumes.len() as i32).to_le_bytes());
    for (v, body) in volumes.iter().zip(&grids) {
        string(&mut out, &v.name);
        string(&mut out, FLOAT_TREE);
        string(&mut out, "");
        let grid_pos = out.len() as i64 + 24;
        let end_pos = grid_pos + body.len() as i64 - 8;
        let block_pos = grid_pos + topology_end(body);
        for pos in [grid_pos, block_pos, end_pos] {
            out.extend_from_slice(&pos.to_le_bytes());
        }
        out.extend_from_slice(&body[8..]);
    }
    out
}

/// A version-4 UUID from a hash of the grids.
fn uuid(grids: &[Vec<u8>]) -> String {
    let mut all = Vec::new();
    grids.iter().for_each(|g| all.extend_from_slice(g));
    let mut h = geode_geo::hash_bytes(&all).to_le_bytes();
    h[6] = (h[6] & 0x0f) | 0x40;
    h[8] = (h[8] & 0x3f) | 0x80;
    let hex: String = h.iter().map(|b| format!("{b:02x}")).collect();
    format!(
        "{}-{}-{}-{}-{}",
        &hex[0..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..32]
    )
}

fn string(out: &mut Vec<u8>, s: &str) {
    out.extend_from_slice(&(s.len() as u32).to_le_bytes());
    out.extend_from_slice(s.as_bytes());
}

/// The body's first eight bytes carry where its topology ends (its
/// buffers start), relative to the body after them.
fn topology_end(body: &[u8]) -> i64 {
    i64::from_le_bytes(body[..8].try_into().expect("eight bytes"))
}

/// A grid after its descriptor: a placeholder for the topology's length,
/// then flags, metadata, transform, topology, buffers.
fn grid_body(v: &SparseVolume, enc: Encoding) -> Vec<u8> {
    let mut out = vec![0u8; 8];
    let flags = COMPRESS_ACTIVE_MASK | if enc.zip { COMPRESS_ZIP } else { 0 };
    out.extend_from_slice(&flags.to_le_bytes());
    metadata(&mut out, v, enc);
    transform(&mut out, v);
    let tree = Tree::group(v);
    tree.write_topology(&mut out, enc);
    let end = (out.len() - 8) as i64;
    out[..8].copy_from_slice(&end.to_le_bytes());
    tree.write_buffers(&mut out, enc);
    out
}

/// A grid's value encoding: its background and whether arrays are zipped.
#[derive(Clone, Copy)]
struct Encoding {
    bg: f32,
    zip: bool,
}

/// The grid's metadata, sorted by name as OpenVDB writes it.
fn metadata(out: &mut Vec<u8>, v: &SparseVolume, enc: Encoding) {
    let (lo, hi) = v.active_bounds().unwrap_or(([i32::MAX; 3], [i32::MIN; 3]));
    let vec3i = |c: [i32; 3]| c.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let mut entries: Vec<(&str, &str, Vec<u8>)> = vec![
        ("file_bbox_max", "vec3i", vec3i(hi)),
        ("file_bbox_min", "vec3i", vec3i(lo)),
        (
            "file_compression",
            "string",
            if enc.zip {
                b"zip + active values".to_vec()
            } else {
                b"active values".to_vec()
            },
        ),
        (
            "file_voxel_count",
            "int64",
            (v.active_voxel_count() as i64).to_le_bytes().to_vec(),
        ),
        ("name", "string", v.name.as_bytes().to_vec()),
    ];
    let class = match v.class {
        VolumeClass::LevelSet => Some("level set"),
        VolumeClass::FogVolume => Some("fog volume"),
        VolumeClass::Unknown => None,
    };
    if let Some(c) = class {
        entries.insert(0, ("class", "string", c.as_bytes().to_vec()));
    }
    out.extend_from_slice(&(entries.len() as u32).to_le_bytes());
    for (name, ty, value) in entries {
        string(out, name);
        string(out, ty);
        out.extend_from_slice(&(value.len() as u32).to_le_bytes());
        out.extend_from_slice(&value);
    }
}

/// The map from index to world: OpenVDB's scale-translate map, uniform
/// when the three scales agree.
fn transform(out: &mut Vec<u8>, v: &SparseVolume) {
    let t = &v.transform;
    let uniform = t.scale.iter().all(|&s| s == t.scale[0]);
    string(
        out,
        if uniform {
            "UniformScaleTranslateMap"
        } else {
            "ScaleTranslateMap"
        },
    );
    let s = t.scale;
    let inv = s.map(|x| 1.0 / x);
    for vec in [
        t.translation,
        s,
        s.map(f64::abs),
        inv,
        inv.map(|x| x * x),
        inv.map(|x| x * 0.5),
    ] {
        vec.iter()
            .for_each(|x| out.extend_from_slice(&x.to_le_bytes()));
    }
}

/// An internal node: its children by slot and its tiles' values.
struct Internal<C> {
    children: BTreeMap<usize, C>,
    values: Vec<f32>,
    active: Mask,
}

impl<C> Internal<C> {
    fn new(level: Level, background: f32) -> Internal<C> {
        Internal {
            children: BTreeMap::new(),
            values: vec![background; level.slots()],
            active: Mask::new(level.slots()),
        }
    }
}

type Lower<'a> = Internal<&'a Leaf>;
type Upper<'a> = Internal<Lower<'a>>;

/// The volume as VDB's tree: upper nodes by origin (sorted as OpenVDB's
/// root map sorts them: x, then y, then z), and the root's tiles.
struct Tree<'a> {
    uppers: BTreeMap<[i32; 3], Upper<'a>>,
    root_tiles: Vec<([i32; 3], f32, bool)>,
}

impl<'a> Tree<'a> {
    fn group(v: &'a SparseVolume) -> Tree<'a> {
        let bg = v.background;
        let mut uppers: BTreeMap<[i32; 3], Upper> = BTreeMap::new();
        let mut root_tiles = Vec::new();
        for leaf in v.leaves() {
            let lower = lower_at(&mut uppers, leaf.origin, bg);
            lower.children.insert(LOWER.slot(leaf.origin), leaf);
        }
        for t in v.tiles() {
            let (slot, node) = match t.log2 {
                3 => {
                    let lower = lower_at(&mut uppers, t.origin, bg);
                    (LOWER.slot(t.origin), (&mut lower.values, &mut lower.active))
                }
                7 => {
                    let upper = upper_at(&mut uppers, t.origin, bg);
                    (UPPER.slot(t.origin), (&mut upper.values, &mut upper.active))
                }
                _ => {
                    root_tiles.push((t.origin, t.value, t.active));
                    continue;
                }
            };
            node.0[slot] = t.value;
            if t.active {
                node.1.set(slot);
            }
        }
        root_tiles.sort_by_key(|t| t.0);
        Tree { uppers, root_tiles }
    }

    fn write_topology(&self, out: &mut Vec<u8>, enc: Encoding) {
        out.extend_from_slice(&1i32.to_le_bytes()); // one buffer per leaf
        out.extend_from_slice(&enc.bg.to_le_bytes());
        out.extend_from_slice(&(self.root_tiles.len() as u32).to_le_bytes());
        out.extend_from_slice(&(self.uppers.len() as u32).to_le_bytes());
        for (origin, value, active) in &self.root_tiles {
            origin
                .iter()
                .for_each(|c| out.extend_from_slice(&c.to_le_bytes()));
            out.extend_from_slice(&value.to_le_bytes());
            out.push(*active as u8);
        }
        for (origin, upper) in &self.uppers {
            origin
                .iter()
                .for_each(|c| out.extend_from_slice(&c.to_le_bytes()));
            internal_topology(out, UPPER, upper, enc, |out, lower| {
                internal_topology(out, LOWER, lower, enc, |out, leaf| {
                    leaf_mask(leaf).write(out);
                })
            });
        }
    }

    /// The leaves' masks and values in topology order, encoded in
    /// parallel (zlib dominates) and joined in order.
    fn write_buffers(&self, out: &mut Vec<u8>, enc: Encoding) {
        let leaves: Vec<&Leaf> = self
            .uppers
            .values()
            .flat_map(|upper| upper.children.values())
            .flat_map(|lower| lower.children.values().copied())
            .collect();
        let encoded: Vec<Vec<u8>> = leaves
            .par_chunks(64)
            .map(|chunk| {
                let mut buf = Vec::new();
                for leaf in chunk {
                    let mask = leaf_mask(leaf);
                    mask.write(&mut buf);
                    values(&mut buf, &leaf.values[..], &mask, None, enc);
                }
                buf
            })
            .collect();
        encoded.iter().for_each(|b| out.extend_from_slice(b));
    }
}

fn upper_at<'m, 'a>(
    uppers: &'m mut BTreeMap<[i32; 3], Upper<'a>>,
    at: [i32; 3],
    bg: f32,
) -> &'m mut Upper<'a> {
    uppers
        .entry(UPPER.origin_of(at))
        .or_insert_with(|| Internal::new(UPPER, bg))
}

fn lower_at<'m, 'a>(
    uppers: &'m mut BTreeMap<[i32; 3], Upper<'a>>,
    at: [i32; 3],
    bg: f32,
) -> &'m mut Lower<'a> {
    upper_at(uppers, at, bg)
        .children
        .entry(UPPER.slot(at))
        .or_insert_with(|| Internal::new(LOWER, bg))
}

fn leaf_mask(leaf: &Leaf) -> Mask {
    Mask(leaf.active.to_vec())
}

/// An internal node's topology: child mask, value mask, values, children.
fn internal_topology<C>(
    out: &mut Vec<u8>,
    level: Level,
    node: &Internal<C>,
    enc: Encoding,
    child: impl Fn(&mut Vec<u8>, &C),
) {
    let mut children = Mask::new(level.slots());
    node.children.keys().for_each(|&n| children.set(n));
    children.write(out);
    node.active.write(out);
    let mut slots = node.values.clone();
    node.children.keys().for_each(|&n| slots[n] = 0.0);
    values(out, &slots, &node.active, Some(&children), enc);
    for c in node.children.values() {
        child(out, c);
    }
}

/// A node's values as OpenVDB's compressed array: the metadata byte, the
/// inactive values and selection mask it calls for, then the active values
/// (or every value).
fn values(out: &mut Vec<u8>, values: &[f32], active: &Mask, child: Option<&Mask>, enc: Encoding) {
    let inactive = Inactive::choose(values, active, child, enc.bg);
    out.push(inactive.metadata);
    let (val0, val1, selection) = Inactive::stores(inactive.metadata);
    if val0 {
        out.extend_from_slice(&inactive.val0.to_le_bytes());
    }
    if val1 {
        out.extend_from_slice(&inactive.val1.to_le_bytes());
    }
    if selection {
        inactive
            .selection
            .as_ref()
            .expect("a selection for metadata 3 to 5")
            .write(out);
    }
    let all = inactive.metadata == ALL_VALUES;
    let mut stored = Vec::with_capacity(4 * values.len());
    for (n, v) in values.iter().enumerate() {
        if all || active.get(n) {
            stored.extend_from_slice(&v.to_le_bytes());
        }
    }
    if !enc.zip {
        out.extend_from_slice(&stored);
        return;
    }
    // A zlib stream where it is smaller, else the raw bytes behind their
    // negated count (OpenVDB's rule).
    let packed = miniz_oxide::deflate::compress_to_vec_zlib(&stored, 6);
    if packed.len() < stored.len() {
        out.extend_from_slice(&(packed.len() as i64).to_le_bytes());
        out.extend_from_slice(&packed);
    } else {
        out.extend_from_slice(&(-(stored.len() as i64)).to_le_bytes());
        out.extend_from_slice(&stored);
    }
}
