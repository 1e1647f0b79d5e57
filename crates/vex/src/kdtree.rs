//! A static k-d tree over points for `nearpoint(s)`, `pcfind` and
//! `pcopen`: built once per input (median splits, axes in turn), its
//! points stored in tree order, in blocks of eight by axis, so a search
//! walks memory it just touched and measures a block at once; ranges of up
//! to `LEAF` points are scanned whole. Queries give the nearest points
//! within a radius, sorted by distance then point number, so ties are
//! deterministic.

use rayon::prelude::*;

/// Points a range holds before it is scanned instead of split.
const LEAF: usize = 16;

/// Points a block holds: a scan measures a block at once, and every
/// range starts a block (splits fall on multiples of it).
const LANES: usize = 8;

// A leaf must be able to hold a block, so both halves of a split have points.
const _: () = assert!(LEAF >= LANES);

/// The most results kept in a fixed sorted array while searching; larger
/// counts gather every point in the radius and sort once.
const SMALL: usize = 64;

/// `LANES` consecutive points in tree order, by axis, and their numbers:
/// two cache lines hold everything a scan of them reads. Lanes past the
/// last point are NaN, which no distance bound admits.
#[derive(Clone, Copy)]
#[repr(align(64))]
struct Block {
    xyz: [[f32; LANES]; 3],
    ids: [u32; LANES],
}

pub struct KdTree {
    /// Each split's coordinate, in heap order (node `i`'s halves are
    /// `2i + 1` and `2i + 2`): the top of the tree shares a few cache
    /// lines.
    splits: Vec<f32>,
    /// The points in tree order.
    blocks: Vec<Block>,
    /// How many points (the last block may be partial).
    len: usize,
}

/// A node of the tree: where its split is kept, its points `lo..hi` and
/// the axis it splits.
#[derive(Clone, Copy)]
struct Node {
    at: usize,
    lo: usize,
    hi: usize,
    axis: usize,
}

impl Node {
    fn root(len: usize) -> Node {
        Node {
            at: 0,
            lo: 0,
            hi: len,
            axis: 0,
        }
    }

    fn is_leaf(&self) -> bool {
        self.hi - self.lo <= LEAF
    }

    /// The halves: the points before the split (at or below its
    /// coordinate), then from it on (at or above).
    fn halves(&self) -> (Node, Node) {
        let mid = split_at(self.lo, self.hi);
        let axis = (self.axis + 1) % 3;
        let half = |at, lo, hi| Node { at, lo, hi, axis };
        (
            half(2 * self.at + 1, self.lo, mid),
            half(2 * self.at + 2, mid, self.hi),
        )
    }
}

/// Where range `lo..hi` splits: near its middle, on a block boundary so
/// every range starts a block and only the last block is partial.
fn split_at(lo: usize, hi: usize) -> usize {
    lo + ((hi - lo) / 2 / LANES).max(1) * LANES
}

/// The nearest `k` (at most `SMALL`) found so far, in a fixed array so a
/// query allocates nothing until it answers.
struct Nearest {
    k: usize,
    len: usize,
    /// (squared distance, point number) packed so one integer comparison
    /// orders by distance, then point number: distances are never
    /// negative, so their bits sort as they do.
    keys: [u64; SMALL],
    /// What a candidate's squared distance must not exceed: the radius's
    /// until `k` are found, then the k-th's (a tie may still enter by a
    /// lower point number).
    bound: f32,
}

impl Nearest {
    fn new(k: usize, r2: f32) -> Nearest {
        Nearest {
            k,
            len: 0,
            keys: [0; SMALL],
            bound: r2,
        }
    }

    /// Takes a candidate whose squared distance is within `bound`.
    fn offer(&mut self, d2: f32, id: u32) {
        let key = (u64::from(d2.to_bits()) << 32) | u64::from(id);
        let keys = &mut self.keys[..self.k];
        let mut at = if self.len == keys.len() {
            if key >= keys[keys.len() - 1] {
                return;
            }
            keys.len() - 1
        } else {
            self.len += 1;
            self.len - 1
        };
        // Small k: an insertion step (a short shift) beats a heap.
        while at > 0 && keys[at - 1] > key {
            keys[at] = keys[at - 1];
            at -= 1;
        }
        keys[at] = key;
        if self.len == keys.len() {
            self.bound = f32::from_bits((keys[keys.len() - 1] >> 32) as u32);
        }
    }

    fn ids(&self) -> Vec<u32> {
        self.keys[..self.len].iter().map(|&k| k as u32).collect()
    }
}

/// The squared length of `d`, summed in the order every distance here is:
/// rounding then keeps a box's bound at or below its points' distances,
/// so pruning by it never drops a tie.
fn norm2(d: [f32; 3]) -> f32 {
    d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
}

impl Block {
    /// (squared distance, point number) of the block's points within
    /// `bound` of `q` (a NaN distance never is). The distances are
    /// measured all at once, then the few within are picked out.
    #[inline]
    fn within(&self, q: [f32; 3], bound: f32) -> impl Iterator<Item = (f32, u32)> + '_ {
        let [x, y, z] = &self.xyz;
        let d2: [f32; LANES] =
            std::array::from_fn(|j| norm2([x[j] - q[0], y[j] - q[1], z[j] - q[2]]));
        let mask = (0..LANES).fold(0u32, |m, j| m | (u32::from(d2[j] <= bound) << j));
        // Each step clears the lowest lane left.
        let rest = |m: u32| (m != 0).then_some(m);
        std::iter::successors(rest(mask), move |m| rest(m & (m - 1))).map(move |m| {
            let j = m.trailing_zeros() as usize;
            (d2[j], self.ids[j])
        })
    }
}

impl KdTree {
    pub fn new(points: Vec<[f32; 3]>) -> KdTree {
        // Points travel with their numbers while the tree is built, so
        // the median selections read contiguous memory, not through an
        // index.
        let mut items: Vec<Item> = points.into_iter().zip(0..).collect();
        let splits = build(&mut items);
        KdTree {
            splits,
            blocks: items.par_chunks(LANES).map(block).collect(),
            len: items.len(),
        }
    }

    /// Up to `count` point numbers within `radius` of `q`, nearest first.
    /// Points at a NaN distance are never within it.
    pub fn nearest(&self, q: [f32; 3], radius: f32, count: usize) -> Vec<u32> {
        if count == 0 || self.len == 0 {
            return Vec::new();
        }
        let r2 = if radius.is_finite() {
            radius * radius
        } else {
            f32::INFINITY
        };
        if count > SMALL {
            // Many results: gather every point in the radius, then sort.
            let mut found = Vec::new();
            self.gather(Node::root(self.len), q, r2, &mut found);
            found.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            return found.into_iter().take(count).map(|f| f.1).collect();
        }
        let mut best = Nearest::new(count, r2);
        self.search(Node::root(self.len), q, [0.0; 3], &mut best);
        best.ids()
    }

    /// A leaf's blocks (its `lo` starts a block; so does its `hi` unless it
    /// is the end).
    fn leaf(&self, node: Node) -> &[Block] {
        &self.blocks[node.lo / LANES..node.hi.div_ceil(LANES)]
    }

    /// Searches `node`, nearer half first; `off` is how far `q` lies
    /// outside the node's box on each axis.
    fn search(&self, node: Node, q: [f32; 3], off: [f32; 3], best: &mut Nearest) {
        if node.is_leaf() {
            for b in self.leaf(node) {
                for (d2, id) in b.within(q, best.bound) {
                    best.offer(d2, id);
                }
            }
            return;
        }
        let axis = node.axis;
        let delta = q[axis] - self.splits[node.at];
        let (below, above) = node.halves();
        let (near, far) = if delta < 0.0 {
            (below, above)
        } else {
            (above, below)
        };
        self.search(near, q, off, best);
        // The far half's box is at least |delta| away on this axis (built
        // lane by lane: a store into `off` then a whole read would stall).
        let far_off = std::array::from_fn(|a| if a == axis { delta.abs() } else { off[a] });
        if norm2(far_off) <= best.bound {
            self.search(far, q, far_off, best);
        }
    }

    /// Every point of `node` within the radius, unordered.
    fn gather(&self, node: Node, q: [f32; 3], r2: f32, out: &mut Vec<(f32, u32)>) {
        if node.is_leaf() {
            for b in self.leaf(node) {
                out.extend(b.within(q, r2));
            }
            return;
        }
        let delta = q[node.axis] - self.splits[node.at];
        let (below, above) = node.halves();
        if delta < 0.0 || delta * delta <= r2 {
            self.gather(below, q, r2, out);
        }
        if delta >= 0.0 || delta * delta <= r2 {
            self.gather(above, q, r2, out);
        }
    }
}

/// A point and its number, as the tree is built.
type Item = ([f32; 3], u32);

/// Up to `LANES` items as a block, NaN past the last.
fn block(items: &[Item]) -> Block {
    let mut b = Block {
        xyz: [[f32::NAN; LANES]; 3],
        ids: [0; LANES],
    };
    for (j, (p, id)) in items.iter().enumerate() {
        for (axis, c) in b.xyz.iter_mut().zip(p) {
            axis[j] = *c;
        }
        b.ids[j] = *id;
    }
    b
}

/// Orders `items` so every range's median (by the range's axis, ties by
/// point number) starts its upper half, smaller before, larger after, down
/// to ranges of `LEAF` points or fewer; gives each split's coordinate in
/// heap order. A depth's ranges split in parallel, each depending only on
/// its own items, so the threads cannot change the result; a split is
/// read before deeper splits reorder its halves.
fn build(items: &mut [Item]) -> Vec<f32> {
    let mut splits = Vec::new();
    // One depth's ranges still to split, left to right, with their nodes.
    let mut level: Vec<(usize, &mut [Item])> = Vec::new();
    if items.len() > LEAF {
        level.push((0, items));
    }
    let mut axis = 0;
    while !level.is_empty() {
        let cuts: Vec<f32> = level
            .par_iter_mut()
            .map(|(_, range)| {
                let mid = split_at(0, range.len());
                let (_, median, _) = range.select_nth_unstable_by(mid, |a, b| {
                    a.0[axis].total_cmp(&b.0[axis]).then(a.1.cmp(&b.1))
                });
                median.0[axis]
            })
            .collect();
        let mut deeper = Vec::with_capacity(level.len() * 2);
        for ((node, range), cut) in level.into_iter().zip(cuts) {
            if splits.len() <= node {
                splits.resize(node + 1, 0.0);
            }
            splits[node] = cut;
            let (below, above) = range.split_at_mut(split_at(0, range.len()));
            for (child, half) in [(2 * node + 1, below), (2 * node + 2, above)] {
                if half.len() > LEAF {
                    deeper.push((child, half));
                }
            }
        }
        level = deeper;
        axis = (axis + 1) % 3;
    }
    splits
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cloud(n: usize) -> Vec<[f32; 3]> {
        (0..n)
            .map(|i| {
                let t = i as f32;
                [
                    (t * 0.618).fract(),
                    (t * 0.414).fract(),
                    (t * 0.732).fract(),
                ]
            })
            .collect()
    }

    fn brute(pts: &[[f32; 3]], q: [f32; 3], r2: f32, k: usize) -> Vec<u32> {
        let mut all: Vec<(f32, u32)> = pts
            .iter()
            .enumerate()
            .map(|(i, p)| ((0..3).map(|a| (p[a] - q[a]).powi(2)).sum::<f32>(), i as u32))
            .filter(|x| x.0 <= r2)
            .collect();
        all.sort_by(|a, b| a.partial_cmp(b).unwrap());
        all.into_iter().take(k).map(|x| x.1).collect()
    }

    #[test]
    fn matches_brute_force() {
        let pts = cloud(2000);
        let tree = KdTree::new(pts.clone());
        for q in [[0.5, 0.5, 0.5], [0.1, 0.9, 0.3], [2.0, 2.0, 2.0]] {
            assert_eq!(tree.nearest(q, 0.2, 16), brute(&pts, q, 0.04, 16));
            assert_eq!(tree.nearest(q, 0.3, 500), brute(&pts, q, 0.09, 500));
            assert_eq!(
                tree.nearest(q, f32::INFINITY, 1),
                brute(&pts, q, f32::INFINITY, 1)
            );
        }
    }

    /// Squares the radius as `nearest` does.
    fn r2(radius: f32) -> f32 {
        if radius.is_finite() {
            radius * radius
        } else {
            f32::INFINITY
        }
    }

    #[test]
    fn lattice_ties_match_brute_force() {
        // A lattice puts many points at exactly the k-th distance, and
        // 11^3 points leave the last block partial.
        let pts: Vec<[f32; 3]> = (0..11 * 11 * 11)
            .map(|i| {
                [
                    (i % 11) as f32 * 0.1,
                    (i / 11 % 11) as f32 * 0.1,
                    (i / 121) as f32 * 0.1,
                ]
            })
            .collect();
        let tree = KdTree::new(pts.clone());
        for (i, p) in pts.iter().enumerate().step_by(37) {
            for q in [*p, [p[0] + 0.05, p[1], p[2] - 0.05]] {
                for radius in [0.1, 0.15, 0.25, f32::INFINITY] {
                    for k in [1, 7, 16, 64, 65, 300] {
                        let want = brute(&pts, q, r2(radius), k);
                        assert_eq!(
                            tree.nearest(q, radius, k),
                            want,
                            "point {i} {q:?} r {radius} k {k}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn every_small_size_matches_brute_force() {
        // Sizes around a block and a leaf: partial blocks, single leaves.
        for n in 0..=70 {
            let pts = cloud(n);
            let tree = KdTree::new(pts.clone());
            for q in [[0.5, 0.5, 0.5], [0.0, 1.0, 0.2]] {
                for (radius, k) in [(0.3, 5), (f32::INFINITY, 1), (f32::INFINITY, 100)] {
                    assert_eq!(
                        tree.nearest(q, radius, k),
                        brute(&pts, q, r2(radius), k),
                        "n {n}"
                    );
                }
            }
        }
    }

    #[test]
    fn points_at_nan_are_never_found() {
        let pts = vec![[f32::NAN, 0.0, 0.0], [1.0, 0.0, 0.0], [-f32::NAN, 2.0, 0.0]];
        let tree = KdTree::new(pts);
        assert_eq!(tree.nearest([0.0; 3], f32::INFINITY, 3), vec![1]);
        assert_eq!(tree.nearest([0.0; 3], f32::INFINITY, 100), vec![1]);
    }

    #[test]
    fn ties_go_to_the_lower_point_number() {
        let pts = vec![[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let tree = KdTree::new(pts);
        assert_eq!(tree.nearest([0.0; 3], 5.0, 2), vec![0, 1]);
        assert_eq!(tree.nearest([0.0; 3], 5.0, 1), vec![0]);
    }
}
