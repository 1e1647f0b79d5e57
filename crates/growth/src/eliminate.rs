//! Sample elimination (Yuksel 2015, "Sample Elimination for Generating
//! Poisson Disk Sample Sets") at millions of candidates: candidates sorted
//! into a grid of cells one neighbourhood radius wide (so neighbours are
//! near in memory), every candidate's neighbour list built once in parallel,
//! then the most crowded removed one at a time from a bucket queue (weights
//! only fall, so the highest non-empty bucket only moves down and each step
//! costs O(neighbours)). Buckets are 1/65536 of the largest weight wide: the
//! order within one is by position, deterministic for any thread count.

use geode_geo::glam::Vec3;
use rayon::prelude::*;

use crate::scatter::ScatterError;

/// A neighbour's weight at distance `d` under `reach`: Yuksel's
/// `(1 - d / reach)^alpha` with alpha 8 (three squarings).
fn falloff(reach: f32) -> impl Fn(f32) -> f64 {
    let per_reach = 1.0 / reach as f64;
    move |d: f32| {
        let x = 1.0 - d as f64 * per_reach;
        let x2 = x * x;
        let x4 = x2 * x2;
        x4 * x4
    }
}

/// Buckets of the removal queue.
const BUCKETS: usize = 1 << 16;

/// Cells a parallel task gathers neighbours for.
const CELLS_PER_TASK: usize = 256;

/// Bytes elimination takes per candidate, for a memory budget: its
/// neighbour list (about 18 entries on a surface and 29 in a volume at five
/// candidates per kept point; 40 allowed) and its position, order, weight,
/// list offset, flag and queue entries.
pub const BYTES_PER_CANDIDATE: f64 = 40.0 * 4.0 + 48.0;

/// Candidates sorted by grid cell, with the cells found by hashing.
struct CellGrid {
    /// Candidate indices in cell order.
    order: Vec<u32>,
    /// Positions in cell order.
    sorted: Vec<Vec3>,
    /// Each cell's key and first position in `order` (plus an end marker).
    cells: Vec<(u64, u32)>,
    /// Each cell's coordinates.
    coords: Vec<[i64; 3]>,
    /// Open addressing from cell key to cell number; `u32::MAX` is empty.
    table: Vec<u32>,
}

const AXIS_BITS: u32 = 21;

/// A cell's key: its coordinates' bits interleaved (Morton order), so cells
/// near in space are mostly near in the sorted candidates too.
fn pack(c: [i64; 3]) -> Option<u64> {
    let limit = 1i64 << AXIS_BITS;
    if !c.iter().all(|&x| (0..limit).contains(&x)) {
        return None;
    }
    let spread = |x: i64| -> u64 {
        let mut x = x as u64 & 0x1f_ffff;
        x = (x | x << 32) & 0x1f_0000_0000_ffff;
        x = (x | x << 16) & 0x1f_0000_ff00_00ff;
        x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
        x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
        x = (x | x << 2) & 0x1249_2492_4924_9249;
        x
    };
    Some(spread(c[0]) | spread(c[1]) << 1 | spread(c[2]) << 2)
}

fn slot(key: u64, bits: u32) -> usize {
    (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - bits)) as usize
}

impl CellGrid {
    /// Cells at least `reach` wide (wider where the points span more than
    /// 2^21 of them on an axis), so every neighbour lies in the 27 cells
    /// around a point's own.
    fn build(points: &[Vec3], reach: f32, cancel: &(dyn Fn() -> bool + Sync)) -> Option<CellGrid> {
        let (lo, hi) = points.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(a, b), p| (a.min(*p), b.max(*p)),
        );
        let span = (hi - lo).max_element();
        let side = reach.max(span / ((1u32 << AXIS_BITS) - 2) as f32);
        // One cell of margin so neighbour cells of the first row are valid.
        let origin = lo - Vec3::splat(side);
        let coords_of = |p: &Vec3| -> [i64; 3] {
            let c = ((*p - origin) / side).floor();
            [c.x as i64, c.y as i64, c.z as i64]
        };
        let key_of = |p: &Vec3| pack(coords_of(p)).unwrap_or(u64::MAX);
        let keyed: Vec<(u64, u32)> = points
            .par_iter()
            .enumerate()
            .map(|(i, p)| (key_of(p), i as u32))
            .collect();
        let keyed = radix_sort(keyed, cancel)?;
        let order: Vec<u32> = keyed.par_iter().map(|k| k.1).collect();
        let sorted: Vec<Vec3> = order.par_iter().map(|&i| points[i as usize]).collect();
        let mut cells: Vec<(u64, u32)> = Vec::new();
        let mut coords = Vec::new();
        for (s, k) in keyed.iter().enumerate() {
            if s % PER_POLL == PER_POLL - 1 && cancel() {
                return None;
            }
            if cells.last().is_none_or(|c| c.0 != k.0) {
                cells.push((k.0, s as u32));
                coords.push(coords_of(&sorted[s]));
            }
        }
        drop(keyed);
        if cancel() {
            return None;
        }
        let bits = (2 * cells.len())
            .next_power_of_two()
            .trailing_zeros()
            .max(4);
        let mut table = vec![u32::MAX; 1 << bits];
        for (c, &(key, _)) in cells.iter().enumerate() {
            let mut at = slot(key, bits);
            while table[at] != u32::MAX {
                at = (at + 1) & (table.len() - 1);
            }
            table[at] = c as u32;
        }
        cells.push((u64::MAX, points.len() as u32));
        Some(CellGrid {
            order,
            sorted,
            cells,
            coords,
            table,
        })
    }

    /// The range in cell order of the cell with `key`, if any point is there.
    fn range(&self, key: u64) -> Option<std::ops::Range<usize>> {
        let bits = self.table.len().trailing_zeros();
        let mut at = slot(key, bits);
        loop {
            let c = self.table[at];
            if c == u32::MAX {
                return None;
            }
            if self.cells[c as usize].0 == key {
                let c = c as usize;
                return Some(self.cells[c].1 as usize..self.cells[c + 1].1 as usize);
            }
            at = (at + 1) & (self.table.len() - 1);
        }
    }

    /// Candidates (cell order) of the 27 cells around cell number `c`.
    fn around(&self, c: usize, out: &mut Vec<u32>) {
        out.clear();
        let at = self.coords[c];
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    if let Some(r) =
                        pack([at[0] + dx, at[1] + dy, at[2] + dz]).and_then(|k| self.range(k))
                    {
                        out.extend(r.start as u32..r.end as u32);
                    }
                }
            }
        }
    }
}

/// Elements a radix pass moves between polls of `cancel`.
const PER_POLL: usize = 1 << 20;

/// `(key, index)` pairs sorted: split by the top eight bits the largest key
/// uses (a counting pass, polling `cancel` per million moves), then the
/// 256 parts sorted in parallel (polling per part), so a cancel is seen
/// within a part's sort; `None` when cancelled.
fn radix_sort(
    pairs: Vec<(u64, u32)>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Option<Vec<(u64, u32)>> {
    let largest = pairs.iter().map(|p| p.0).max().unwrap_or(0);
    let shift = (u64::BITS - largest.leading_zeros()).saturating_sub(8);
    let digit = |p: &(u64, u32)| (p.0 >> shift) as usize & 255;
    let mut counts = [0usize; 257];
    pairs.iter().for_each(|p| counts[digit(p) + 1] += 1);
    for d in 1..257 {
        counts[d] += counts[d - 1];
    }
    let mut next = counts;
    let mut split = vec![(0u64, 0u32); pairs.len()];
    for chunk in pairs.chunks(PER_POLL) {
        if cancel() {
            return None;
        }
        for p in chunk {
            let d = digit(p);
            split[next[d]] = *p;
            next[d] += 1;
        }
    }
    drop(pairs);
    let mut parts: Vec<&mut [(u64, u32)]> = Vec::with_capacity(256);
    let mut rest = split.as_mut_slice();
    for d in 0..256 {
        let (part, tail) = rest.split_at_mut(counts[d + 1] - counts[d]);
        parts.push(part);
        rest = tail;
    }
    let sorted = parts.into_par_iter().all(|part| {
        if cancel() {
            return false;
        }
        part.sort_unstable();
        true
    });
    sorted.then_some(split)
}

/// Every candidate's neighbours closer than `reach` (cell order, compressed
/// rows) and its crowding weight; `None` when cancelled.
fn neighbourhoods(
    grid: &CellGrid,
    reach: f32,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Option<(Vec<u32>, Vec<u32>, Vec<f64>)> {
    let weight = falloff(reach);
    let cell_count = grid.cells.len() - 1;
    let parts: Vec<(Vec<u32>, Vec<u32>, Vec<f64>)> = (0..cell_count.div_ceil(CELLS_PER_TASK))
        .into_par_iter()
        .map(|task| {
            if cancel() {
                return None;
            }
            let cells = task * CELLS_PER_TASK..((task + 1) * CELLS_PER_TASK).min(cell_count);
            let (mut counts, mut lists, mut weights) = (Vec::new(), Vec::new(), Vec::new());
            let (mut near, mut hits) = (Vec::new(), Vec::new());
            let (mut xs, mut ys, mut zs, mut d2) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
            for c in cells {
                grid.around(c, &mut near);
                // The 27 cells' points side by side, coordinates apart, so
                // the distance tests run as plain vector arithmetic.
                for (axis, column) in [&mut xs, &mut ys, &mut zs].into_iter().enumerate() {
                    column.clear();
                    column.extend(near.iter().map(|&t| grid.sorted[t as usize][axis]));
                }
                for s in grid.cells[c].1..grid.cells[c + 1].1 {
                    let p = grid.sorted[s as usize];
                    d2.clear();
                    d2.extend(xs.iter().zip(&ys).zip(&zs).map(|((x, y), z)| {
                        (x - p.x).powi(2) + (y - p.y).powi(2) + (z - p.z).powi(2)
                    }));
                    // Branch-free gathering: most of the 27 cells' points
                    // lie beyond reach, unpredictably.
                    hits.resize(near.len(), 0);
                    let mut found = 0;
                    for (k, &t) in near.iter().enumerate() {
                        hits[found] = k as u32;
                        found += usize::from(t != s && d2[k] < reach * reach);
                    }
                    let w: f64 = hits[..found]
                        .iter()
                        .map(|&k| weight(d2[k as usize].sqrt()))
                        .sum();
                    for h in &mut hits[..found] {
                        *h = near[*h as usize];
                    }
                    lists.extend_from_slice(&hits[..found]);
                    counts.push(found as u32);
                    weights.push(w);
                }
            }
            Some((counts, lists, weights))
        })
        .collect::<Option<Vec<_>>>()?;
    let total: usize = parts.iter().map(|p| p.1.len()).sum();
    let mut offsets = Vec::with_capacity(grid.order.len() + 1);
    let mut lists = Vec::with_capacity(total);
    let mut weights = Vec::with_capacity(grid.order.len());
    offsets.push(0u32);
    for (k, (counts, part, w)) in parts.into_iter().enumerate() {
        if k % 64 == 63 && cancel() {
            return None;
        }
        for n in counts {
            offsets.push(offsets.last().copied().unwrap_or(0) + n);
        }
        lists.extend_from_slice(&part);
        weights.extend_from_slice(&w);
    }
    Some((offsets, lists, weights))
}

/// Indices (ascending) of `keep` of `points` chosen by sample elimination:
/// the point with the most weight from neighbours closer than `2 r` goes
/// first, where `r` is the spacing of `keep` points packed in `measure`
/// (a volume when `dims` is 3, an area when 2). `cancel` is polled per
/// few hundred cells while neighbours are gathered and per 4096 steps of
/// removal.
pub fn eliminate(
    points: &[Vec3],
    keep: usize,
    measure: f64,
    dims: u32,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<usize>, ScatterError> {
    let n = points.len();
    if keep >= n {
        return Ok((0..n).collect());
    }
    let r_max = if dims == 3 {
        (measure / (4.0 * std::f64::consts::SQRT_2 * keep as f64)).cbrt()
    } else {
        (measure / (2.0 * 3f64.sqrt() * keep as f64)).sqrt()
    };
    let reach = (2.0 * r_max) as f32;
    if !(reach > 0.0 && reach.is_finite()) || points.iter().any(|p| !p.is_finite()) {
        return Ok((0..keep).collect());
    }
    let grid = CellGrid::build(points, reach, cancel).ok_or(ScatterError::Cancelled)?;
    let (offsets, lists, mut w) =
        neighbourhoods(&grid, reach, cancel).ok_or(ScatterError::Cancelled)?;
    let largest = w.iter().copied().fold(0.0f64, f64::max);
    let per_weight = if largest > 0.0 {
        (BUCKETS - 1) as f64 / largest
    } else {
        0.0
    };
    let bucket = |x: f64| -> usize { ((x * per_weight) as usize).min(BUCKETS - 1) };
    let mut queue: Vec<Vec<u32>> = vec![Vec::new(); BUCKETS];
    for (s, &x) in w.iter().enumerate() {
        queue[bucket(x)].push(s as u32);
    }
    let mut alive = vec![true; n];
    let mut left = n;
    let mut top = BUCKETS - 1;
    let weight = falloff(reach);
    let mut pops = 0u32;
    while left > keep {
        pops = pops.wrapping_add(1);
        if pops.is_multiple_of(4096) && cancel() {
            return Err(ScatterError::Cancelled);
        }
        let Some(s) = queue[top].pop() else {
            if top == 0 {
                break;
            }
            top -= 1;
            continue;
        };
        let s = s as usize;
        if !alive[s] {
            continue;
        }
        // Weights only fall and entries move down lazily, when popped.
        let now = bucket(w[s]);
        if now < top {
            queue[now].push(s as u32);
            continue;
        }
        alive[s] = false;
        left -= 1;
        let p = grid.sorted[s];
        for &t in &lists[offsets[s] as usize..offsets[s + 1] as usize] {
            let t = t as usize;
            if alive[t] {
                w[t] -= weight(p.distance(grid.sorted[t]));
            }
        }
    }
    let mut kept: Vec<usize> = (0..n)
        .filter(|&s| alive[s])
        .map(|s| grid.order[s] as usize)
        .collect();
    kept.sort_unstable();
    Ok(kept)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// Seeded candidates on the unit sphere's surface.
    fn on_sphere(n: usize, seed: u64) -> Vec<Vec3> {
        use geode_geo::random::unit;
        (0..n as u64)
            .map(|i| {
                let z = 2.0 * unit(seed, i, 0) - 1.0;
                let a = std::f32::consts::TAU * unit(seed, i, 1);
                let r = (1.0 - z * z).max(0.0).sqrt();
                Vec3::new(r * a.cos(), r * a.sin(), z)
            })
            .collect()
    }

    #[test]
    fn keeps_the_exact_count_with_no_close_pairs_left() {
        let cands = on_sphere(50_000, 3);
        let area = 4.0 * std::f64::consts::PI;
        let kept = eliminate(&cands, 10_000, area, 2, &|| false).unwrap();
        assert_eq!(kept.len(), 10_000);
        assert!(kept.windows(2).all(|w| w[0] < w[1]), "ascending, distinct");
        // Hexagonal packing of 10,000 points on the sphere is ~0.038 apart;
        // elimination keeps them at least 0.5 of that (random: ~0.0005).
        let pts: Vec<Vec3> = kept.iter().map(|&i| cands[i]).collect();
        let grid = CellGrid::build(&pts, 0.02, &|| false).unwrap();
        let mut near = Vec::new();
        let mut closest = f32::MAX;
        for c in 0..grid.cells.len() - 1 {
            grid.around(c, &mut near);
            for s in grid.cells[c].1..grid.cells[c + 1].1 {
                for &t in &near {
                    if t != s {
                        let d = grid.sorted[s as usize].distance(grid.sorted[t as usize]);
                        closest = closest.min(d);
                    }
                }
            }
        }
        assert!(closest > 0.019, "closest pair {closest}");
    }

    #[test]
    fn the_same_on_any_thread_count() {
        let cands = on_sphere(40_000, 9);
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| eliminate(&cands, 8_000, 4.0 * std::f64::consts::PI, 2, &|| false))
                .unwrap()
        };
        let one = run(1);
        assert_eq!(one, run(3));
        assert_eq!(one, run(4));
    }

    #[test]
    fn stops_when_cancelled_while_gathering_or_removing() {
        let cands = on_sphere(200_000, 5);
        for after in [3, 40, 200] {
            let polls = AtomicUsize::new(0);
            let cancel = || polls.fetch_add(1, Ordering::Relaxed) >= after;
            let r = eliminate(&cands, 40_000, 4.0 * std::f64::consts::PI, 2, &cancel);
            assert_eq!(r, Err(ScatterError::Cancelled), "after {after} polls");
        }
    }

    #[test]
    fn degenerate_inputs_keep_a_prefix_or_everything() {
        let cands = on_sphere(100, 1);
        assert_eq!(
            eliminate(&cands, 200, 1.0, 2, &|| false).unwrap().len(),
            100
        );
        assert_eq!(
            eliminate(&cands, 10, 0.0, 2, &|| false).unwrap(),
            (0..10).collect::<Vec<_>>()
        );
        let mut bad = cands.clone();
        bad[7] = Vec3::NAN;
        assert_eq!(eliminate(&bad, 10, 1.0, 2, &|| false).unwrap().len(), 10);
    }
}
