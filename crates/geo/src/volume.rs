//! Sparse voxel volumes shaped as OpenVDB's trees: values in leaves of 8^3
//! voxels, constant tiles of 8^3, 128^3 and 4096^3 voxels (the spans of
//! VDB's leaf, lower and upper internal nodes) and a background elsewhere,
//! mapped to space by a per-axis scale and a translation (voxel centres at
//! integer indices). One model serves fields sampled on a narrow band and
//! VDB files read and written: the spans are VDB's so a file's tree maps
//! onto this one node for node.

use std::collections::HashMap;

/// Voxels along a leaf's side.
pub const LEAF_SIDE: i32 = 8;
/// Voxels in a leaf.
pub const LEAF_VOXELS: usize = 512;
/// log2 of the tile spans, smallest first: a leaf-sized tile, a lower
/// internal node's and an upper internal node's.
pub const TILE_LOG2: [u32; 3] = [3, 7, 12];

/// How near (in voxels) a point must be to a voxel centre to read its
/// value unblended.
const SNAP: f64 = 1e-4;

/// What a volume's values mean (VDB's grid class).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VolumeClass {
    /// Signed distances, negative inside (VDB's convention).
    LevelSet,
    /// Densities, zero outside.
    FogVolume,
    /// Anything else.
    Unknown,
}

/// Index space to world: `world = index * scale + translation`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoxelTransform {
    pub scale: [f64; 3],
    pub translation: [f64; 3],
}

impl VoxelTransform {
    pub fn uniform(voxel_size: f64, translation: [f64; 3]) -> VoxelTransform {
        VoxelTransform {
            scale: [voxel_size; 3],
            translation,
        }
    }

    /// The continuous index of a world point.
    pub fn to_index(&self, p: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|k| (p[k] - self.translation[k]) / self.scale[k])
    }

    /// The world position of a voxel centre.
    pub fn to_world(&self, i: [i32; 3]) -> [f64; 3] {
        std::array::from_fn(|k| i[k] as f64 * self.scale[k] + self.translation[k])
    }
}

/// 8^3 voxel values, z fastest (VDB's order), and which are active.
#[derive(Clone, Debug, PartialEq)]
pub struct Leaf {
    /// The voxel index of its lowest corner (a multiple of 8).
    pub origin: [i32; 3],
    /// Bit `n` of word `n / 64`: voxel `n` is active.
    pub active: [u64; 8],
    pub values: Box<[f32; LEAF_VOXELS]>,
}

impl Leaf {
    /// The linear index of a voxel within its leaf.
    pub fn offset(i: [i32; 3]) -> usize {
        (((i[0] & 7) << 6) | ((i[1] & 7) << 3) | (i[2] & 7)) as usize
    }

    /// The index of voxel `n` (the inverse of [`Leaf::offset`]).
    pub fn voxel(&self, n: usize) -> [i32; 3] {
        let local = [n >> 6, (n >> 3) & 7, n & 7];
        std::array::from_fn(|k| self.origin[k] + local[k] as i32)
    }

    pub fn is_active(&self, n: usize) -> bool {
        self.active[n >> 6] >> (n & 63) & 1 == 1
    }

    pub fn active_count(&self) -> u64 {
        self.active.iter().map(|w| w.count_ones() as u64).sum()
    }
}

/// A cube of one value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tile {
    /// Its lowest voxel (a multiple of its span).
    pub origin: [i32; 3],
    /// log2 of its span, one of [`TILE_LOG2`].
    pub log2: u32,
    pub value: f32,
    pub active: bool,
}

/// Why a volume cannot be built.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum VolumeError {
    #[error("the voxel transform must have finite, nonzero scales and a finite translation")]
    Transform,
    #[error("a {0} at ({1}, {2}, {3}) is not aligned to its span")]
    Unaligned(&'static str, i32, i32, i32),
    #[error("two {0}s at ({1}, {2}, {3})")]
    Duplicate(&'static str, i32, i32, i32),
    #[error("a tile span of 2^{0} voxels (expected 2^3, 2^7 or 2^12)")]
    Span(u32),
    #[error("a tile of 2^{0} voxels at ({1}, {2}, {3}) covers a leaf or a smaller tile")]
    Overlap(u32, i32, i32, i32),
}

/// A sparse volume (see the module doc).
#[derive(Clone, Debug)]
pub struct SparseVolume {
    pub name: String,
    pub class: VolumeClass,
    pub transform: VoxelTransform,
    pub background: f32,
    leaves: Vec<Leaf>,
    tiles: Vec<Tile>,
    leaf_at: HashMap<[i32; 3], u32>,
    tile_at: [HashMap<[i32; 3], u32>; 3],
    /// Per leaf: its values' least and greatest.
    leaf_range: Vec<(f32, f32)>,
    /// Every value the volume holds, background included.
    range: (f32, f32),
}

impl PartialEq for SparseVolume {
    fn eq(&self, o: &Self) -> bool {
        self.name == o.name
            && self.class == o.class
            && self.transform == o.transform
            && self.background.to_bits() == o.background.to_bits()
            && self.leaves == o.leaves
            && self.tiles == o.tiles
    }
}

impl SparseVolume {
    /// A volume of leaves and tiles (in any order: they are sorted by span,
    /// then origin, so equal content is equal volumes).
    pub fn new(
        name: impl Into<String>,
        class: VolumeClass,
        transform: VoxelTransform,
        background: f32,
        mut leaves: Vec<Leaf>,
        mut tiles: Vec<Tile>,
    ) -> Result<SparseVolume, VolumeError> {
        let ok = |v: f64| v.is_finite();
        if !(transform.scale.iter().all(|&s| ok(s) && s != 0.0)
            && transform.translation.iter().all(|&t| ok(t)))
        {
            return Err(VolumeError::Transform);
        }
        leaves.sort_by_key(|l| l.origin);
        tiles.sort_by_key(|t| (t.log2, t.origin));
        let mut leaf_at = HashMap::with_capacity(leaves.len());
        for (n, l) in leaves.iter().enumerate() {
            let [x, y, z] = l.origin;
            if l.origin.iter().any(|v| v & 7 != 0) {
                return Err(VolumeError::Unaligned("leaf", x, y, z));
            }
            if leaf_at.insert(l.origin, n as u32).is_some() {
                return Err(VolumeError::Duplicate("leaf", x, y, z));
            }
        }
        let mut tile_at: [HashMap<[i32; 3], u32>; 3] = Default::default();
        for (n, t) in tiles.iter().enumerate() {
            let [x, y, z] = t.origin;
            let level = TILE_LOG2
                .iter()
                .position(|&l| l == t.log2)
                .ok_or(VolumeError::Span(t.log2))?;
            let mask = (1i32 << t.log2) - 1;
            if t.origin.iter().any(|v| v & mask != 0) {
                return Err(VolumeError::Unaligned("tile", x, y, z));
            }
            if tile_at[level].insert(t.origin, n as u32).is_some() {
                return Err(VolumeError::Duplicate("tile", x, y, z));
            }
        }
        let covered = |at: [i32; 3], below: usize| -> Option<&Tile> {
            (below..3).find_map(|level| {
                let key = at.map(|v| v & !((1i32 << TILE_LOG2[level]) - 1));
                tile_at[level].get(&key).map(|&n| &tiles[n as usize])
            })
        };
        let nested = leaves
            .iter()
            .find_map(|l| covered(l.origin, 0))
            .or_else(|| {
                tiles.iter().find_map(|t| {
                    let level = TILE_LOG2.iter().position(|&l| l == t.log2)?;
                    covered(t.origin, level + 1)
                })
            });
        if let Some(t) = nested {
            let [x, y, z] = t.origin;
            return Err(VolumeError::Overlap(t.log2, x, y, z));
        }
        let leaf_range: Vec<(f32, f32)> = leaves
            .iter()
            .map(|l| {
                l.values
                    .iter()
                    .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &v| {
                        (a.min(v), b.max(v))
                    })
            })
            .collect();
        let range = leaf_range
            .iter()
            .copied()
            .chain(tiles.iter().map(|t| (t.value, t.value)))
            .fold((background, background), |(a, b), (lo, hi)| {
                (a.min(lo), b.max(hi))
            });
        Ok(SparseVolume {
            name: name.into(),
            class,
            transform,
            background,
            leaves,
            tiles,
            leaf_at,
            tile_at,
            leaf_range,
            range,
        })
    }

    /// Leaves in ascending order of origin.
    pub fn leaves(&self) -> &[Leaf] {
        &self.leaves
    }

    /// Tiles by span, then origin.
    pub fn tiles(&self) -> &[Tile] {
        &self.tiles
    }

    /// The least and greatest value anywhere.
    pub fn range(&self) -> (f32, f32) {
        self.range
    }

    pub fn active_voxel_count(&self) -> u64 {
        let leaves: u64 = self.leaves.iter().map(Leaf::active_count).sum();
        let tiles: u64 = self
            .tiles
            .iter()
            .filter(|t| t.active)
            .map(|t| 1u64 << (3 * t.log2))
            .sum();
        leaves + tiles
    }

    /// The index box (inclusive) of the active voxels, `None` when none is.
    pub fn active_bounds(&self) -> Option<([i32; 3], [i32; 3])> {
        let mut lo = [i32::MAX; 3];
        let mut hi = [i32::MIN; 3];
        let mut grow = |p: [i32; 3], span: i32| {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k].saturating_add(span - 1));
            }
        };
        for l in &self.leaves {
            for n in (0..LEAF_VOXELS).filter(|&n| l.is_active(n)) {
                grow(l.voxel(n), 1);
            }
        }
        for t in self.tiles.iter().filter(|t| t.active) {
            grow(t.origin, 1 << t.log2);
        }
        (lo[0] <= hi[0]).then_some((lo, hi))
    }

    /// Bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.leaves.len() * (std::mem::size_of::<Leaf>() + 4 * LEAF_VOXELS + 32)
            + self.tiles.len() * (std::mem::size_of::<Tile>() + 24)
    }

    /// The leaf holding voxel `i`.
    fn leaf(&self, i: [i32; 3]) -> Option<&Leaf> {
        let key = i.map(|v| v & !7);
        self.leaf_at.get(&key).map(|&n| &self.leaves[n as usize])
    }

    /// The value of the tile or background covering voxel `i` (outside
    /// every leaf).
    fn tile_value(&self, i: [i32; 3]) -> f32 {
        for (level, &log2) in TILE_LOG2.iter().enumerate() {
            let key = i.map(|v| v & !((1i32 << log2) - 1));
            if let Some(&n) = self.tile_at[level].get(&key) {
                return self.tiles[n as usize].value;
            }
        }
        self.background
    }

    /// The value of voxel `i`.
    pub fn value(&self, i: [i32; 3]) -> f32 {
        match self.leaf(i) {
            Some(l) => l.values[Leaf::offset(i)],
            None => self.tile_value(i),
        }
    }

    /// The eight voxel values around a continuous index, and the
    /// fractions along each axis.
    fn corners(&self, p: [f64; 3]) -> ([f64; 8], [f64; 3]) {
        // Within a ten-thousandth of a voxel of its centre, a point reads
        // the voxel's own value: points sent in single precision (a batch
        // of voxel centres) land a few millionths off and would blend in
        // their neighbours, turning a clamped background into a band value.
        let p = p.map(|v| {
            if (v - v.round()).abs() < SNAP {
                v.round()
            } else {
                v
            }
        });
        let base = p.map(|v| v.floor().clamp(i32::MIN as f64, (i32::MAX - 1) as f64) as i32);
        let t: [f64; 3] = std::array::from_fn(|k| p[k] - base[k] as f64);
        let mut v = [0.0; 8];
        let same_leaf = base.iter().all(|b| b & 7 != 7);
        let leaf = if same_leaf { self.leaf(base) } else { None };
        for (c, slot) in v.iter_mut().enumerate() {
            let i = [
                base[0] + (c >> 2) as i32,
                base[1] + ((c >> 1) & 1) as i32,
                base[2] + (c & 1) as i32,
            ];
            *slot = match leaf {
                Some(l) => l.values[Leaf::offset(i)],
                None => self.value(i),
            } as f64;
        }
        (v, t)
    }

    /// The trilinear interpolation of the voxel values at world point `p`.
    pub fn sample(&self, p: [f64; 3]) -> f64 {
        let q = self.transform.to_index(p);
        if !q.iter().all(|v| v.is_finite()) {
            return f64::NAN;
        }
        let (v, t) = self.corners(q);
        let lerp = |a: f64, b: f64, s: f64| a + (b - a) * s;
        let x: [f64; 4] = std::array::from_fn(|k| lerp(v[k], v[k + 4], t[0]));
        let y = [lerp(x[0], x[2], t[1]), lerp(x[1], x[3], t[1])];
        lerp(y[0], y[1], t[2])
    }

    /// The trilinear value at world point `p` and its gradient in world
    /// units.
    pub fn sample_gradient(&self, p: [f64; 3]) -> (f64, [f64; 3]) {
        let q = self.transform.to_index(p);
        if !q.iter().all(|v| v.is_finite()) {
            return (f64::NAN, [f64::NAN; 3]);
        }
        let (v, t) = self.corners(q);
        let mut value = 0.0;
        let mut grad = [0.0; 3];
        for (c, &vc) in v.iter().enumerate() {
            let bits = [c >> 2, (c >> 1) & 1, c & 1];
            let w: [f64; 3] = std::array::from_fn(|k| if bits[k] == 1 { t[k] } else { 1.0 - t[k] });
            let dw: [f64; 3] = std::array::from_fn(|k| if bits[k] == 1 { 1.0 } else { -1.0 });
            value += vc * w[0] * w[1] * w[2];
            grad[0] += vc * dw[0] * w[1] * w[2];
            grad[1] += vc * w[0] * dw[1] * w[2];
            grad[2] += vc * w[0] * w[1] * dw[2];
        }
        (
            value,
            std::array::from_fn(|k| grad[k] / self.transform.scale[k]),
        )
    }

    /// The least and greatest value the trilinear samples take over the
    /// inclusive index box `lo..=hi`, from the leaves and tiles it meets;
    /// the whole volume's range when the box meets more than `budget`
    /// leaf-sized blocks.
    pub fn range_over(&self, lo: [i32; 3], hi: [i32; 3], budget: u64) -> (f32, f32) {
        let blocks: [(i32, i32); 3] = std::array::from_fn(|k| (lo[k] >> 3, hi[k] >> 3));
        let count: u64 = blocks
            .iter()
            .map(|(a, b)| (*b as i64 - *a as i64 + 1).max(0) as u64)
            .product();
        if count > budget {
            return self.range;
        }
        let mut r = (f32::INFINITY, f32::NEG_INFINITY);
        for bx in blocks[0].0..=blocks[0].1 {
            for by in blocks[1].0..=blocks[1].1 {
                for bz in blocks[2].0..=blocks[2].1 {
                    let origin = [bx << 3, by << 3, bz << 3];
                    let (a, b) = match self.leaf_at.get(&origin) {
                        Some(&n) => self.leaf_range[n as usize],
                        None => {
                            let v = self.tile_value(origin);
                            (v, v)
                        }
                    };
                    r = (r.0.min(a), r.1.max(b));
                }
            }
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A volume whose voxel values are `f(index)` over one leaf at the
    /// origin, with a tile of 7 beside it.
    fn linear() -> SparseVolume {
        let f = |i: [i32; 3]| (i[0] + 2 * i[1] - 3 * i[2]) as f32;
        let mut values = Box::new([0.0f32; LEAF_VOXELS]);
        for x in 0..8 {
            for y in 0..8 {
                for z in 0..8 {
                    values[Leaf::offset([x, y, z])] = f([x, y, z]);
                }
            }
        }
        let leaf = Leaf {
            origin: [0; 3],
            active: [u64::MAX; 8],
            values,
        };
        let tile = Tile {
            origin: [8, 0, 0],
            log2: 3,
            value: 7.0,
            active: false,
        };
        SparseVolume::new(
            "v",
            VolumeClass::Unknown,
            VoxelTransform::uniform(0.5, [1.0, 0.0, 0.0]),
            -1.0,
            vec![leaf],
            vec![tile],
        )
        .unwrap()
    }

    #[test]
    fn trilinear_reproduces_a_linear_function_and_its_gradient() {
        let v = linear();
        let p = [1.0 + 0.5 * 2.25, 0.5 * 3.5, 0.5 * 4.75];
        let expected = 2.25 + 2.0 * 3.5 - 3.0 * 4.75;
        assert!((v.sample(p) - expected).abs() < 1e-12);
        let (value, g) = v.sample_gradient(p);
        assert!((value - expected).abs() < 1e-12);
        assert_eq!(g, [2.0, 4.0, -6.0]);
    }

    #[test]
    fn voxels_outside_leaves_read_their_tile_or_the_background() {
        let v = linear();
        assert_eq!(v.value([3, 4, 5]), 3.0 + 8.0 - 15.0);
        assert_eq!(v.value([9, 7, 0]), 7.0);
        assert_eq!(v.value([-1, 0, 0]), -1.0);
        assert_eq!(v.active_voxel_count(), 512);
        assert_eq!(v.active_bounds(), Some(([0; 3], [7; 3])));
        assert_eq!(v.range_over([6, 0, 0], [9, 0, 0], 8), (-21.0, 21.0));
        assert_eq!(v.range_over([8, 0, 0], [15, 7, 7], 8), (7.0, 7.0));
        assert_eq!(v.range_over([-8, 0, 0], [-1, 7, 7], 8), (-1.0, -1.0));
        assert_eq!(v.range_over([-800, 0, 0], [800, 7, 7], 8), v.range());
    }

    #[test]
    fn misplaced_nodes_are_refused() {
        let bad = Tile {
            origin: [4, 0, 0],
            log2: 3,
            value: 0.0,
            active: false,
        };
        let t = VoxelTransform::uniform(1.0, [0.0; 3]);
        let e = SparseVolume::new("", VolumeClass::Unknown, t, 0.0, vec![], vec![bad]);
        assert_eq!(e.unwrap_err(), VolumeError::Unaligned("tile", 4, 0, 0));
        let e = SparseVolume::new(
            "",
            VolumeClass::Unknown,
            VoxelTransform::uniform(0.0, [0.0; 3]),
            0.0,
            vec![],
            vec![],
        );
        assert_eq!(e.unwrap_err(), VolumeError::Transform);
        let over = Tile {
            origin: [0, 0, 0],
            log2: 7,
            value: 0.0,
            active: false,
        };
        let e = SparseVolume::new(
            "",
            VolumeClass::Unknown,
            t,
            0.0,
            linear().leaves,
            vec![over],
        );
        assert_eq!(e.unwrap_err(), VolumeError::Overlap(7, 0, 0, 0));
    }
}
