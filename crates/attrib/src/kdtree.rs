//! A k-d tree over points for nearest-neighbour queries (transfer, blur by
//! proximity, sort by proximity): median splits on the widest axis of each
//! node's box, eight points a leaf, subtrees built in parallel; queries
//! descend the nearer side first and prune boxes farther than the current
//! k-th best. Ties in distance go to the lower point number, so a query's
//! answer does not depend on the build's thread count.
//!
//! Written here rather than taken from a crate: the ordering of equal
//! distances must be fixed for byte-identical cooks, and the tree is
//! small.

use glam::Vec3;

const LEAF: usize = 8;
/// Subtrees smaller than this are built on one thread.
const PARALLEL_BUILD: usize = 1 << 14;

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: Vec3,
    hi: Vec3,
    /// Range of `order` this node holds.
    start: u32,
    end: u32,
    /// Children (both or neither), as node indices.
    left: u32,
    right: u32,
}

/// The tree; it borrows nothing, so it can outlive the points' slice.
#[derive(Clone, Debug)]
pub struct KdTree {
    /// The points in tree order: a leaf's points are contiguous, so a
    /// query reads memory it just touched (`order` maps back).
    sorted: Vec<Vec3>,
    order: Vec<u32>,
    nodes: Vec<Node>,
}

/// A found point: its number and squared distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Neighbour {
    pub index: u32,
    pub dist2: f32,
}

impl Neighbour {
    fn before(&self, other: &Neighbour) -> bool {
        (self.dist2, self.index) < (other.dist2, other.index)
    }
}

impl KdTree {
    /// The tree over `points` (non-finite points are never found).
    pub fn new(points: &[Vec3]) -> KdTree {
        Self::new_cancellable(points, &|| false).expect("never cancelled")
    }

    /// [`KdTree::new`], polling `cancel` once per subtree of 16,384 points
    /// or more: `None` once it answers true.
    pub fn new_cancellable(points: &[Vec3], cancel: &(dyn Fn() -> bool + Sync)) -> Option<KdTree> {
        let mut order: Vec<u32> = (0..points.len() as u32)
            .filter(|&i| points[i as usize].is_finite())
            .collect();
        let nodes = if order.is_empty() {
            Vec::new()
        } else {
            build(points, &mut order, 0, cancel)?
        };
        let sorted = order.iter().map(|&i| points[i as usize]).collect();
        Some(KdTree {
            sorted,
            order,
            nodes,
        })
    }

    pub fn len(&self) -> usize {
        self.order.len()
    }

    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// The nearest point within `max_dist` of `q`.
    pub fn nearest(&self, q: Vec3, max_dist: f32) -> Option<Neighbour> {
        let mut out = Vec::with_capacity(1);
        self.k_nearest(q, 1, max_dist, &mut out);
        out.first().copied()
    }

    /// The `k` nearest points within `max_dist` of `q`, nearest first, in
    /// `out` (cleared first).
    pub fn k_nearest(&self, q: Vec3, k: usize, max_dist: f32, out: &mut Vec<Neighbour>) {
        out.clear();
        if k == 0 || self.nodes.is_empty() || !q.is_finite() {
            return;
        }
        let limit = if max_dist.is_finite() {
            max_dist * max_dist
        } else {
            f32::INFINITY
        };
        self.search(0, q, k, limit, out);
    }

    /// Every point within `radius` of `q`, nearest first, in `out`.
    pub fn within(&self, q: Vec3, radius: f32, out: &mut Vec<Neighbour>) {
        self.k_nearest(q, usize::MAX, radius, out);
    }

    fn search(&self, node: usize, q: Vec3, k: usize, limit: f32, out: &mut Vec<Neighbour>) {
        let n = &self.nodes[node];
        let bound = |out: &Vec<Neighbour>| {
            if out.len() == k {
                out[k - 1].dist2
            } else {
                limit
            }
        };
        if box_dist2(n, q) > bound(out) {
            return;
        }
        if n.left == u32::MAX {
            let range = n.start as usize..n.end as usize;
            for (&i, p) in self.order[range.clone()].iter().zip(&self.sorted[range]) {
                let d = p.distance_squared(q);
                if d > limit {
                    continue;
                }
                let cand = Neighbour { index: i, dist2: d };
                if out.len() == k && !cand.before(&out[k - 1]) {
                    continue;
                }
                let at = out.partition_point(|x| x.before(&cand));
                if out.len() == k {
                    out.pop();
                }
                out.insert(at, cand);
            }
            return;
        }
        let (a, b) = (n.left as usize, n.right as usize);
        let (first, second) = if box_dist2(&self.nodes[a], q) <= box_dist2(&self.nodes[b], q) {
            (a, b)
        } else {
            (b, a)
        };
        self.search(first, q, k, limit, out);
        self.search(second, q, k, limit, out);
    }
}

fn box_dist2(n: &Node, q: Vec3) -> f32 {
    let d = (n.lo - q).max(q - n.hi).max(Vec3::ZERO);
    d.length_squared()
}

/// The nodes of the subtree over `order` (its first node is its root),
/// point ranges offset by `base`.
fn build(
    points: &[Vec3],
    order: &mut [u32],
    base: u32,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Option<Vec<Node>> {
    if order.len() >= PARALLEL_BUILD && cancel() {
        return None;
    }
    let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for &i in order.iter() {
        lo = lo.min(points[i as usize]);
        hi = hi.max(points[i as usize]);
    }
    let mut root = Node {
        lo,
        hi,
        start: base,
        end: base + order.len() as u32,
        left: u32::MAX,
        right: u32::MAX,
    };
    if order.len() <= LEAF {
        return Some(vec![root]);
    }
    let ext = hi - lo;
    let axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    let mid = order.len() / 2;
    order.select_nth_unstable_by(mid, |&a, &b| {
        let (pa, pb) = (points[a as usize][axis], points[b as usize][axis]);
        pa.total_cmp(&pb).then(a.cmp(&b))
    });
    let (left_order, right_order) = order.split_at_mut(mid);
    let (left, right) = if left_order.len() + right_order.len() >= PARALLEL_BUILD {
        rayon::join(
            || build(points, left_order, base, cancel),
            || build(points, right_order, base + mid as u32, cancel),
        )
    } else {
        (
            build(points, left_order, base, cancel),
            build(points, right_order, base + mid as u32, cancel),
        )
    };
    let (left, right) = (left?, right?);
    root.left = 1;
    root.right = 1 + left.len() as u32;
    let mut nodes = Vec::with_capacity(1 + left.len() + right.len());
    nodes.push(root);
    let shift = |mut n: Node, by: u32| {
        if n.left != u32::MAX {
            n.left += by;
            n.right += by;
        }
        n
    };
    nodes.extend(left.into_iter().map(|n| shift(n, 1)));
    let offset = root.right;
    nodes.extend(right.into_iter().map(|n| shift(n, offset)));
    Some(nodes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cloud(n: usize, seed: u32) -> Vec<Vec3> {
        let mut s = seed.wrapping_mul(2654435761).max(1);
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            (s as f32 / u32::MAX as f32) * 10.0
        };
        (0..n).map(|_| Vec3::new(next(), next(), next())).collect()
    }

    fn brute(points: &[Vec3], q: Vec3, k: usize, max_dist: f32) -> Vec<Neighbour> {
        let mut all: Vec<Neighbour> = points
            .iter()
            .enumerate()
            .map(|(i, p)| Neighbour {
                index: i as u32,
                dist2: p.distance_squared(q),
            })
            .filter(|n| n.dist2 <= max_dist * max_dist)
            .collect();
        all.sort_by(|a, b| (a.dist2, a.index).partial_cmp(&(b.dist2, b.index)).unwrap());
        all.truncate(k);
        all
    }

    #[test]
    fn queries_match_a_brute_force_search() {
        let points = cloud(5000, 7);
        let tree = KdTree::new(&points);
        let mut out = Vec::new();
        for (j, q) in cloud(300, 99).into_iter().enumerate() {
            for (k, r) in [(1, f32::INFINITY), (5, 2.0), (40, 1.0), (3, 0.05)] {
                tree.k_nearest(q, k, r, &mut out);
                assert_eq!(out, brute(&points, q, k, r), "query {j} k {k} r {r}");
            }
        }
    }

    #[test]
    fn equal_distances_go_to_the_lower_number() {
        // A lattice: many points at equal distance from its centre.
        let mut points = Vec::new();
        for x in 0..9 {
            for y in 0..9 {
                for z in 0..9 {
                    points.push(Vec3::new(x as f32, y as f32, z as f32));
                }
            }
        }
        points.reverse();
        let tree = KdTree::new(&points);
        let mut out = Vec::new();
        tree.k_nearest(Vec3::splat(4.0), 7, f32::INFINITY, &mut out);
        assert_eq!(out, brute(&points, Vec3::splat(4.0), 7, f32::INFINITY));
        tree.k_nearest(Vec3::new(4.5, 4.0, 4.0), 2, f32::INFINITY, &mut out);
        assert!(out[0].index < out[1].index && out[0].dist2 == out[1].dist2);
    }

    #[test]
    fn empty_and_non_finite_inputs_find_nothing() {
        let tree = KdTree::new(&[]);
        assert!(tree.nearest(Vec3::ZERO, 1.0).is_none());
        let tree = KdTree::new(&[Vec3::NAN, Vec3::ONE]);
        assert_eq!(tree.nearest(Vec3::ZERO, f32::INFINITY).unwrap().index, 1);
        assert!(tree.nearest(Vec3::NAN, f32::INFINITY).is_none());
    }
}
