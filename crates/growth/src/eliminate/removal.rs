//! Sample elimination's removal: the most crowded candidate goes first,
//! from a bucket queue over the weights, with the records of the next pops
//! fetched ahead because the loop waits on memory, not arithmetic. Most
//! removals run in tiles of the cell order in parallel (a tile's interior
//! candidates only touch its own records), the rest in one pass over all.

use geode_geo::glam::Vec3;
use geode_geo::hint::prefetch;
use rayon::prelude::*;

use super::falloff;
use crate::scatter::ScatterError;

/// A candidate as the removal loop reads it: position, neighbour list and
/// weight in one 32-byte record, so each pop and each neighbour update
/// touches one cache line instead of one per column.
#[derive(Clone, Copy, Default)]
#[repr(C, align(32))]
pub(super) struct Slot {
    pub at: Vec3,
    /// Its neighbours: `count` entries from `first` of list `part`.
    pub part: u32,
    pub first: u32,
    pub count: u32,
    pub weight: f64,
}

impl Slot {
    /// Its neighbours (indices in cell order), if `lists` holds them.
    fn neighbours<'l>(&self, lists: &'l [Vec<u32>]) -> Option<&'l [u32]> {
        let first = self.first as usize;
        lists
            .get(self.part as usize)?
            .get(first..first + self.count as usize)
    }
}

/// A removed candidate's weight: subtracting from it changes nothing, so
/// neighbour updates need no liveness test.
pub(super) const REMOVED: f64 = f64::NEG_INFINITY;

/// Buckets of a removal queue: 1/65536 of the largest weight wide. The
/// order within one is by position, deterministic for any thread count.
/// Coarser buckets are faster (fewer entries move down) but spread the
/// points worse: at 5M candidates the mean nearest-neighbour distance is
/// 0.748 of the reach with 65536 buckets, 0.743 with 16384, 0.714 with 4096.
const BUCKETS: usize = 1 << 16;

/// Candidates per tile, a pass per size: tiles follow from the count alone,
/// never from the threads, so the result is the same on any machine. Small
/// tiles fit the caches but have thin interiors in row-major cell order;
/// each larger pass takes the seams of the smaller.
pub(super) const TILES: [usize; 3] = [1 << 13, 1 << 15, 1 << 18];

/// Share of the removals the tiles make in their interiors; the rest run
/// over all candidates, so those next to a seam (frozen while the tiles
/// run) thin out too. The kept points' nearest neighbours stay as far
/// apart as in one pass over all (mean 0.747 of the reach against 0.748 on
/// a surface, 0.745 against 0.747 in a volume: the tiles test); 0.95 and
/// 0.99 measured 0.746 and 0.743 at 5M candidates.
const TILED_SHARE: f64 = 0.85;

/// How far ahead of the current pop (in entries of its bucket) a record is
/// fetched, its neighbour list, and its neighbours' records (only for
/// entries whose weight says they will be removed rather than moved down).
/// Measured at 5M candidates in one pass: none 4.6 s; records and lists
/// only 2.4 s; all three ~1.1 s.
const RECORD_AHEAD: usize = 16;
const LIST_AHEAD: usize = 8;
const NEIGHBOURS_AHEAD: usize = 4;

/// Pops between polls of `cancel`.
const PER_POLL: u32 = 4096;

/// Removes `remove` candidates, the most crowded first, marking them
/// `REMOVED`. Tiles first, a pass per size in `tiles`, each tile in
/// parallel: the tile's interior (candidates whose neighbours all lie in
/// the tile, so a tile writes only its own records) is brought down to the
/// share alive that `TILED_SHARE` of the removals would leave everywhere;
/// then one pass over every candidate left makes the rest of the removals.
/// Each pass removes the most crowded of its candidates first.
pub(super) fn remove_most_crowded(
    slots: &mut [Slot],
    lists: &[Vec<u32>],
    remove: usize,
    reach: f32,
    tiles: &[usize],
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<(), ScatterError> {
    let largest = slots.iter().map(|s| s.weight).fold(0.0f64, f64::max);
    let rule = Rule::new(largest, reach);
    let n = slots.len();
    let alive_share = 1.0 - remove as f64 * TILED_SHARE / n as f64;
    let mut removed = 0;
    for size in tiles.iter().copied().filter(|&size| n > size) {
        removed += slots
            .par_chunks_mut(size)
            .enumerate()
            .map_init(Buckets::new, |buckets, (tile, here)| {
                let base = (tile * size) as u32;
                let span = base..base + here.len() as u32;
                // The interior's size, and its candidates still alive.
                let mut interior = 0;
                let mut alive = Vec::new();
                for s in 0..here.len() as u32 {
                    let slot = &here[s as usize];
                    if slot
                        .neighbours(lists)
                        .is_some_and(|list| within(list, &span))
                    {
                        interior += 1;
                        if slot.weight != REMOVED {
                            alive.push(s);
                        }
                    }
                }
                let keep = (interior as f64 * alive_share).ceil() as usize;
                let share = alive.len().saturating_sub(keep);
                rule.remove(buckets, here, base, &alive, lists, share, cancel)
            })
            .try_reduce(|| 0, |a, b| Ok(a + b))?;
    }
    let left: Vec<u32> = (0..n as u32)
        .filter(|&s| slots[s as usize].weight != REMOVED)
        .collect();
    let mut buckets = Buckets::new();
    rule.remove(
        &mut buckets,
        slots,
        0,
        &left,
        lists,
        remove - removed,
        cancel,
    )?;
    Ok(())
}

/// Whether every entry of `list` (ascending, as neighbour lists are: the
/// rows around a cell come in cell order) lies in `span`.
fn within(list: &[u32], span: &std::ops::Range<u32>) -> bool {
    list.first().is_none_or(|t| span.contains(t)) && list.last().is_none_or(|t| span.contains(t))
}

/// The rule of every removal pass: weights to buckets, and a neighbour's
/// weight.
struct Rule<W> {
    per_weight: f64,
    weight: W,
}

impl Rule<()> {
    fn new(largest: f64, reach: f32) -> Rule<impl Fn(f32) -> f64 + Sync> {
        let per_weight = if largest > 0.0 {
            (BUCKETS - 1) as f64 / largest
        } else {
            0.0
        };
        Rule {
            per_weight,
            weight: falloff(reach),
        }
    }
}

impl<W: Fn(f32) -> f64> Rule<W> {
    fn bucket(&self, x: f64) -> usize {
        ((x * self.per_weight) as usize).min(BUCKETS - 1)
    }

    /// Removes up to `remove` of `entries` (indices into `slots`, which
    /// starts at candidate `base`; every neighbour of an entry lies in
    /// `slots`) and returns how many. Weights only fall, so the highest
    /// non-empty bucket only moves down and an entry whose weight fell below
    /// its bucket moves down lazily, when popped; every entry is queued once
    /// at any time. Within a bucket the order is last in, first out.
    #[allow(clippy::too_many_arguments)]
    fn remove(
        &self,
        buckets: &mut Buckets,
        slots: &mut [Slot],
        base: u32,
        entries: &[u32],
        lists: &[Vec<u32>],
        remove: usize,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<usize, ScatterError> {
        let highest = buckets.fill(entries, |s| self.bucket(slots[s as usize].weight));
        let queue = &mut buckets.queue;
        let local = |t: u32| t.wrapping_sub(base) as usize;
        let ahead = |entries: &[u32], k: usize| {
            entries
                .len()
                .checked_sub(1 + k)
                .map(|at| entries[at] as usize)
        };
        let (mut removed, mut top, mut pops) = (0, highest, 0u32);
        while removed < remove {
            pops = pops.wrapping_add(1);
            if pops.is_multiple_of(PER_POLL) && cancel() {
                buckets.clear(highest);
                return Err(ScatterError::Cancelled);
            }
            let entries = &queue[top];
            let Some(&s) = entries.last() else {
                if top == 0 {
                    break;
                }
                top -= 1;
                continue;
            };
            // The next pops of this bucket are known: fetch what they read.
            if let Some(t) = ahead(entries, RECORD_AHEAD) {
                prefetch(&slots[t]);
            }
            if let Some(t) = ahead(entries, LIST_AHEAD) {
                let slot = &slots[t];
                if self.bucket(slot.weight) >= top {
                    if let Some(list) = slot.neighbours(lists) {
                        prefetch(list.as_ptr());
                    }
                }
            }
            if let Some(t) = ahead(entries, NEIGHBOURS_AHEAD) {
                let slot = &slots[t];
                if self.bucket(slot.weight) >= top {
                    for &n in slot.neighbours(lists).unwrap_or(&[]) {
                        prefetch(slots.as_ptr().wrapping_add(local(n)));
                    }
                }
            }
            queue[top].pop();
            let slot = slots[s as usize];
            let now = self.bucket(slot.weight);
            if now < top {
                queue[now].push(s);
                continue;
            }
            slots[s as usize].weight = REMOVED;
            removed += 1;
            for &t in slot.neighbours(lists).unwrap_or(&[]) {
                let neighbour = &mut slots[local(t)];
                neighbour.weight -= (self.weight)(slot.at.distance(neighbour.at));
            }
        }
        buckets.clear(highest);
        Ok(removed)
    }
}

/// A bucket queue's storage, kept from tile to tile (a fresh one per tile
/// allocated and zeroed megabytes each time).
struct Buckets {
    queue: Vec<Vec<u32>>,
    sizes: Vec<u32>,
    marks: Vec<u16>,
}

impl Buckets {
    fn new() -> Buckets {
        Buckets {
            queue: vec![Vec::new(); BUCKETS],
            sizes: vec![0; BUCKETS],
            marks: Vec::new(),
        }
    }

    /// Puts every entry in its bucket, in the order given, each bucket
    /// grown once to its size (a push per entry into growing buckets
    /// reallocated them millions of times); returns the highest bucket.
    fn fill(&mut self, entries: &[u32], bucket: impl Fn(u32) -> usize) -> usize {
        self.marks.clear();
        self.marks.extend(entries.iter().map(|&s| bucket(s) as u16));
        self.sizes.fill(0);
        for &b in &self.marks {
            self.sizes[b as usize] += 1;
        }
        for (queue, &size) in self.queue.iter_mut().zip(&self.sizes) {
            queue.reserve(size as usize);
        }
        for (&s, &b) in entries.iter().zip(&self.marks) {
            self.queue[b as usize].push(s);
        }
        self.marks.iter().map(|&b| b as usize).max().unwrap_or(0)
    }

    /// Empties buckets up to `highest`, the only ones a pass fills.
    fn clear(&mut self, highest: usize) {
        self.queue[..=highest].iter_mut().for_each(Vec::clear);
    }
}
