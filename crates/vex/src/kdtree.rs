//! A static k-d tree over points for `nearpoint(s)`, `pcfind` and
//! `pcopen`: built once per input (median splits, axes in turn), its
//! points stored in tree order so a search walks memory it just touched,
//! ranges of up to `LEAF` points scanned whole. Queries give the nearest
//! points within a radius, sorted by distance then point number, so ties
//! are deterministic.

/// Points a range holds before it is scanned instead of split.
const LEAF: usize = 12;

pub struct KdTree {
    /// Point numbers in tree order: each split's median sits mid-range.
    order: Vec<u32>,
    /// The points in tree order.
    points: Vec<[f32; 3]>,
}

/// The best `k` found so far, ordered by (squared distance, point number).
struct Best {
    k: usize,
    found: Vec<(f32, u32)>,
    r2: f32,
}

impl Best {
    /// The distance a candidate must beat.
    fn bound(&self) -> f32 {
        if self.found.len() == self.k {
            self.found.last().map_or(self.r2, |f| f.0)
        } else {
            self.r2
        }
    }

    fn offer(&mut self, d2: f32, id: u32) {
        if d2 > self.r2 {
            return;
        }
        let item = (d2, id);
        let full = self.found.len() == self.k;
        if full && !less(item, *self.found.last().expect("full")) {
            return;
        }
        // Small k (the common 1 to 64) keeps a sorted list: an insertion
        // is a short shift, no heap.
        let at = self.found.partition_point(|f| less(*f, item));
        if full {
            self.found.pop();
        }
        self.found.insert(at, item);
    }
}

fn less(a: (f32, u32), b: (f32, u32)) -> bool {
    a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).is_lt()
}

impl KdTree {
    pub fn new(points: Vec<[f32; 3]>) -> KdTree {
        let mut order: Vec<u32> = (0..points.len() as u32).collect();
        build(&mut order, &points, 0);
        let points = order.iter().map(|&i| points[i as usize]).collect();
        KdTree { order, points }
    }

    /// Up to `count` point numbers within `radius` of `q`, nearest first.
    pub fn nearest(&self, q: [f32; 3], radius: f32, count: usize) -> Vec<u32> {
        if count == 0 || self.points.is_empty() {
            return Vec::new();
        }
        let r2 = if radius.is_finite() {
            radius * radius
        } else {
            f32::INFINITY
        };
        let mut best = Best {
            k: count,
            found: Vec::with_capacity(count.min(64)),
            r2,
        };
        if count > 64 {
            // Many results: gather every point in the radius, then sort.
            self.gather(0, self.points.len(), 0, q, r2, &mut best.found);
            best.found
                .sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            best.found.truncate(count);
        } else {
            self.search(0, self.points.len(), 0, q, &mut best);
        }
        best.found.into_iter().map(|f| f.1).collect()
    }

    fn dist2(&self, i: usize, q: [f32; 3]) -> f32 {
        let p = self.points[i];
        let (x, y, z) = (p[0] - q[0], p[1] - q[1], p[2] - q[2]);
        x * x + y * y + z * z
    }

    fn search(&self, lo: usize, hi: usize, axis: usize, q: [f32; 3], best: &mut Best) {
        if hi - lo <= LEAF {
            for i in lo..hi {
                best.offer(self.dist2(i, q), self.order[i]);
            }
            return;
        }
        let mid = (lo + hi) / 2;
        best.offer(self.dist2(mid, q), self.order[mid]);
        let delta = q[axis] - self.points[mid][axis];
        let (near, far) = if delta < 0.0 {
            ((lo, mid), (mid + 1, hi))
        } else {
            ((mid + 1, hi), (lo, mid))
        };
        let next = (axis + 1) % 3;
        self.search(near.0, near.1, next, q, best);
        if delta * delta <= best.bound() {
            self.search(far.0, far.1, next, q, best);
        }
    }

    /// Every point within the radius, unordered.
    fn gather(
        &self,
        lo: usize,
        hi: usize,
        axis: usize,
        q: [f32; 3],
        r2: f32,
        out: &mut Vec<(f32, u32)>,
    ) {
        if hi - lo <= LEAF {
            for i in lo..hi {
                let d2 = self.dist2(i, q);
                if d2 <= r2 {
                    out.push((d2, self.order[i]));
                }
            }
            return;
        }
        let mid = (lo + hi) / 2;
        let d2 = self.dist2(mid, q);
        if d2 <= r2 {
            out.push((d2, self.order[mid]));
        }
        let delta = q[axis] - self.points[mid][axis];
        let next = (axis + 1) % 3;
        if delta < 0.0 || delta * delta <= r2 {
            self.gather(lo, mid, next, q, r2, out);
        }
        if delta >= 0.0 || delta * delta <= r2 {
            self.gather(mid + 1, hi, next, q, r2, out);
        }
    }
}

/// Orders `order` so every range's median (by the range's axis) sits at
/// its middle, smaller before, larger after; ranges of `LEAF` points or
/// fewer stay as they are (they are scanned).
fn build(order: &mut [u32], points: &[[f32; 3]], axis: usize) {
    if order.len() <= LEAF {
        return;
    }
    let mid = order.len() / 2;
    order.select_nth_unstable_by(mid, |a, b| {
        let (x, y) = (points[*a as usize][axis], points[*b as usize][axis]);
        x.total_cmp(&y).then(a.cmp(b))
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

    #[test]
    fn ties_go_to_the_lower_point_number() {
        let pts = vec![[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let tree = KdTree::new(pts);
        assert_eq!(tree.nearest([0.0; 3], 5.0, 2), vec![0, 1]);
        assert_eq!(tree.nearest([0.0; 3], 5.0, 1), vec![0]);
    }
}
