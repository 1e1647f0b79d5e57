//! Unions of many capsules (sphere sweeps along polylines) as one field
//! primitive over a bounding-volume hierarchy: point, gradient and interval
//! evaluation visit only the capsules that can decide the value where they
//! look, and an interval evaluation over a region narrows the set to the
//! capsules that may win there (the tape keeps the narrowed set).
//!
//! Each capsule is `r(t) - |p - (a + t (b - a))|` with `t` the clamped
//! parameter of the point of the segment nearest `p` and `r` interpolated
//! linearly between the end radii; the union is the maximum. The maximum is
//! exact in floating point, so visiting fewer capsules never changes a value.
//! A set may carry a floor (the mesher's: it reads values only a few cells
//! from the surface), below which capsules drop out of every search.

use crate::interval::Interval;

/// One segment with its end radii.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Capsule {
    a: [f64; 3],
    ab: [f64; 3],
    /// `1 / |ab|^2`, or 0 for a point (then `t` is always 0).
    inv_len2: f64,
    ra: f64,
    dr: f64,
}

/// A hierarchy node: the box of its segments (radii not included), the
/// largest radius under it, its capsules `start..end` and, for an inner node,
/// its second child (the first is the next node).
#[derive(Clone, Copy, Debug)]
struct BvhNode {
    lo: [f64; 3],
    hi: [f64; 3],
    r_max: f64,
    start: u32,
    end: u32,
    second: u32,
}

/// Capsules per leaf, and the set size under which evaluation is a plain loop.
const LEAF: usize = 4;
const LINEAR: usize = 8;
/// The set size over which a batch first looks for the capsules near it.
const SEARCHED: usize = 16;

thread_local! {
    /// The last point query's set and winner on this thread (a hint only:
    /// answers never depend on it).
    static LAST_WINNER: std::cell::Cell<(u128, usize)> = const { std::cell::Cell::new((0, usize::MAX)) };
}

/// A union of capsules with its hierarchy; immutable once built.
#[derive(Debug)]
pub struct CapsuleSet {
    /// In hierarchy order.
    caps: Vec<Capsule>,
    nodes: Vec<BvhNode>,
    identity: u128,
    /// The union is `max(floor, capsules)`: a mesher that reads values only
    /// near zero floors far values, and capsules that cannot rise above the
    /// floor drop out of every search (negative infinity: no floor).
    floor: f64,
}

impl PartialEq for CapsuleSet {
    fn eq(&self, other: &CapsuleSet) -> bool {
        self.identity == other.identity
    }
}

fn sub(p: [f64; 3], q: [f64; 3]) -> [f64; 3] {
    [p[0] - q[0], p[1] - q[1], p[2] - q[2]]
}

fn dot(p: [f64; 3], q: [f64; 3]) -> f64 {
    p[0] * q[0] + p[1] * q[1] + p[2] * q[2]
}

/// Distance from a point to a box (0 inside).
fn point_box_distance(p: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> f64 {
    let d: [f64; 3] = std::array::from_fn(|k| (lo[k] - p[k]).max(p[k] - hi[k]).max(0.0));
    dot(d, d).sqrt()
}

/// Distance between two boxes (0 when they overlap).
fn box_box_distance(lo: [f64; 3], hi: [f64; 3], lo2: [f64; 3], hi2: [f64; 3]) -> f64 {
    let d: [f64; 3] = std::array::from_fn(|k| (lo2[k] - hi[k]).max(lo[k] - hi2[k]).max(0.0));
    dot(d, d).sqrt()
}

impl Capsule {
    fn new(a: [f64; 3], b: [f64; 3], ra: f64, rb: f64) -> Capsule {
        let ab = sub(b, a);
        let len2 = dot(ab, ab);
        Capsule {
            a,
            ab,
            inv_len2: if len2 > 0.0 { 1.0 / len2 } else { 0.0 },
            ra,
            dr: rb - ra,
        }
    }

    fn b(&self) -> [f64; 3] {
        std::array::from_fn(|k| self.a[k] + self.ab[k])
    }

    fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let b = self.b();
        (
            std::array::from_fn(|k| self.a[k].min(b[k])),
            std::array::from_fn(|k| self.a[k].max(b[k])),
        )
    }

    fn r_min(&self) -> f64 {
        self.ra.min(self.ra + self.dr)
    }

    fn r_max(&self) -> f64 {
        self.ra.max(self.ra + self.dr)
    }

    /// The clamped parameter of the nearest point, whether it was clamped,
    /// and the offset from that point to `p`.
    fn nearest(&self, p: [f64; 3]) -> (f64, bool, [f64; 3]) {
        let ap = sub(p, self.a);
        let t = dot(ap, self.ab) * self.inv_len2;
        let clamped = !(t > 0.0 && t < 1.0);
        let t = t.clamp(0.0, 1.0);
        (t, clamped, std::array::from_fn(|k| ap[k] - t * self.ab[k]))
    }

    fn value(&self, p: [f64; 3]) -> f64 {
        let (t, _, d) = self.nearest(p);
        self.ra + t * self.dr - dot(d, d).sqrt()
    }

    fn distance(&self, p: [f64; 3]) -> f64 {
        let (_, _, d) = self.nearest(p);
        dot(d, d).sqrt()
    }

    /// Value and gradient; on the segment itself the distance's gradient is
    /// taken as 0 (a subgradient), as the evaluators do for `sqrt` at 0.
    fn value_gradient(&self, p: [f64; 3]) -> (f64, [f64; 3]) {
        let (t, clamped, d) = self.nearest(p);
        let dist = dot(d, d).sqrt();
        let mut g = [0.0; 3];
        if dist > 0.0 {
            // d = p - a - t ab; with t free, dd/dp = I - ab ab^T / |ab|^2.
            let along = if clamped {
                0.0
            } else {
                dot(d, self.ab) * self.inv_len2
            };
            for k in 0..3 {
                g[k] = -(d[k] - along * self.ab[k]) / dist;
            }
        }
        if !clamped {
            for (gk, abk) in g.iter_mut().zip(self.ab) {
                *gk += self.dr * abk * self.inv_len2;
            }
        }
        (self.ra + t * self.dr - dist, g)
    }
}

/// A capsule in single precision, for batches (as the batch evaluator's
/// other operations are): four lanes per instruction instead of two.
#[derive(Clone, Copy)]
struct Capsule32 {
    a: [f32; 3],
    ab: [f32; 3],
    inv_len2: f32,
    ra: f32,
    dr: f32,
}

impl Capsule32 {
    fn of(c: &Capsule) -> Capsule32 {
        Capsule32 {
            a: c.a.map(|v| v as f32),
            ab: c.ab.map(|v| v as f32),
            inv_len2: c.inv_len2 as f32,
            ra: c.ra as f32,
            dr: c.dr as f32,
        }
    }

    #[inline(always)]
    fn value(&self, x: f32, y: f32, z: f32) -> f32 {
        let (px, py, pz) = (x - self.a[0], y - self.a[1], z - self.a[2]);
        let t =
            ((px * self.ab[0] + py * self.ab[1] + pz * self.ab[2]) * self.inv_len2).clamp(0.0, 1.0);
        let (dx, dy, dz) = (
            px - t * self.ab[0],
            py - t * self.ab[1],
            pz - t * self.ab[2],
        );
        self.ra + t * self.dr - (dx * dx + dy * dy + dz * dz).sqrt()
    }
}

impl CapsuleSet {
    /// The capsules of the polyline `points` (one sphere for a single point),
    /// radii per point.
    pub fn polyline_segments(
        points: &[[f64; 3]],
        radii: &[f64],
    ) -> Vec<([f64; 3], [f64; 3], f64, f64)> {
        if points.len() == 1 {
            return vec![(points[0], points[0], radii[0], radii[0])];
        }
        points
            .windows(2)
            .zip(radii.windows(2))
            .map(|(p, r)| (p[0], p[1], r[0], r[1]))
            .collect()
    }

    /// Builds the hierarchy over segments `(a, b, ra, rb)`; `None` when empty.
    pub fn new(segments: &[([f64; 3], [f64; 3], f64, f64)]) -> Option<CapsuleSet> {
        if segments.is_empty() {
            return None;
        }
        let caps: Vec<Capsule> = segments
            .iter()
            .map(|&(a, b, ra, rb)| Capsule::new(a, b, ra, rb))
            .collect();
        let identity = {
            use xxhash_rust::xxh3::Xxh3;
            let mut h = Xxh3::new();
            h.update(b"capsules");
            for &(a, b, ra, rb) in segments {
                for v in a.iter().chain(&b).chain(&[ra, rb]) {
                    h.update(&v.to_bits().to_le_bytes());
                }
            }
            h.digest128()
        };
        Some(CapsuleSet::build(caps, identity, f64::NEG_INFINITY))
    }

    fn build(mut caps: Vec<Capsule>, identity: u128, floor: f64) -> CapsuleSet {
        let mut nodes = Vec::with_capacity(2 * caps.len() / LEAF + 1);
        let n = caps.len();
        build_node(&mut caps, 0, n, &mut nodes);
        CapsuleSet {
            caps,
            nodes,
            identity,
            floor,
        }
    }

    /// The same union with values below `floor` raised to it (see the
    /// field's doc); equal to this set wherever either is above the floor.
    pub fn with_floor(&self, floor: f64) -> CapsuleSet {
        let floor = floor.max(self.floor);
        let identity = {
            use xxhash_rust::xxh3::Xxh3;
            let mut h = Xxh3::new();
            h.update(&self.identity.to_le_bytes());
            h.update(b"floor");
            h.update(&floor.to_bits().to_le_bytes());
            h.digest128()
        };
        CapsuleSet {
            caps: self.caps.clone(),
            nodes: self.nodes.clone(),
            identity,
            floor,
        }
    }

    /// Appends the set as built (see `codec.rs`).
    pub(crate) fn encode(&self, out: &mut Vec<u8>) {
        let f = |out: &mut Vec<u8>, v: &[f64]| {
            v.iter()
                .for_each(|x| out.extend_from_slice(&x.to_le_bytes()))
        };
        out.extend_from_slice(&self.identity.to_le_bytes());
        f(out, &[self.floor]);
        out.extend_from_slice(&(self.caps.len() as u64).to_le_bytes());
        for c in &self.caps {
            f(out, &c.a);
            f(out, &c.ab);
            f(out, &[c.inv_len2, c.ra, c.dr]);
        }
        out.extend_from_slice(&(self.nodes.len() as u64).to_le_bytes());
        for n in &self.nodes {
            f(out, &n.lo);
            f(out, &n.hi);
            f(out, &[n.r_max]);
            for i in [n.start, n.end, n.second] {
                out.extend_from_slice(&i.to_le_bytes());
            }
        }
    }

    /// Reads a set [`CapsuleSet::encode`] wrote; every index is checked, so
    /// evaluation of a decoded set never reads out of bounds.
    pub(crate) fn decode(
        r: &mut crate::codec::Reader,
    ) -> Result<CapsuleSet, crate::codec::FieldDecodeError> {
        use crate::codec::FieldDecodeError as E;
        let identity = u128::from_le_bytes(r.take(16)?.try_into().expect("sixteen bytes"));
        let floor = r.f64()?;
        let n_caps = r.count(88)?;
        let mut caps = Vec::with_capacity(n_caps);
        let v3 = |r: &mut crate::codec::Reader| -> Result<[f64; 3], E> {
            Ok([r.f64()?, r.f64()?, r.f64()?])
        };
        for _ in 0..n_caps {
            let (a, ab) = (v3(r)?, v3(r)?);
            caps.push(Capsule {
                a,
                ab,
                inv_len2: r.f64()?,
                ra: r.f64()?,
                dr: r.f64()?,
            });
        }
        let n_nodes = r.count(68)?;
        let mut nodes = Vec::with_capacity(n_nodes);
        for _ in 0..n_nodes {
            let (lo, hi) = (v3(r)?, v3(r)?);
            let r_max = r.f64()?;
            let (start, end, second) = (r.u32()?, r.u32()?, r.u32()?);
            nodes.push(BvhNode {
                lo,
                hi,
                r_max,
                start,
                end,
                second,
            });
        }
        // A leaf has `second` 0; an inner node's children come after it (so
        // no traversal can loop) and exist.
        let len = nodes.len();
        let bad = nodes.is_empty()
            || caps.is_empty()
            || nodes.iter().enumerate().any(|(i, n)| {
                let inner_bad = n.second != 0
                    && (i + 1 >= len || n.second as usize <= i || n.second as usize >= len);
                n.start > n.end || n.end as usize > caps.len() || inner_bad
            });
        if bad {
            return Err(E::Invalid("capsule hierarchy".into()));
        }
        Ok(CapsuleSet {
            caps,
            nodes,
            identity,
            floor,
        })
    }

    /// Structural identity: equal for equal segment lists.
    pub fn identity(&self) -> u128 {
        self.identity
    }

    pub fn len(&self) -> usize {
        self.caps.len()
    }

    pub fn is_empty(&self) -> bool {
        self.caps.is_empty()
    }

    /// Bytes held by the capsules and their hierarchy.
    pub fn memory_bytes(&self) -> usize {
        self.caps.len() * std::mem::size_of::<Capsule>()
            + self.nodes.len() * std::mem::size_of::<BvhNode>()
    }

    /// A step for central differences of the union's value: a thousandth of
    /// the set's extent, coarse enough for single-precision batches.
    pub fn difference_step(&self) -> f64 {
        let root = &self.nodes[0];
        let extent = (0..3).map(|k| root.hi[k] - root.lo[k]).fold(0.0, f64::max);
        1e-3 * (extent + root.r_max).max(1e-6)
    }

    /// The union's value at `p`.
    pub fn value(&self, p: [f64; 3]) -> f64 {
        match self.winner(p) {
            Some(i) => self.caps[i].value(p),
            None => self.floor,
        }
    }

    /// The union's value and gradient at `p` (the winning capsule's).
    pub fn value_gradient(&self, p: [f64; 3]) -> (f64, [f64; 3]) {
        match self.winner(p) {
            Some(i) => self.caps[i].value_gradient(p),
            None => (self.floor, [0.0; 3]),
        }
    }

    /// The capsule of the largest value at `p`, the lowest index among equals
    /// (so the answer does not depend on the order capsules are visited in);
    /// `None` where no capsule rises above the floor.
    /// The thread's previous winner in this set is tried first: neighbouring
    /// points mostly share a winner, and its value prunes the search.
    fn winner(&self, p: [f64; 3]) -> Option<usize> {
        let better =
            |v: f64, i: usize, best: (f64, usize)| v > best.0 || (v == best.0 && i < best.1);
        let consider = |best: &mut (f64, usize), range: std::ops::Range<usize>| {
            for i in range {
                let v = self.caps[i].value(p);
                if better(v, i, *best) {
                    *best = (v, i);
                }
            }
        };
        // The floor as a capsule past every index: it wins only above all.
        // With no floor, a point where nothing wins (infinitely far) takes
        // the first capsule's value.
        let mut best = (self.floor, usize::MAX);
        let found = |best: (f64, usize)| match best.1 {
            usize::MAX if self.floor == f64::NEG_INFINITY => Some(0),
            usize::MAX => None,
            i => Some(i),
        };
        if p.iter().any(|c| c.is_nan()) {
            // Not a number: the first capsule's value says so.
            return Some(0);
        }
        if self.caps.len() <= LINEAR || p.iter().any(|c| !c.is_finite()) {
            consider(&mut best, 0..self.caps.len());
            return found(best);
        }
        let hint = LAST_WINNER.with(|h| {
            let (set, i) = h.get();
            (set == self.identity && i < self.caps.len()).then_some(i)
        });
        if let Some(i) = hint {
            let v = self.caps[i].value(p);
            if better(v, i, best) {
                best = (v, i);
            }
        }
        // Median splits keep the depth under 64 for any set that fits in memory.
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let n = stack[top];
            let node = &self.nodes[n as usize];
            // Strictly below: an equal value may still win on its index.
            if node.r_max - point_box_distance(p, node.lo, node.hi) < best.0 {
                continue;
            }
            if node.second == 0 {
                consider(&mut best, node.start as usize..node.end as usize);
                continue;
            }
            // The nearer child last on the stack: visited first, it raises
            // the bound that prunes the other.
            let (first, second) = (n + 1, node.second);
            let d = |c: u32| {
                let c = &self.nodes[c as usize];
                point_box_distance(p, c.lo, c.hi)
            };
            let (later, sooner) = if d(first) <= d(second) {
                (second, first)
            } else {
                (first, second)
            };
            stack[top] = later;
            stack[top + 1] = sooner;
            top += 2;
        }
        if best.1 != usize::MAX {
            LAST_WINNER.with(|h| h.set((self.identity, best.1)));
        }
        found(best)
    }

    /// Bounds of the union over a box, and the set narrowed to the capsules
    /// that may win somewhere in it (`None`: all of them may).
    pub fn interval(
        &self,
        x: Interval,
        y: Interval,
        z: Interval,
    ) -> (Interval, Option<CapsuleSet>) {
        let lo = [x.lo, y.lo, z.lo];
        let hi = [x.hi, y.hi, z.hi];
        if lo.iter().chain(&hi).any(|v| v.is_nan()) {
            return (Interval::new(f64::NEG_INFINITY, f64::INFINITY), None);
        }
        let (best_lo, mut candidates) = self.candidates(lo, hi);
        let best_hi = candidates.iter().fold(self.floor, |m, &(_, h)| m.max(h));
        if candidates.is_empty() {
            // Only the floor is left: one capsule keeps the set a set.
            candidates.push((0, self.floor));
        }
        let narrowed = (candidates.len() < self.caps.len()).then(|| {
            candidates.sort_unstable_by_key(|&(i, _)| i);
            let caps = candidates
                .iter()
                .map(|&(i, _)| self.caps[i as usize])
                .collect();
            CapsuleSet::build(
                caps,
                narrowed_identity(self.identity, &candidates),
                self.floor,
            )
        });
        (Interval::new(best_lo, best_hi), narrowed)
    }

    /// The union's values at many points (`out[i]` at `(xs[i], ys[i],
    /// zs[i])`): the capsules that may win in the points' bounding box
    /// found once, then each evaluated over all the points in a loop the
    /// compiler vectorises.
    pub fn values(&self, xs: &[f32], ys: &[f32], zs: &[f32], out: &mut [f32]) {
        let axes = [xs, ys, zs];
        let lo: [f64; 3] = axes.map(|a| a.iter().fold(f32::INFINITY, |m, &v| m.min(v)) as f64);
        let hi: [f64; 3] = axes.map(|a| a.iter().fold(f32::NEG_INFINITY, |m, &v| m.max(v)) as f64);
        if lo.iter().chain(&hi).any(|v| !v.is_finite()) {
            for (i, o) in out.iter_mut().enumerate() {
                *o = self.value([xs[i], ys[i], zs[i]].map(f64::from)) as f32;
            }
            return;
        }
        // A small set costs less evaluated whole than searched.
        let candidates: Vec<(u32, f64)> = if self.caps.len() <= SEARCHED {
            (0..self.caps.len() as u32).map(|i| (i, 0.0)).collect()
        } else {
            self.candidates(lo, hi).1
        };
        let floor = self.floor as f32;
        let mut best = [floor; crate::eval::LANES];
        for chunk_start in (0..out.len()).step_by(best.len()) {
            let n = (out.len() - chunk_start).min(best.len());
            let best = &mut best[..n];
            best.fill(floor);
            let at = |k: usize| &axes[k][chunk_start..chunk_start + n];
            let (px, py, pz) = (at(0), at(1), at(2));
            for &(c, _) in &candidates {
                let c = Capsule32::of(&self.caps[c as usize]);
                for (((b, &x), &y), &z) in best.iter_mut().zip(px).zip(py).zip(pz) {
                    *b = b.max(c.value(x, y, z));
                }
            }
            for (o, b) in out[chunk_start..chunk_start + n]
                .iter_mut()
                .zip(best.iter())
            {
                *o = *b;
            }
        }
    }

    /// The capsules that may give the union's value somewhere in the box
    /// `lo..hi` (finite), each with the upper bound of its value there, and
    /// the largest lower bound of any capsule's value (the union's lower
    /// bound). Bounds per capsule: its distance to the segment is convex, so
    /// its largest value over the box is at a corner; its smallest is at
    /// least the boxes' distance and the centre's distance less half the
    /// diagonal.
    fn candidates(&self, lo: [f64; 3], hi: [f64; 3]) -> (f64, Vec<(u32, f64)>) {
        let finite = lo.iter().chain(&hi).all(|v| v.is_finite());
        let center: [f64; 3] = std::array::from_fn(|k| 0.5 * (lo[k] + hi[k]));
        let half_diagonal = 0.5 * dot(sub(hi, lo), sub(hi, lo)).sqrt();
        let corners: [[f64; 3]; 8] = std::array::from_fn(|c| {
            std::array::from_fn(|k| if c >> k & 1 == 0 { lo[k] } else { hi[k] })
        });
        // The upper bound first: a capsule that cannot reach the best lower
        // bound so far cannot raise it either, and its corners are skipped.
        // Returns (upper bound, distance from the centre).
        let upper = |c: &Capsule| {
            let (clo, chi) = c.bounds();
            let mut near = box_box_distance(lo, hi, clo, chi);
            let mut from_center = f64::INFINITY;
            if finite {
                from_center = c.distance(center);
                near = near.max(from_center - half_diagonal);
            }
            (c.r_max() - near, from_center)
        };
        // The distance is convex, so its largest value over the box is at a
        // corner and at least the centre's: corners are only measured when
        // the centre says they could raise the best lower bound.
        let lower = |c: &Capsule, from_center: f64, best_lo: f64| {
            if !finite || c.r_min() - from_center <= best_lo {
                return f64::NEG_INFINITY;
            }
            c.r_min() - corners.iter().fold(0.0f64, |m, &p| m.max(c.distance(p)))
        };
        let mut best_lo = self.floor;
        let mut candidates: Vec<(u32, f64)> = Vec::new();
        let mut stack = vec![0u32];
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n as usize];
            if node.r_max - box_box_distance(lo, hi, node.lo, node.hi) < best_lo {
                continue;
            }
            if node.second == 0 {
                for i in node.start..node.end {
                    let c = &self.caps[i as usize];
                    let (h, from_center) = upper(c);
                    if h >= best_lo {
                        best_lo = best_lo.max(lower(c, from_center, best_lo));
                        candidates.push((i, h));
                    }
                }
                continue;
            }
            let (first, second) = (n + 1, node.second);
            let d = |c: u32| {
                let c = &self.nodes[c as usize];
                box_box_distance(lo, hi, c.lo, c.hi)
            };
            if d(first) <= d(second) {
                stack.extend([second, first]);
            } else {
                stack.extend([first, second]);
            }
        }
        candidates.retain(|&(_, h)| h >= best_lo);
        (best_lo, candidates)
    }
}

fn narrowed_identity(parent: u128, kept: &[(u32, f64)]) -> u128 {
    use xxhash_rust::xxh3::Xxh3;
    let mut h = Xxh3::new();
    h.update(&parent.to_le_bytes());
    for &(i, _) in kept {
        h.update(&i.to_le_bytes());
    }
    h.digest128()
}

/// Builds the node over `caps[start..end]` (reordering them) depth first:
/// split at the median of the segment midpoints along the box's longest axis.
fn build_node(caps: &mut [Capsule], start: usize, end: usize, nodes: &mut Vec<BvhNode>) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    let mut r_max = f64::NEG_INFINITY;
    for c in &caps[start..end] {
        let (clo, chi) = c.bounds();
        for k in 0..3 {
            lo[k] = lo[k].min(clo[k]);
            hi[k] = hi[k].max(chi[k]);
        }
        r_max = r_max.max(c.r_max());
    }
    let index = nodes.len();
    nodes.push(BvhNode {
        lo,
        hi,
        r_max,
        start: start as u32,
        end: end as u32,
        second: 0,
    });
    // A set evaluated as a plain loop needs no hierarchy under its root.
    if end - start <= LEAF || (start == 0 && end <= LINEAR) {
        return;
    }
    let axis = (0..3)
        .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
        .unwrap_or(0);
    let mid = |c: &Capsule| 2.0 * c.a[axis] + c.ab[axis];
    // A partition about the median (linear time); the same input always
    // gives the same hierarchy.
    let half = (end - start) / 2;
    caps[start..end].select_nth_unstable_by(half, |p, q| mid(p).total_cmp(&mid(q)));
    let half = start + half;
    build_node(caps, start, half, nodes);
    let second = nodes.len() as u32;
    build_node(caps, half, end, nodes);
    nodes[index].second = second;
}

#[cfg(test)]
mod tests;
