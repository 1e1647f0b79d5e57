//! What the VDB reader and writer share: the three node levels, bit masks
//! in VDB's order, and mask compression (how a node's inactive values are
//! told apart without storing them), chosen and undone by one rule.

/// A node level of the 5-4-3 tree.
#[derive(Clone, Copy, Debug)]
pub(super) struct Level {
    /// log2 of the node's slots along an axis.
    pub log2: u32,
    /// log2 of the voxels one slot spans along an axis.
    pub child_log2: u32,
}

pub(super) const UPPER: Level = Level {
    log2: 5,
    child_log2: 7,
};
pub(super) const LOWER: Level = Level {
    log2: 4,
    child_log2: 3,
};
pub(super) const LEAF: Level = Level {
    log2: 3,
    child_log2: 0,
};

impl Level {
    /// Slots in the node.
    pub fn slots(self) -> usize {
        1 << (3 * self.log2)
    }

    /// log2 of the voxels the node spans along an axis.
    pub fn span_log2(self) -> u32 {
        self.log2 + self.child_log2
    }

    /// The origin of the node holding voxel `i`.
    pub fn origin_of(self, i: [i32; 3]) -> [i32; 3] {
        i.map(|v| v & !((1i32 << self.span_log2()) - 1))
    }

    /// The slot of voxel `i` (z fastest).
    pub fn slot(self, i: [i32; 3]) -> usize {
        let local = i.map(|v| ((v & ((1 << self.span_log2()) - 1)) >> self.child_log2) as usize);
        (local[0] << (2 * self.log2)) | (local[1] << self.log2) | local[2]
    }

    /// The lowest voxel of slot `n` of the node at `origin`.
    pub fn slot_origin(self, origin: [i32; 3], n: usize) -> [i32; 3] {
        let m = (1usize << self.log2) - 1;
        let local = [n >> (2 * self.log2), (n >> self.log2) & m, n & m];
        std::array::from_fn(|k| origin[k] + ((local[k] as i32) << self.child_log2))
    }
}

/// A bit per slot, stored as VDB stores it: 64-bit words, bit `n` in word
/// `n / 64`, little-endian.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Mask(pub Vec<u64>);

impl Mask {
    pub fn new(slots: usize) -> Mask {
        Mask(vec![0; slots.div_ceil(64)])
    }

    pub fn get(&self, n: usize) -> bool {
        self.0[n >> 6] >> (n & 63) & 1 == 1
    }

    pub fn set(&mut self, n: usize) {
        self.0[n >> 6] |= 1 << (n & 63);
    }

    pub fn count(&self) -> usize {
        self.0.iter().map(|w| w.count_ones() as usize).sum()
    }

    pub fn write(&self, out: &mut Vec<u8>) {
        self.0
            .iter()
            .for_each(|w| out.extend_from_slice(&w.to_le_bytes()));
    }
}

/// How a node's inactive values are stored: OpenVDB's metadata byte (0:
/// all +background, 1: all -background, 2: all `val0`, 3: selection on
/// +background else -background, 4: on +background else `val0`, 5: on
/// `val1` else `val0`, 6: every value stored).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Inactive {
    pub metadata: u8,
    pub val0: f32,
    pub val1: f32,
    pub selection: Option<Mask>,
}

pub(super) const ALL_VALUES: u8 = 6;

impl Inactive {
    /// The defaults a metadata byte implies before any stored value.
    pub fn defaults(metadata: u8, background: f32) -> Inactive {
        Inactive {
            metadata,
            val0: if metadata == 0 {
                background
            } else {
                -background
            },
            val1: background,
            selection: None,
        }
    }

    /// Whether the byte is followed by `val0`, `val1`, a selection mask.
    pub fn stores(metadata: u8) -> (bool, bool, bool) {
        (
            matches!(metadata, 2 | 4 | 5),
            metadata == 5,
            matches!(metadata, 3..=5),
        )
    }

    /// OpenVDB's choice for a node's values: the distinct values of its
    /// inactive slots (neither active nor holding a child), up to three.
    pub fn choose(values: &[f32], active: &Mask, child: Option<&Mask>, bg: f32) -> Inactive {
        let mut distinct: Vec<f32> = Vec::with_capacity(3);
        let inactive = |n: usize| !active.get(n) && !child.is_some_and(|c| c.get(n));
        for (n, &v) in values.iter().enumerate() {
            if inactive(n) && !distinct.contains(&v) {
                distinct.push(v);
                if distinct.len() == 3 {
                    break;
                }
            }
        }
        let selection = |on: f32| {
            let mut m = Mask::new(values.len());
            for (n, &v) in values.iter().enumerate() {
                if inactive(n) && v == on {
                    m.set(n);
                }
            }
            Some(m)
        };
        let plain = |metadata, val0, val1| Inactive {
            metadata,
            val0,
            val1,
            selection: None,
        };
        match distinct[..] {
            [] => plain(0, bg, bg),
            [v] if v == bg => plain(0, bg, bg),
            [v] if v == -bg => plain(1, -bg, bg),
            [v] => plain(2, v, bg),
            [a, b] if (a == bg && b == -bg) || (a == -bg && b == bg) => Inactive {
                selection: selection(bg),
                ..plain(3, -bg, bg)
            },
            [a, b] if a == bg || b == bg => Inactive {
                selection: selection(bg),
                ..plain(4, if a == bg { b } else { a }, bg)
            },
            [a, b] => Inactive {
                selection: selection(b),
                ..plain(5, a, b)
            },
            _ => plain(ALL_VALUES, bg, bg),
        }
    }

    /// The value of inactive slot `n`.
    pub fn value(&self, n: usize) -> f32 {
        match &self.selection {
            Some(m) if m.get(n) => self.val1,
            _ => self.val0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slots_and_origins_invert() {
        for level in [UPPER, LOWER, LEAF] {
            let origin = level.origin_of([-5000, 300, 17]);
            for n in [0, 1, level.slots() / 2 + 3, level.slots() - 1] {
                let at = level.slot_origin(origin, n);
                assert_eq!(level.slot(at), n);
                assert_eq!(level.origin_of(at), origin);
            }
        }
        // The spec's example: leaf voxel (1, 2, 3) is slot 83.
        assert_eq!(LEAF.slot([1, 2, 3]), 83);
    }

    #[test]
    fn every_choice_restores_its_values() {
        let bg = 3.0;
        let active = {
            let mut m = Mask::new(8);
            m.set(0);
            m
        };
        for inactive in [
            [bg; 7],
            [-bg; 7],
            [1.0; 7],
            [bg, -bg, bg, bg, -bg, -bg, bg],
            [bg, 2.0, bg, 2.0, 2.0, bg, bg],
            [5.0, 2.0, 5.0, 2.0, 2.0, 5.0, 5.0],
            [5.0, 2.0, 1.0, 2.0, 2.0, 5.0, 5.0],
        ] {
            let values: Vec<f32> = std::iter::once(9.0).chain(inactive).collect();
            let c = Inactive::choose(&values, &active, None, bg);
            for (n, &v) in values.iter().enumerate().skip(1) {
                if c.metadata != ALL_VALUES {
                    assert_eq!(c.value(n), v, "{inactive:?} as {}", c.metadata);
                }
            }
        }
        let count = |vals: [f32; 7]| {
            let values: Vec<f32> = std::iter::once(9.0).chain(vals).collect();
            Inactive::choose(&values, &active, None, bg).metadata
        };
        assert_eq!(count([bg; 7]), 0);
        assert_eq!(count([-bg; 7]), 1);
        assert_eq!(count([5.0, 2.0, 1.0, 2.0, 2.0, 5.0, 5.0]), ALL_VALUES);
    }
}
