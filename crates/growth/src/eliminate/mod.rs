//! Sample elimination (Yuksel 2015, "Sample Elimination for Generating
//! Poisson Disk Sample Sets") at millions of candidates: candidates sorted
//! into a grid of cells one neighbourhood radius wide (`grid`), every
//! candidate's neighbour list and crowding weight built once in parallel
//! (here), then the most crowded removed one at a time (`removal`).

mod grid;
mod removal;

use geode_geo::glam::Vec3;
use rayon::prelude::*;

use self::grid::CellGrid;
use self::removal::{remove_most_crowded, Slot, REMOVED, TILES};
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

/// Cells a parallel task gathers neighbours for.
const CELLS_PER_TASK: usize = 1024;

/// Bytes elimination takes per candidate, for a memory budget: its
/// neighbour list (about 18 entries on a surface and 29 in a volume at five
/// candidates per kept point; 40 allowed) and its record, position, order,
/// sort key and queue entry.
pub const BYTES_PER_CANDIDATE: f64 = 40.0 * 4.0 + 64.0;

/// Every candidate's record (cell order) with its crowding weight, and the
/// neighbours closer than `reach`: one list per task of cells, which the
/// records index by `part` and `first` (joining them would copy hundreds of
/// megabytes); `None` when cancelled.
fn neighbourhoods(
    grid: &CellGrid,
    reach: f32,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Option<(Vec<Slot>, Vec<Vec<u32>>)> {
    let cell_count = grid.cell_count();
    let tasks: Vec<std::ops::Range<usize>> = (0..cell_count)
        .step_by(CELLS_PER_TASK)
        .map(|c| c..(c + CELLS_PER_TASK).min(cell_count))
        .collect();
    let mut slots = vec![Slot::default(); grid.sorted.len()];
    let mut places = Vec::with_capacity(tasks.len());
    let mut rest = slots.as_mut_slice();
    for cells in &tasks {
        let members = grid.cells[cells.end].1 - grid.cells[cells.start].1;
        let (here, tail) = rest.split_at_mut(members as usize);
        places.push(here);
        rest = tail;
    }
    let lists = tasks
        .into_par_iter()
        .zip(places)
        .enumerate()
        .map(|(part, (cells, place))| {
            if cancel() {
                return None;
            }
            Some(gather(grid, cells, reach, part as u32, place))
        })
        .collect::<Option<Vec<_>>>()?;
    Some((slots, lists))
}

/// The records of the candidates in `cells`, written to `slots`, and their
/// neighbour lists, returned.
fn gather(
    grid: &CellGrid,
    cells: std::ops::Range<usize>,
    reach: f32,
    part: u32,
    slots: &mut [Slot],
) -> Vec<u32> {
    let weight = falloff(reach);
    let mut lists = Vec::with_capacity(slots.len() * 20);
    let mut slots = slots.iter_mut();
    let mut sweep = grid.sweep_from(cells.start);
    let (mut near, mut hits) = (Vec::new(), Vec::new());
    let (mut xs, mut ys, mut zs, mut d2) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for c in cells {
        near.clear();
        let runs = sweep.around(c);
        // Where the cell's own row begins among the neighbours, to find
        // each candidate itself there.
        let before_own_row = near_count(&runs[..4]);
        let own_row = runs[4].start as usize;
        for run in runs {
            near.extend(run);
        }
        // The 27 cells' points side by side, coordinates apart, so the
        // distance tests run as plain vector arithmetic.
        for (axis, column) in [&mut xs, &mut ys, &mut zs].into_iter().enumerate() {
            column.clear();
            column.extend(near.iter().map(|&t| grid.sorted[t as usize][axis]));
        }
        d2.resize(near.len(), 0.0);
        hits.resize(near.len(), 0);
        for (s, slot) in grid.members(c).zip(&mut slots) {
            let p = grid.sorted[s];
            for (((d, x), y), z) in d2.iter_mut().zip(&xs).zip(&ys).zip(&zs) {
                *d = (x - p.x) * (x - p.x) + (y - p.y) * (y - p.y) + (z - p.z) * (z - p.z);
            }
            d2[before_own_row + s - own_row] = f32::INFINITY;
            // Branch-free gathering: most of the 27 cells' points lie
            // beyond reach, unpredictably.
            let mut found = 0;
            for (k, &d) in d2.iter().enumerate() {
                hits[found] = k as u32;
                found += usize::from(d < reach * reach);
            }
            let w: f64 = hits[..found]
                .iter()
                .map(|&k| weight(d2[k as usize].sqrt()))
                .sum();
            *slot = Slot {
                at: p,
                part,
                first: lists.len() as u32,
                weight: w,
                count: found as u32,
            };
            lists.extend(hits[..found].iter().map(|&k| near[k as usize]));
        }
    }
    lists
}

/// Candidates in `runs`.
fn near_count(runs: &[std::ops::Range<u32>]) -> usize {
    runs.iter().map(|r| r.len()).sum()
}

/// Indices (ascending) of `keep` of `points` chosen by sample elimination:
/// the point with the most weight from neighbours closer than `2 r` goes
/// first, where `r` is the spacing of `keep` points packed in `measure`
/// (a volume when `dims` is 3, an area when 2). `cancel` is polled while
/// the grid is sorted, per task of cells while neighbours are gathered and
/// per 4096 steps of removal.
pub fn eliminate(
    points: &[Vec3],
    keep: usize,
    measure: f64,
    dims: u32,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<usize>, ScatterError> {
    eliminate_in_tiles(points, keep, measure, dims, &TILES, cancel)
}

/// `eliminate` with the removal's passes over tiles of the given sizes.
fn eliminate_in_tiles(
    points: &[Vec3],
    keep: usize,
    measure: f64,
    dims: u32,
    tiles: &[usize],
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
    let (mut slots, lists) = neighbourhoods(&grid, reach, cancel).ok_or(ScatterError::Cancelled)?;
    remove_most_crowded(&mut slots, &lists, n - keep, reach, tiles, cancel)?;
    let mut kept: Vec<usize> = (0..n)
        .filter(|&s| slots[s].weight != REMOVED)
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

    /// Calls `f` for every pair (cell order) the grid's sweep offers.
    fn for_pairs_within(grid: &CellGrid, mut f: impl FnMut(usize, usize)) {
        let mut sweep = grid.sweep_from(0);
        for c in 0..grid.cell_count() {
            for run in sweep.around(c) {
                for t in run {
                    for s in grid.members(c) {
                        if s != t as usize {
                            f(s, t as usize);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn the_sweep_finds_every_pair_within_reach() {
        // A sphere's surface, a dense clump and a far outlier: cells empty,
        // full and alone, rows that end and begin.
        let mut pts = on_sphere(3_000, 4);
        pts.extend(on_sphere(500, 6).iter().map(|p| *p * 0.01 + Vec3::X * 0.5));
        pts.push(Vec3::new(40.0, -3.0, 7.0));
        for reach in [0.05f32, 0.2] {
            let grid = CellGrid::build(&pts, reach, &|| false).unwrap();
            let mut found = std::collections::BTreeSet::new();
            for_pairs_within(&grid, |s, t| {
                if grid.sorted[s].distance(grid.sorted[t]) < reach {
                    found.insert((grid.order[s], grid.order[t]));
                }
            });
            let mut expected = std::collections::BTreeSet::new();
            for (i, p) in pts.iter().enumerate() {
                for (j, q) in pts.iter().enumerate() {
                    if i != j && p.distance(*q) < reach {
                        expected.insert((i as u32, j as u32));
                    }
                }
            }
            assert!(!expected.is_empty());
            assert_eq!(found, expected, "reach {reach}");
        }
    }

    #[test]
    fn neighbour_lists_are_ascending_and_exact() {
        // The removal's tiles test a list against a range by its ends.
        let cands = on_sphere(20_000, 8);
        let reach = 0.05;
        let grid = CellGrid::build(&cands, reach, &|| false).unwrap();
        let (slots, lists) = neighbourhoods(&grid, reach, &|| false).unwrap();
        let mut total = 0;
        for (s, slot) in slots.iter().enumerate() {
            let first = slot.first as usize;
            let list = &lists[slot.part as usize][first..first + slot.count as usize];
            assert!(list.windows(2).all(|w| w[0] < w[1]), "candidate {s}");
            assert!(list.iter().all(|&t| t as usize != s));
            assert!(list
                .iter()
                .all(|&t| grid.sorted[s].distance(grid.sorted[t as usize]) < reach));
            total += list.len();
        }
        let mut pairs = 0;
        for_pairs_within(&grid, |s, t| {
            pairs += usize::from(grid.sorted[s].distance(grid.sorted[t]) < reach);
        });
        assert_eq!(total, pairs);
    }

    /// Each point's distance to its nearest other point, for points no
    /// farther apart than `within`.
    fn nearest(points: &[Vec3], within: f32) -> Vec<f32> {
        let grid = CellGrid::build(points, within, &|| false).unwrap();
        let mut nearest = vec![f32::MAX; points.len()];
        for_pairs_within(&grid, |s, t| {
            let d = grid.sorted[s].distance(grid.sorted[t]);
            let at = grid.order[s] as usize;
            nearest[at] = nearest[at].min(d);
        });
        nearest
    }

    #[test]
    fn tiles_keep_points_as_evenly_spread_as_one_pass() {
        // On a surface (120k candidates: passes over tiles of 8k and 32k,
        // seams included) and in a volume (40k: the same).
        let sphere = on_sphere(120_000, 11);
        let ball: Vec<Vec3> = on_sphere(60_000, 12)
            .iter()
            .enumerate()
            .map(|(i, p)| *p * geode_geo::random::unit(13, i as u64, 0).cbrt())
            .take(40_000)
            .collect();
        let area = 4.0 * std::f64::consts::PI;
        let volume = area / 3.0;
        for (cands, keep, measure, dims) in [(&sphere, 24_000, area, 2), (&ball, 8_000, volume, 3)]
        {
            let spread = |tiles: &[usize]| {
                let kept =
                    eliminate_in_tiles(cands, keep, measure, dims, tiles, &|| false).unwrap();
                assert_eq!(kept.len(), keep);
                let pts: Vec<Vec3> = kept.iter().map(|&i| cands[i]).collect();
                let nearest = nearest(&pts, 0.2);
                let mean = nearest.iter().map(|&d| d as f64).sum::<f64>() / nearest.len() as f64;
                (nearest.iter().copied().fold(f32::MAX, f32::min), mean)
            };
            let (one_min, one_mean) = spread(&[]);
            let (tiled_min, tiled_mean) = spread(&TILES);
            assert!(
                tiled_min >= 0.97 * one_min,
                "{dims}D: closest {tiled_min} against {one_min}"
            );
            assert!(
                tiled_mean >= 0.995 * one_mean,
                "{dims}D: mean {tiled_mean} against {one_mean}"
            );
            // Sample elimination's spacing: mean nearest neighbour ~0.75 of
            // the reach, on a surface and in a volume (random: ~0.25).
            let reach = if dims == 2 {
                2.0 * (measure / (2.0 * 3f64.sqrt() * keep as f64)).sqrt()
            } else {
                2.0 * (measure / (4.0 * std::f64::consts::SQRT_2 * keep as f64)).cbrt()
            };
            assert!(
                tiled_mean > 0.72 * reach,
                "{dims}D: {tiled_mean} of reach {reach}"
            );
        }
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
        let closest = nearest(&pts, 0.02).into_iter().fold(f32::MAX, f32::min);
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
