//! A static k-d tree over points for `nearpoint` and `nearpoints`: built
//! once per input (median splits), queried for the nearest points within a
//! radius, sorted by distance then point number so ties are deterministic.

use std::collections::BinaryHeap;

pub struct KdTree {
    /// Point numbers in tree order: each node is the median of its range.
    order: Vec<u32>,
    points: Vec<[f32; 3]>,
}

/// A point and its squared distance, ordered by distance then number.
#[derive(PartialEq)]
struct Found(f32, u32);

impl Eq for Found {}

impl PartialOrd for Found {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}

impl Ord for Found {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&o.0).then(self.1.cmp(&o.1))
    }
}

impl KdTree {
    pub fn new(points: Vec<[f32; 3]>) -> KdTree {
        let mut order: Vec<u32> = (0..points.len() as u32).collect();
        build(&mut order, &points, 0);
        KdTree { order, points }
    }

    /// Up to `count` point numbers within `radius` of `q`, nearest first.
    pub fn nearest(&self, q: [f32; 3], radius: f32, count: usize) -> Vec<u32> {
        if count == 0 {
            return Vec::new();
        }
        let mut heap = BinaryHeap::new();
        let r2 = if radius.is_finite() {
            radius * radius
        } else {
            f32::INFINITY
        };
        self.search(0, self.order.len(), 0, q, r2, count, &mut heap);
        let mut v = heap.into_vec();
        v.sort();
        v.into_iter().map(|f| f.1).collect()
    }

    #[allow(clippy::too_many_arguments)]
    fn search(
        &self,
        lo: usize,
        hi: usize,
        axis: usize,
        q: [f32; 3],
        r2: f32,
        k: usize,
        heap: &mut BinaryHeap<Found>,
    ) {
        if lo >= hi {
            return;
        }
        let mid = (lo + hi) / 2;
        let id = self.order[mid];
        let p = self.points[id as usize];
        let d2 = (0..3).map(|a| (p[a] - q[a]) * (p[a] - q[a])).sum::<f32>();
        let bound = |heap: &BinaryHeap<Found>| {
            if heap.len() == k {
                heap.peek().map_or(r2, |f| f.0)
            } else {
                r2
            }
        };
        if d2 <= r2 {
            let f = Found(d2, id);
            if heap.len() < k {
                heap.push(f);
            } else if heap.peek().is_some_and(|top| f < *top) {
                heap.pop();
                heap.push(f);
            }
        }
        let delta = q[axis] - p[axis];
        let (near, far) = if delta < 0.0 {
            ((lo, mid), (mid + 1, hi))
        } else {
            ((mid + 1, hi), (lo, mid))
        };
        let next = (axis + 1) % 3;
        self.search(near.0, near.1, next, q, r2, k, heap);
        if delta * delta <= bound(heap) {
            self.search(far.0, far.1, next, q, r2, k, heap);
        }
    }
}

fn build(order: &mut [u32], points: &[[f32; 3]], axis: usize) {
    if order.len() <= 1 {
        return;
    }
    let mid = order.len() / 2;
    order.select_nth_unstable_by(mid, |a, b| {
        let (x, y) = (points[*a as usize][axis], points[*b as usize][axis]);
        x.partial_cmp(&y)
            .unwrap_or(std::cmp::Ordering::Equal)
            .then(a.cmp(b))
    });
    let (left, right) = order.split_at_mut(mid);
    let next = (axis + 1) % 3;
    if left.len() + right.len() > 4096 {
        rayon::join(
            || build(left, points, next),
            || build(&mut right[1..], points, next),
        );
    } else {
        build(left, points, next);
        build(&mut right[1..], points, next);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_brute_force() {
        let pts: Vec<[f32; 3]> = (0..2000)
            .map(|i| {
                let t = i as f32;
                [
                    (t * 0.618).fract(),
                    (t * 0.414).fract(),
                    (t * 0.732).fract(),
                ]
            })
            .collect();
        let tree = KdTree::new(pts.clone());
        for q in [[0.5, 0.5, 0.5], [0.1, 0.9, 0.3], [2.0, 2.0, 2.0]] {
            let got = tree.nearest(q, 0.2, 16);
            let mut all: Vec<(f32, u32)> = pts
                .iter()
                .enumerate()
                .map(|(i, p)| ((0..3).map(|a| (p[a] - q[a]).powi(2)).sum::<f32>(), i as u32))
                .filter(|x| x.0 <= 0.04)
                .collect();
            all.sort_by(|a, b| a.partial_cmp(b).unwrap());
            let want: Vec<u32> = all.into_iter().take(16).map(|x| x.1).collect();
            assert_eq!(got, want);
        }
    }
}
