//! The candidates of sample elimination sorted into cells one neighbourhood
//! wide, in row-major order, so that the 27 cells around any cell are nine
//! runs of three consecutive cells and a sweep over the cells finds them
//! with nine cursors that only move forward (no hashing).

use std::ops::Range;

use geode_geo::glam::Vec3;
use rayon::prelude::*;

/// Cells per axis at most: three axes' keys fit one `u64` below the end
/// marker.
const AXIS_CELLS: u64 = 1 << 21;

/// Elements a radix pass moves between polls of `cancel`.
const PER_POLL: usize = 1 << 20;

/// Candidates sorted by cell.
pub(super) struct CellGrid {
    /// Candidate indices in cell order.
    pub order: Vec<u32>,
    /// Positions in cell order.
    pub sorted: Vec<Vec3>,
    /// Each non-empty cell's key and first position in `order`, ascending,
    /// then an end marker with key `u64::MAX`.
    pub cells: Vec<(u64, u32)>,
    /// Key offset from a cell to the first (x - 1) cell of each of the nine
    /// rows (y and z within one) around it.
    rows: [i64; 9],
}

impl CellGrid {
    /// Cells at least `reach` wide (wider where the points span more than
    /// 2^21 - 3 of them on an axis), so every neighbour lies in the 27
    /// cells around a point's own; one empty cell of margin on every side,
    /// so those 27 never leave the grid or wrap into another row.
    pub fn build(
        points: &[Vec3],
        reach: f32,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Option<CellGrid> {
        let (lo, hi) = points
            .par_iter()
            .fold(
                || (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
                |(a, b), p| (a.min(*p), b.max(*p)),
            )
            .reduce(
                || (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
                |(a, b), (c, d)| (a.min(c), b.max(d)),
            );
        let span = (hi - lo).max_element().max(0.0);
        let side = reach.max(span / (AXIS_CELLS - 3) as f32);
        let origin = lo - Vec3::splat(side);
        let extent = ((hi - origin) / side).floor();
        let dims = [extent.x, extent.y, extent.z].map(|e| (e.max(0.0) as u64 + 2).min(AXIS_CELLS));
        let key_of = |p: &Vec3| -> u64 {
            let c = ((*p - origin) / side).floor();
            let at = |v: f32, n: u64| (v.max(1.0) as u64).min(n - 2);
            (at(c.z, dims[2]) * dims[1] + at(c.y, dims[1])) * dims[0] + at(c.x, dims[0])
        };
        let keyed: Vec<(u64, u32)> = points
            .par_iter()
            .enumerate()
            .map(|(i, p)| (key_of(p), i as u32))
            .collect();
        let keyed = radix_sort(keyed, cancel)?;
        let order: Vec<u32> = keyed.par_iter().map(|k| k.1).collect();
        let sorted: Vec<Vec3> = order.par_iter().map(|&i| points[i as usize]).collect();
        let mut cells: Vec<(u64, u32)> = Vec::new();
        for (s, k) in keyed.iter().enumerate() {
            if s % PER_POLL == PER_POLL - 1 && cancel() {
                return None;
            }
            if cells.last().is_none_or(|c| c.0 != k.0) {
                cells.push((k.0, s as u32));
            }
        }
        cells.push((u64::MAX, points.len() as u32));
        let (nx, ny) = (dims[0] as i64, dims[1] as i64);
        let mut rows = [0i64; 9];
        for (r, row) in rows.iter_mut().enumerate() {
            let (dy, dz) = (r as i64 % 3 - 1, r as i64 / 3 - 1);
            *row = (dz * ny + dy) * nx - 1;
        }
        Some(CellGrid {
            order,
            sorted,
            cells,
            rows,
        })
    }

    /// Non-empty cells, not counting the end marker.
    pub fn cell_count(&self) -> usize {
        self.cells.len() - 1
    }

    /// Positions (cell order) of the candidates in cell `c`.
    pub fn members(&self, c: usize) -> Range<usize> {
        self.cells[c].1 as usize..self.cells[c + 1].1 as usize
    }

    /// A sweep of cells from `c` upwards: its cursors start at the first
    /// cell of each row around `c`.
    pub fn sweep_from(&self, c: usize) -> Sweep<'_> {
        let key = self.cells[c].0;
        let cursors = self.rows.map(|row| {
            self.cells
                .partition_point(|cell| cell.0 < key.wrapping_add_signed(row))
        });
        Sweep {
            grid: self,
            cursors,
        }
    }
}

/// Nine cursors over the cells, one per row around the current cell.
pub(super) struct Sweep<'g> {
    grid: &'g CellGrid,
    cursors: [usize; 9],
}

impl Sweep<'_> {
    /// Positions (cell order) of the candidates in the 27 cells around
    /// cell `c`, as nine runs, one per row. Cells must come in ascending
    /// order, each at or after the one the sweep started from.
    pub fn around(&mut self, c: usize) -> [Range<u32>; 9] {
        let cells = &self.grid.cells;
        let key = cells[c].0;
        std::array::from_fn(|r| {
            let first = key.wrapping_add_signed(self.grid.rows[r]);
            let cursor = &mut self.cursors[r];
            while cells[*cursor].0 < first {
                *cursor += 1;
            }
            let mut end = *cursor;
            while cells[end].0 <= first + 2 {
                end += 1;
            }
            cells[*cursor].1..cells[end].1
        })
    }
}

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
