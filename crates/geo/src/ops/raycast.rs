//! Ray casts against triangles through a bounding-volume hierarchy (median
//! splits on the widest centroid axis, four triangles a leaf), built once
//! and shared by every ray of a query.

use glam::Vec3;
use rayon::prelude::*;

/// Triangles per leaf.
const LEAF: usize = 4;

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Node {
    pub(super) lo: Vec3,
    pub(super) hi: Vec3,
    /// Leaf: triangles `start..end` (in `order`). Inner: `end == start` and
    /// the children are the next node and `second`.
    pub(super) start: u32,
    pub(super) end: u32,
    pub(super) second: u32,
}

/// A hit: the distance along the ray (in units of its direction's length)
/// and the triangle's index in the list given to [`TriangleBvh::new`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    pub t: f32,
    pub triangle: u32,
    /// Barycentric weights of the triangle's second and third corners at
    /// the hit (the point is `c0 + u (c1 - c0) + v (c2 - c0)`).
    pub u: f32,
    pub v: f32,
}

/// Triangles by their corners, with their hierarchy; immutable once built.
pub struct TriangleBvh {
    /// Corners in hierarchy order (a leaf's triangles are contiguous:
    /// a query reads memory it just touched); `order` maps back.
    pub(super) corners: Vec<[Vec3; 3]>,
    /// Triangle indices in hierarchy order.
    pub(super) order: Vec<u32>,
    pub(super) nodes: Vec<Node>,
}

fn bounds_of(corners: &[[Vec3; 3]], tris: &[u32]) -> (Vec3, Vec3) {
    tris.iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &t| {
            let c = &corners[t as usize];
            (
                lo.min(c[0]).min(c[1]).min(c[2]),
                hi.max(c[0]).max(c[1]).max(c[2]),
            )
        })
}

impl TriangleBvh {
    /// The hierarchy over `triangles` (indices into `positions`).
    pub fn new(positions: &[Vec3], triangles: &[[u32; 3]]) -> TriangleBvh {
        Self::new_cancellable(positions, triangles, &|| false).expect("never cancelled")
    }

    /// [`TriangleBvh::new`], polling `cancel` once per subtree of more
    /// than 4096 triangles: `None` once it answers true.
    pub fn new_cancellable(
        positions: &[Vec3],
        triangles: &[[u32; 3]],
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Option<TriangleBvh> {
        let corners: Vec<[Vec3; 3]> = triangles
            .par_iter()
            .map(|t| t.map(|i| positions[i as usize]))
            .collect();
        let centroids: Vec<Vec3> = corners
            .par_iter()
            .map(|c| (c[0] + c[1] + c[2]) / 3.0)
            .collect();
        let mut order: Vec<u32> = (0..triangles.len() as u32).collect();
        let empty = Node {
            lo: Vec3::INFINITY,
            hi: Vec3::NEG_INFINITY,
            start: 0,
            end: 0,
            second: 0,
        };
        let mut counts = Vec::new();
        let mut nodes = vec![empty; node_count(triangles.len(), &mut counts)];
        let tree = Subtree {
            corners: &corners,
            centroids: &centroids,
            counts: &counts,
            cancel,
        };
        tree.build(&mut order, 0, 0, &mut nodes);
        if cancel() {
            return None;
        }
        let corners = order.par_iter().map(|&t| corners[t as usize]).collect();
        Some(TriangleBvh {
            corners,
            order,
            nodes,
        })
    }

    /// Bytes held by the corners, the order and the nodes.
    pub fn memory_bytes(&self) -> usize {
        self.corners.len() * std::mem::size_of::<[Vec3; 3]>()
            + self.order.len() * 4
            + self.nodes.len() * std::mem::size_of::<Node>()
    }

    /// The number of triangles.
    pub fn len(&self) -> usize {
        self.order.len()
    }

    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// The nearest hit with `t` in `(t_min, t_max)` of the ray `origin + t dir`,
    /// ignoring triangles `skip` rejects; ties go to the lower index.
    pub fn first_hit(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_min: f32,
        mut t_max: f32,
        skip: impl Fn(u32) -> bool,
    ) -> Option<RayHit> {
        if self.corners.is_empty() {
            return None;
        }
        let inv = dir.recip();
        let mut best: Option<RayHit> = None;
        // Median splits keep the depth under 64 for any mesh that fits in
        // memory; a fixed stack keeps rays free of allocation.
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let n = stack[top];
            let node = &self.nodes[n as usize];
            if !slab_hit(node.lo, node.hi, origin, inv, t_min, t_max) {
                continue;
            }
            if node.end > node.start {
                for i in node.start as usize..node.end as usize {
                    let tri = self.order[i];
                    if skip(tri) {
                        continue;
                    }
                    let Some((t, u, v)) = triangle_hit(&self.corners[i], origin, dir) else {
                        continue;
                    };
                    let better = match best {
                        Some(b) => t < b.t || (t == b.t && tri < b.triangle),
                        None => true,
                    };
                    if t > t_min && t <= t_max && better {
                        best = Some(RayHit {
                            t,
                            triangle: tri,
                            u,
                            v,
                        });
                        t_max = t;
                    }
                }
            } else {
                stack[top] = node.second;
                stack[top + 1] = n + 1;
                top += 2;
            }
        }
        best
    }
}

/// Subtrees of at least this many triangles build their halves on two
/// threads.
const PARALLEL: usize = 1 << 14;

/// Subtrees of more than this many triangles poll the cancel first.
const POLL: usize = 1 << 12;

/// The nodes a median-split hierarchy over `n` triangles has; `memo`
/// gathers every subtree size of more than a leaf with its count (a level
/// has at most two sizes, `k` and `k + 1`, so it stays short).
fn node_count(n: usize, memo: &mut Vec<(usize, usize)>) -> usize {
    if n <= LEAF {
        return 1;
    }
    if let Some(&(_, count)) = memo.iter().find(|(m, _)| *m == n) {
        return count;
    }
    let count = 1 + node_count(n / 2, memo) + node_count(n - n / 2, memo);
    memo.push((n, count));
    count
}

/// What every subtree's build reads.
struct Subtree<'a> {
    corners: &'a [[Vec3; 3]],
    centroids: &'a [Vec3],
    /// Every subtree size of more than a leaf, with its node count.
    counts: &'a [(usize, usize)],
    cancel: &'a (dyn Fn() -> bool + Sync),
}

impl Subtree<'_> {
    /// Builds the hierarchy over `order` (triangles `offset..` in the
    /// final order) into `nodes`, exactly the slice its nodes take, in
    /// depth-first order: a node's first child follows it, its second is
    /// at `second`, `base` the index of `nodes[0]`. Node counts are known
    /// before the build, so the halves write disjoint slices and the
    /// layout is the same on any number of threads.
    fn build(&self, order: &mut [u32], offset: u32, base: u32, nodes: &mut [Node]) {
        let end = offset + order.len() as u32;
        // A cancelled build stops; its caller drops the half-made tree.
        if order.len() > POLL && (self.cancel)() {
            return;
        }
        if order.len() <= LEAF {
            let (lo, hi) = bounds_of(self.corners, order);
            nodes[0] = Node {
                lo,
                hi,
                start: offset,
                end,
                second: 0,
            };
            return;
        }
        let (clo, chi) = order
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(l, h), &t| {
                (
                    l.min(self.centroids[t as usize]),
                    h.max(self.centroids[t as usize]),
                )
            });
        let axis = (chi - clo).max_position();
        let mid = order.len() / 2;
        order.select_nth_unstable_by(mid, |&a, &b| {
            self.centroids[a as usize][axis]
                .total_cmp(&self.centroids[b as usize][axis])
                .then(a.cmp(&b))
        });
        let (left, right) = order.split_at_mut(mid);
        let (me, below) = nodes.split_first_mut().expect("a node for the subtree");
        let left_count = match mid {
            0..=LEAF => 1,
            _ => {
                self.counts
                    .iter()
                    .find(|(n, _)| *n == mid)
                    .expect("counted")
                    .1
            }
        };
        let (left_nodes, right_nodes) = below.split_at_mut(left_count);
        let second = base + 1 + left_nodes.len() as u32;
        let mut build_left = move || self.build(left, offset, base + 1, left_nodes);
        let mut build_right = move || self.build(right, offset + mid as u32, second, right_nodes);
        if mid >= PARALLEL {
            rayon::join(build_left, build_right);
        } else {
            build_left();
            build_right();
        }
        let (a, b) = (&below[0], &below[left_count]);
        *me = Node {
            lo: a.lo.min(b.lo),
            hi: a.hi.max(b.hi),
            start: offset,
            end: offset,
            second,
        };
    }
}

/// Whether the ray meets the box within `(t_min, t_max)` (slab test).
fn slab_hit(lo: Vec3, hi: Vec3, origin: Vec3, inv: Vec3, t_min: f32, t_max: f32) -> bool {
    let a = (lo - origin) * inv;
    let b = (hi - origin) * inv;
    let near = a.min(b).max_element().max(t_min);
    let far = a.max(b).min_element().min(t_max);
    // NaN (a zero direction component on the slab's plane) fails neither test.
    near <= far || near.is_nan() || far.is_nan()
}

/// Barycentric slack: a ray through a shared edge or corner hits at least
/// one of the triangles there despite rounding (no cracks in closed meshes).
const EDGE_SLACK: f32 = 1e-6;

/// Möller–Trumbore: the ray's parameter at the triangle, either side
/// facing, and the hit's barycentric (u, v) clamped into the triangle.
fn triangle_hit(c: &[Vec3; 3], origin: Vec3, dir: Vec3) -> Option<(f32, f32, f32)> {
    let e1 = c[1] - c[0];
    let e2 = c[2] - c[0];
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < f32::MIN_POSITIVE {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - c[0];
    let u = s.dot(p) * inv;
    if !(-EDGE_SLACK..=1.0 + EDGE_SLACK).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = dir.dot(q) * inv;
    if v < -EDGE_SLACK || u + v > 1.0 + EDGE_SLACK {
        return None;
    }
    let (u, v) = (u.clamp(0.0, 1.0), v.clamp(0.0, 1.0));
    let over = (u + v - 1.0).max(0.0) / 2.0;
    Some((e2.dot(q) * inv, u - over, v - over))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grid of unit squares (two triangles each) in the plane z = `z`.
    fn grid(n: u32, z: f32, positions: &mut Vec<Vec3>, tris: &mut Vec<[u32; 3]>) {
        let base = positions.len() as u32;
        for j in 0..=n {
            for i in 0..=n {
                positions.push(Vec3::new(i as f32, j as f32, z));
            }
        }
        let at = |i: u32, j: u32| base + j * (n + 1) + i;
        for j in 0..n {
            for i in 0..n {
                tris.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                tris.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
    }

    #[test]
    fn nearest_of_stacked_planes_against_brute_force() {
        let (mut p, mut t) = (Vec::new(), Vec::new());
        for z in [0.0, 0.7, 2.5, -1.0] {
            grid(12, z, &mut p, &mut t);
        }
        let bvh = TriangleBvh::new(&p, &t);
        let mut seed = 7u32;
        let mut next = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1u32 << 24) as f32
        };
        for _ in 0..200 {
            let o = Vec3::new(next() * 12.0, next() * 12.0, next() * 4.0 - 1.5);
            let d = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize();
            let hit = bvh.first_hit(o, d, 1e-6, f32::INFINITY, |_| false);
            if let Some(h) = hit {
                // The weights give back the point the ray reaches.
                let c = t[h.triangle as usize].map(|i| p[i as usize]);
                let on = c[0] + (c[1] - c[0]) * h.u + (c[2] - c[0]) * h.v;
                assert!(on.distance(o + d * h.t) < 1e-4, "ray {o} {d}: {on}");
            }
            let got = hit.map(|h| h.t);
            let want = t
                .iter()
                .filter_map(|tri| triangle_hit(&tri.map(|i| p[i as usize]), o, d))
                .map(|(s, _, _)| s)
                .filter(|&s| s > 1e-6)
                .fold(None, |m: Option<f32>, s| Some(m.map_or(s, |m| m.min(s))));
            assert_eq!(got, want, "ray {o} {d}");
        }
    }

    /// Big enough that the top levels build on two threads: the same
    /// nodes in the same places, and each node's box the union of its
    /// triangles'.
    #[test]
    fn the_hierarchy_is_the_same_on_any_number_of_threads() {
        let (mut p, mut t) = (Vec::new(), Vec::new());
        grid(130, 0.0, &mut p, &mut t);
        for q in p.iter_mut() {
            q.z = (q.x * 0.37).sin() * (q.y * 0.21).cos();
        }
        let in_pool = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| TriangleBvh::new(&p, &t))
        };
        let (one, four) = (in_pool(1), in_pool(4));
        assert!(t.len() / 2 >= PARALLEL);
        assert_eq!(one.order, four.order);
        assert_eq!(one.nodes, four.nodes);
        assert_eq!(one.nodes.len(), node_count(t.len(), &mut Vec::new()));
        for node in one.nodes.iter().filter(|n| n.end > n.start) {
            let (lo, hi) = bounds_of(
                &t.iter()
                    .map(|x| x.map(|i| p[i as usize]))
                    .collect::<Vec<_>>(),
                &one.order[node.start as usize..node.end as usize],
            );
            assert_eq!((node.lo, node.hi), (lo, hi));
        }
        assert_eq!(
            (one.nodes[0].lo, one.nodes[0].hi),
            bounds_of(&one.corners, &(0..t.len() as u32).collect::<Vec<_>>())
        );
    }

    #[test]
    fn skipped_triangles_are_passed_through() {
        let (mut p, mut t) = (Vec::new(), Vec::new());
        grid(2, 0.0, &mut p, &mut t);
        grid(2, 1.0, &mut p, &mut t);
        let bvh = TriangleBvh::new(&p, &t);
        let o = Vec3::new(0.3, 0.6, -1.0);
        let first = bvh
            .first_hit(o, Vec3::Z, 0.0, f32::INFINITY, |_| false)
            .unwrap();
        assert_eq!(first.t, 1.0);
        let second = bvh
            .first_hit(o, Vec3::Z, 0.0, f32::INFINITY, |tri| tri == first.triangle)
            .unwrap();
        assert_eq!(second.t, 2.0);
    }
}
