//! Fields and sparse volumes both ways: a field sampled into a narrow-band
//! level set (OpenVDB's kind: signed distances within a half width of the
//! surface, constant tiles inside, background outside), and a volume as a
//! field (trilinear between voxel centres, positive inside).
//!
//! Sampling prunes top-down: a block of voxels needs values only where the
//! field may have surface within the half width of it, which the interval
//! evaluator decides over the block grown by the half width (a field
//! without a zero there is wholly inside or outside: a tile, or nothing).
//! The blocks left take the field's signed distance at their voxel centres.

use geode_geo::volume::{
    Leaf, SparseVolume, Tile, VolumeClass, VoxelTransform, LEAF_SIDE, LEAF_VOXELS,
};
use rayon::prelude::*;

use crate::codec::{FieldDecodeError, Reader};
use crate::eval::{BatchEval, IntervalEval};
use crate::interval::Interval;
use crate::{distance, Field, Tape};

/// Why a field cannot be sampled.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SampleError {
    #[error("the bounds must have max > min on every axis")]
    Bounds,
    #[error("the voxel size must be finite and positive")]
    VoxelSize,
    #[error("the half width must be at least one voxel")]
    HalfWidth,
    #[error("{0:.3e} voxels in the bounds: too many to sample (at most 2^42, a box of 16384 voxels along every side)")]
    TooManyVoxels(f64),
    #[error("the narrow band holds over {leaves} leaves of voxels, {bytes} bytes, more than the memory budget of {budget}")]
    TooLarge {
        leaves: u64,
        bytes: u64,
        budget: u64,
    },
    #[error("cancelled")]
    Cancelled,
}

/// Bytes a sampled leaf holds.
const LEAF_COST: u64 = (4 * LEAF_VOXELS + 128) as u64;

/// Where and how finely to sample.
#[derive(Clone, Copy, Debug)]
pub struct SampleOptions {
    pub min: [f64; 3],
    pub max: [f64; 3],
    /// The edge of a voxel; voxel centres sit at its multiples.
    pub voxel_size: f64,
    /// Voxels on each side of the surface that hold distances.
    pub half_width: f64,
    /// Bytes the sampled volume may hold: planning stops past it.
    pub memory_budget: u64,
}

/// The sampling's first pass: the leaves that need values, and the tiles
/// that fill the inside.
pub struct SamplePlan {
    options: SampleOptions,
    leaves: Vec<[i32; 3]>,
    tiles: Vec<Tile>,
}

/// One block's leaves to sample and its tiles.
type BlockPlan = (Vec<[i32; 3]>, Vec<Tile>);

/// Blocks of leaves classified together (a lower VDB node's span).
const BLOCK_LOG2: u32 = 7;

impl SamplePlan {
    /// Classifies the bounds' blocks by the field's intervals.
    pub fn new(
        f: &Field,
        options: SampleOptions,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<SamplePlan, SampleError> {
        let o = options;
        if !(o.voxel_size.is_finite() && o.voxel_size > 0.0) {
            return Err(SampleError::VoxelSize);
        }
        if !(o.half_width >= 1.0 && o.half_width.is_finite()) {
            return Err(SampleError::HalfWidth);
        }
        if !(0..3).all(|k| o.min[k].is_finite() && o.max[k].is_finite() && o.max[k] > o.min[k]) {
            return Err(SampleError::Bounds);
        }
        // Refused before any block list is made: the count of voxels, in
        // floating point (it may not fit any integer).
        let lo: [f64; 3] = std::array::from_fn(|k| (o.min[k] / o.voxel_size).floor());
        let hi: [f64; 3] = std::array::from_fn(|k| (o.max[k] / o.voxel_size).ceil());
        let voxels: f64 = (0..3).map(|k| hi[k] - lo[k] + 1.0).product();
        let limit = (1u64 << 30) as f64;
        if voxels > (1u64 << 42) as f64 || (0..3).any(|k| lo[k] < -limit || hi[k] > limit) {
            return Err(SampleError::TooManyVoxels(voxels));
        }
        let lo = lo.map(|v| v as i32);
        let hi = hi.map(|v| v as i32);
        let tape = Tape::compile(f);
        let band = o.half_width * o.voxel_size;
        // Whether the field may have surface within the band of the voxel
        // box `a..=b`: Some(inside) when it has not.
        let settled = |eval: &mut IntervalEval, a: [i32; 3], b: [i32; 3]| -> Option<bool> {
            let span = |k: usize| {
                Interval::new(
                    a[k] as f64 * o.voxel_size - band,
                    b[k] as f64 * o.voxel_size + band,
                )
            };
            let v = eval.eval(span(0), span(1), span(2));
            (v.lo > 0.0 || v.hi < 0.0).then_some(v.lo > 0.0)
        };
        let blocks = blocks_between(lo, hi, BLOCK_LOG2);
        let planned = std::sync::atomic::AtomicU64::new(0);
        let over = |leaves: usize| {
            let total = planned.fetch_add(leaves as u64, std::sync::atomic::Ordering::Relaxed)
                + leaves as u64;
            total * LEAF_COST > o.memory_budget
        };
        let classified: Vec<Option<BlockPlan>> = blocks
            .par_iter()
            .map_init(
                || IntervalEval::new(&tape),
                |eval, &block| {
                    if cancel() || over(0) {
                        return None;
                    }
                    let end = block.map(|v| v + (1 << BLOCK_LOG2) - 1);
                    let mut leaves = Vec::new();
                    let mut tiles = Vec::new();
                    match settled(eval, block, end) {
                        Some(true) => tiles.push(inside_tile(block, BLOCK_LOG2, band)),
                        Some(false) => {}
                        None => {
                            let a: [i32; 3] = std::array::from_fn(|k| lo[k].max(block[k]));
                            let b: [i32; 3] = std::array::from_fn(|k| hi[k].min(end[k]));
                            for leaf in blocks_between(a, b, 3) {
                                match settled(eval, leaf, leaf.map(|v| v + LEAF_SIDE - 1)) {
                                    Some(true) => tiles.push(inside_tile(leaf, 3, band)),
                                    Some(false) => {}
                                    None => leaves.push(leaf),
                                }
                            }
                        }
                    }
                    (!over(leaves.len())).then_some((leaves, tiles))
                },
            )
            .collect();
        let mut plan = SamplePlan {
            options,
            leaves: Vec::new(),
            tiles: Vec::new(),
        };
        let leaves = planned.into_inner();
        if leaves * LEAF_COST > o.memory_budget {
            return Err(SampleError::TooLarge {
                leaves,
                bytes: leaves * LEAF_COST,
                budget: o.memory_budget,
            });
        }
        for c in classified {
            let (leaves, tiles) = c.ok_or(SampleError::Cancelled)?;
            plan.leaves.extend(leaves);
            plan.tiles.extend(tiles);
        }
        Ok(plan)
    }

    /// Leaves the sampling will fill.
    pub fn leaf_count(&self) -> usize {
        self.leaves.len()
    }

    /// Bytes the sampled volume will hold.
    pub fn bytes(&self) -> u64 {
        self.leaves.len() as u64 * LEAF_COST + self.tiles.len() as u64 * 64
    }

    /// The level set: the field's signed distance (negated: negative
    /// inside, as VDB's) at every voxel of the planned leaves, clamped to
    /// the half width, active within it. A leaf left without an active
    /// voxel becomes a tile or nothing.
    pub fn sample(
        self,
        f: &Field,
        name: &str,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<SparseVolume, SampleError> {
        let o = self.options;
        let bg = (o.half_width * o.voxel_size) as f32;
        // The side from the field itself, the magnitude from its distance
        // estimate: where the field's gradient vanishes (a gyroid's
        // channels), Newton steps may land on the other side, the field
        // never does.
        let distance = distance::signed_distance(f);
        let exact = distance.identity() == f.identity();
        let side_tape = Tape::compile(f);
        let distance_tape = Tape::compile(&distance);
        let filled: Vec<Option<Result<Leaf, Option<Tile>>>> = self
            .leaves
            .par_iter()
            .map_init(
                || {
                    (
                        BatchEval::new(&side_tape),
                        BatchEval::new(&distance_tape),
                        LeafPoints::default(),
                    )
                },
                |(side_eval, distance_eval, pts), &origin| {
                    if cancel() {
                        return None;
                    }
                    pts.fill(origin, o.voxel_size);
                    let mut side = [0.0f32; LEAF_VOXELS];
                    side_eval.eval(&pts.x, &pts.y, &pts.z, &mut side);
                    if !exact {
                        let mut d = [0.0f32; LEAF_VOXELS];
                        distance_eval.eval(&pts.x, &pts.y, &pts.z, &mut d);
                        for (s, d) in side.iter_mut().zip(d) {
                            let magnitude = if d.is_nan() { f32::INFINITY } else { d.abs() };
                            *s = if *s > 0.0 {
                                magnitude
                            } else if *s < 0.0 {
                                -magnitude
                            } else {
                                *s
                            };
                        }
                    }
                    Some(level_set_leaf(origin, &side, bg))
                },
            )
            .collect();
        let mut leaves = Vec::with_capacity(filled.len());
        let mut tiles = self.tiles;
        for leaf in filled {
            match leaf.ok_or(SampleError::Cancelled)? {
                Ok(l) => leaves.push(l),
                Err(Some(t)) => tiles.push(t),
                Err(None) => {}
            }
        }
        let transform = VoxelTransform::uniform(o.voxel_size, [0.0; 3]);
        Ok(
            SparseVolume::new(name, VolumeClass::LevelSet, transform, bg, leaves, tiles)
                .expect("sampled blocks are aligned and distinct"),
        )
    }
}

/// A tile of the inside (-background, inactive).
fn inside_tile(origin: [i32; 3], log2: u32, band: f64) -> Tile {
    Tile {
        origin,
        log2,
        value: -(band as f32),
        active: false,
    }
}

/// The origins of the aligned blocks of `2^log2` voxels meeting `lo..=hi`,
/// x slowest.
fn blocks_between(lo: [i32; 3], hi: [i32; 3], log2: u32) -> Vec<[i32; 3]> {
    let first = lo.map(|v| v >> log2);
    let last = hi.map(|v| v >> log2);
    let mut out = Vec::new();
    for x in first[0]..=last[0] {
        for y in first[1]..=last[1] {
            for z in first[2]..=last[2] {
                out.push([x << log2, y << log2, z << log2]);
            }
        }
    }
    out
}

/// A leaf's voxel centres, laid out for the batch evaluator.
#[derive(Default)]
struct LeafPoints {
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
}

impl LeafPoints {
    fn fill(&mut self, origin: [i32; 3], voxel: f64) {
        self.x.clear();
        self.y.clear();
        self.z.clear();
        for n in 0..LEAF_VOXELS {
            let local = [n >> 6, (n >> 3) & 7, n & 7];
            let at = |k: usize| ((origin[k] + local[k] as i32) as f64 * voxel) as f32;
            self.x.push(at(0));
            self.y.push(at(1));
            self.z.push(at(2));
        }
    }
}

/// A leaf from distances positive inside; a tile (or nothing) when no
/// voxel lies within the band.
fn level_set_leaf(origin: [i32; 3], d: &[f32; LEAF_VOXELS], bg: f32) -> Result<Leaf, Option<Tile>> {
    let mut values = Box::new([0.0f32; LEAF_VOXELS]);
    let mut active = [0u64; 8];
    for (n, &dist) in d.iter().enumerate() {
        let phi = -dist;
        // NaN (no value) reads as outside.
        values[n] = if phi.is_nan() { bg } else { phi.clamp(-bg, bg) };
        if phi.abs() < bg {
            active[n >> 6] |= 1 << (n & 63);
        }
    }
    if active.iter().any(|&w| w != 0) {
        return Ok(Leaf {
            origin,
            active,
            values,
        });
    }
    if values.iter().all(|&v| v < 0.0) {
        Err(Some(Tile {
            origin,
            log2: 3,
            value: -bg,
            active: false,
        }))
    } else if values.iter().all(|&v| v > 0.0) {
        Err(None)
    } else {
        Ok(Leaf {
            origin,
            active,
            values,
        })
    }
}

/// A sparse volume as a field: trilinear between voxel centres, level sets
/// negated so the inside is positive; other volumes (densities) less an
/// isovalue, so the inside is where they pass it.
#[derive(Debug, PartialEq)]
pub struct VolumeField {
    volume: SparseVolume,
    sign: f64,
    iso: f64,
    identity: u128,
}

impl VolumeField {
    /// A level set's field (any other volume's surface at 0).
    pub fn new(volume: SparseVolume) -> VolumeField {
        VolumeField::with_iso(volume, 0.0)
    }

    /// A volume's field; a volume other than a level set has its surface
    /// where its values pass `iso` (a level set's is at 0: `iso` is unused).
    pub fn with_iso(volume: SparseVolume, iso: f64) -> VolumeField {
        let level_set = volume.class == VolumeClass::LevelSet;
        let (sign, iso) = if level_set { (-1.0, 0.0) } else { (1.0, iso) };
        let mut bytes = Vec::new();
        encode_volume(&volume, &mut bytes);
        bytes.extend_from_slice(&iso.to_le_bytes());
        VolumeField {
            identity: geode_geo::hash_bytes(&bytes),
            volume,
            sign,
            iso,
        }
    }

    pub fn volume(&self) -> &SparseVolume {
        &self.volume
    }

    pub fn identity(&self) -> u128 {
        self.identity
    }

    /// Leaves held.
    pub fn len(&self) -> usize {
        self.volume.leaves().len()
    }

    pub fn is_empty(&self) -> bool {
        self.volume.leaves().is_empty() && self.volume.tiles().is_empty()
    }

    pub fn memory_bytes(&self) -> usize {
        self.volume.memory_bytes()
    }

    /// A thousandth of the smallest voxel edge.
    pub fn difference_step(&self) -> f64 {
        1e-3 * self
            .volume
            .transform
            .scale
            .iter()
            .map(|s| s.abs())
            .fold(f64::INFINITY, f64::min)
    }

    pub fn value(&self, p: [f64; 3]) -> f64 {
        self.sign * self.volume.sample(p) - self.iso
    }

    pub fn value_gradient(&self, p: [f64; 3]) -> (f64, [f64; 3]) {
        let (v, g) = self.volume.sample_gradient(p);
        (self.sign * v - self.iso, g.map(|c| self.sign * c))
    }

    /// Bounds over a box: the least and greatest voxel value among the
    /// voxels whose values the box's samples blend (trilinear samples are
    /// convex combinations of them).
    pub fn interval(&self, x: Interval, y: Interval, z: Interval) -> Interval {
        let spans = [x, y, z];
        let (lo, hi) = if spans.iter().all(|s| s.lo.is_finite() && s.hi.is_finite()) {
            let t = &self.volume.transform;
            let a = t.to_index(spans.map(|s| s.lo));
            let b = t.to_index(spans.map(|s| s.hi));
            let index = |v: f64| v.clamp(i32::MIN as f64 / 2.0, i32::MAX as f64 / 2.0);
            let lo: [i32; 3] = std::array::from_fn(|k| index(a[k].min(b[k]).floor()) as i32);
            let hi: [i32; 3] = std::array::from_fn(|k| index(a[k].max(b[k]).ceil()) as i32);
            self.volume.range_over(lo, hi, 4096)
        } else {
            self.volume.range()
        };
        let (a, b) = (
            self.sign * lo as f64 - self.iso,
            self.sign * hi as f64 - self.iso,
        );
        Interval::new(a.min(b), a.max(b))
    }

    pub fn values(&self, xs: &[f32], ys: &[f32], zs: &[f32], out: &mut [f32]) {
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.value([xs[i], ys[i], zs[i]].map(f64::from)) as f32;
        }
    }

    pub(crate) fn encode(&self, out: &mut Vec<u8>) {
        encode_volume(&self.volume, out);
        out.extend_from_slice(&self.iso.to_le_bytes());
    }

    pub(crate) fn decode(r: &mut Reader) -> Result<VolumeField, FieldDecodeError> {
        let volume = decode_volume(r)?;
        Ok(VolumeField::with_iso(volume, r.f64()?))
    }
}

fn encode_volume(v: &SparseVolume, out: &mut Vec<u8>) {
    let mut put = |b: &[u8]| out.extend_from_slice(b);
    put(&(v.name.len() as u64).to_le_bytes());
    put(v.name.as_bytes());
    put(&[match v.class {
        VolumeClass::LevelSet => 0,
        VolumeClass::FogVolume => 1,
        VolumeClass::Unknown => 2,
    }]);
    for x in v.transform.scale.iter().chain(&v.transform.translation) {
        put(&x.to_le_bytes());
    }
    put(&v.background.to_le_bytes());
    put(&(v.leaves().len() as u64).to_le_bytes());
    for l in v.leaves() {
        l.origin.iter().for_each(|c| put(&c.to_le_bytes()));
        l.active.iter().for_each(|w| put(&w.to_le_bytes()));
        l.values.iter().for_each(|x| put(&x.to_le_bytes()));
    }
    put(&(v.tiles().len() as u64).to_le_bytes());
    for t in v.tiles() {
        t.origin.iter().for_each(|c| put(&c.to_le_bytes()));
        put(&[t.log2 as u8, t.active as u8]);
        put(&t.value.to_le_bytes());
    }
}

fn decode_volume(r: &mut Reader) -> Result<SparseVolume, FieldDecodeError> {
    let i32_at =
        |b: &[u8], k: usize| i32::from_le_bytes(b[4 * k..4 * k + 4].try_into().expect("4"));
    let name_len = r.count(1)?;
    let name = String::from_utf8(r.take(name_len)?.to_vec())
        .map_err(|_| FieldDecodeError::Invalid("volume name".into()))?;
    let class = match r.take(1)?[0] {
        0 => VolumeClass::LevelSet,
        1 => VolumeClass::FogVolume,
        2 => VolumeClass::Unknown,
        c => return Err(FieldDecodeError::Invalid(format!("volume class {c}"))),
    };
    let scale = [r.f64()?, r.f64()?, r.f64()?];
    let translation = [r.f64()?, r.f64()?, r.f64()?];
    let background = r.f32()?;
    const LEAF_BYTES: usize = 12 + 64 + 4 * LEAF_VOXELS;
    let n_leaves = r.count(LEAF_BYTES)?;
    let mut leaves = Vec::with_capacity(n_leaves);
    for _ in 0..n_leaves {
        let b = r.take(LEAF_BYTES)?;
        let origin = [i32_at(b, 0), i32_at(b, 1), i32_at(b, 2)];
        let active = std::array::from_fn(|k| {
            u64::from_le_bytes(b[12 + 8 * k..20 + 8 * k].try_into().expect("8"))
        });
        let mut values = Box::new([0.0f32; LEAF_VOXELS]);
        for (n, v) in values.iter_mut().enumerate() {
            *v = f32::from_le_bytes(b[76 + 4 * n..80 + 4 * n].try_into().expect("4"));
        }
        leaves.push(Leaf {
            origin,
            active,
            values,
        });
    }
    let n_tiles = r.count(18)?;
    let mut tiles = Vec::with_capacity(n_tiles);
    for _ in 0..n_tiles {
        let b = r.take(18)?;
        tiles.push(Tile {
            origin: [i32_at(b, 0), i32_at(b, 1), i32_at(b, 2)],
            log2: b[12] as u32,
            active: b[13] != 0,
            value: f32::from_le_bytes(b[14..18].try_into().expect("4")),
        });
    }
    SparseVolume::new(
        name,
        class,
        VoxelTransform { scale, translation },
        background,
        leaves,
        tiles,
    )
    .map_err(|e| FieldDecodeError::Invalid(format!("volume: {e}")))
}
