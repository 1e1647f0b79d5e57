//! Named membership sets over points or primitives, stored as bitsets.

/// A fixed-length set of element flags.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Default)]
pub struct Group {
    words: Vec<u64>,
    len: usize,
}

impl Group {
    pub fn new(len: usize) -> Group {
        Group {
            words: vec![0; len.div_ceil(64)],
            len,
        }
    }

    pub fn from_flags(flags: impl IntoIterator<Item = bool>) -> Group {
        let mut g = Group::new(0);
        for f in flags {
            g.push(f);
        }
        g
    }

    pub fn from_members(len: usize, members: impl IntoIterator<Item = usize>) -> Group {
        let mut g = Group::new(len);
        for m in members {
            if m < len {
                g.set(m, true);
            }
        }
        g
    }

    /// From its bitset words (`len.div_ceil(64)` of them; bits past `len` cleared).
    pub(crate) fn from_words(mut words: Vec<u64>, len: usize) -> Group {
        words.resize(len.div_ceil(64), 0);
        if !len.is_multiple_of(64) {
            if let Some(last) = words.last_mut() {
                *last &= (1u64 << (len % 64)) - 1;
            }
        }
        Group { words, len }
    }

    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    pub fn contains(&self, i: usize) -> bool {
        i < self.len && self.words[i / 64] >> (i % 64) & 1 == 1
    }

    pub fn set(&mut self, i: usize, on: bool) {
        assert!(i < self.len, "group index {i} out of range {}", self.len);
        let bit = 1u64 << (i % 64);
        if on {
            self.words[i / 64] |= bit;
        } else {
            self.words[i / 64] &= !bit;
        }
    }

    pub fn push(&mut self, on: bool) {
        let i = self.len;
        self.resize(i + 1);
        self.set(i, on);
    }

    /// Grows (new elements are not members) or shrinks.
    pub fn resize(&mut self, len: usize) {
        self.words.resize(len.div_ceil(64), 0);
        self.len = len;
        // Keep the bits past `len` zero so equal sets hash equally.
        if !len.is_multiple_of(64) {
            if let Some(last) = self.words.last_mut() {
                *last &= (1u64 << (len % 64)) - 1;
            }
        }
    }

    pub fn count(&self) -> usize {
        self.words.iter().map(|w| w.count_ones() as usize).sum()
    }

    /// Member indices in increasing order.
    pub fn members(&self) -> impl Iterator<Item = usize> + '_ {
        self.words.iter().enumerate().flat_map(|(wi, &w)| {
            let mut bits = w;
            std::iter::from_fn(move || {
                if bits == 0 {
                    return None;
                }
                let b = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                Some(wi * 64 + b)
            })
        })
    }

    /// The group restricted to `indices` (in that order).
    pub fn gather(&self, indices: &[u32]) -> Group {
        let mut g = Group::new(indices.len());
        for (new, &old) in indices.iter().enumerate() {
            if self.contains(old as usize) {
                g.set(new, true);
            }
        }
        g
    }

    /// Appends `other`'s flags after ours.
    pub fn append(&mut self, other: &Group) {
        let base = self.len;
        self.resize(base + other.len);
        for m in other.members() {
            self.set(base + m, true);
        }
    }

    pub fn words(&self) -> &[u64] {
        &self.words
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_members_resize() {
        let mut g = Group::new(130);
        g.set(0, true);
        g.set(64, true);
        g.set(129, true);
        assert_eq!(g.members().collect::<Vec<_>>(), vec![0, 64, 129]);
        assert_eq!(g.count(), 3);
        g.resize(100);
        assert_eq!(g.members().collect::<Vec<_>>(), vec![0, 64]);
        g.resize(130);
        assert!(!g.contains(129), "shrinking must clear dropped bits");
        let mut h = Group::from_flags([true, false]);
        h.append(&g);
        assert_eq!(h.members().collect::<Vec<_>>(), vec![0, 2, 66]);
    }
}
