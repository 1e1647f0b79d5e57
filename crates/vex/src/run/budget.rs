//! The wrangle's memory budget: one account per run of the bytes that its
//! registers and queued effects hold, charged before a call allocates, so
//! that an oversized request is refused with its element and line instead
//! of exhausting the machine.
//!
//! Each batch's frame knows what it has charged (`Frame::held`). Calls
//! charge what they add to the destination register; a frame is measured
//! again at loop polls and whenever a request would not fit, so copies the
//! account does not see (register moves, loads) are found before anything
//! is refused for want of room. Effects are charged as they queue and stay
//! charged until the run ends, as they stay in memory until they apply.

use std::sync::atomic::{AtomicU64, Ordering};

use geode_geo::human_bytes;

use super::exec::Frame;
use crate::value::HeapBytes;

/// The bytes a run may hold at once and the bytes it holds.
pub struct Budget {
    limit: u64,
    used: AtomicU64,
}

impl Budget {
    pub fn new(limit: u64) -> Budget {
        Budget {
            limit,
            used: AtomicU64::new(0),
        }
    }

    /// Moves the account by `delta` bytes.
    pub fn charge(&self, delta: i64) {
        // Every batch trues up: most have nothing to say, and the shared
        // counter is a cache line the threads would fight over.
        if delta == 0 {
            return;
        }
        if delta > 0 {
            self.used.fetch_add(delta as u64, Ordering::Relaxed);
        } else {
            // Saturating: an account never goes below zero, even when a
            // frame's measure drops by more than this thread last charged.
            let _ = self
                .used
                .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |u| {
                    Some(u.saturating_sub(delta.unsigned_abs()))
                });
        }
    }

    /// Whether `extra` more bytes fit.
    pub fn fits(&self, extra: u64) -> bool {
        self.used
            .load(Ordering::Relaxed)
            .checked_add(extra)
            .is_some_and(|t| t <= self.limit)
    }

    /// Why `what`, needing `extra` bytes, is refused.
    pub fn refusal(&self, what: &str, extra: u64) -> String {
        let left = self.limit.saturating_sub(self.used.load(Ordering::Relaxed));
        format!(
            "{what} would need {}, more than the {} left of the memory budget of {} (GEODE_MEMORY_MB)",
            human_bytes(extra as f64),
            human_bytes(left as f64),
            human_bytes(self.limit as f64)
        )
    }
}

/// Bytes a register's value holds on the heap: the one rule every measure
/// of the account (a value, a lane, a register, a frame) follows.
/// Bytes a run of register slots holds.
pub fn slots_bytes<T: HeapBytes>(slots: &[T]) -> u64 {
    slots.iter().map(HeapBytes::heap_bytes).sum()
}

/// Bytes `frame`'s string and array registers hold on the heap.
pub fn frame_bytes(frame: &Frame) -> u64 {
    slots_bytes(&frame.s)
        + slots_bytes(&frame.af)
        + slots_bytes(&frame.ai)
        + slots_bytes(&frame.as_)
}

/// Whether `bytes` more fit, once `frame`'s own account is brought up to
/// date if the shared one says no (it may be stale).
pub fn reserve(budget: &Budget, frame: &mut Frame, bytes: u64) -> bool {
    if bytes == 0 || budget.fits(bytes) {
        return true;
    }
    true_up(budget, frame);
    budget.fits(bytes)
}

/// Charges what a write into one of `frame`'s registers changed.
pub fn charge_write(budget: &Budget, frame: &mut Frame, before: u64, after: u64) {
    budget.charge(after as i64 - before as i64);
    frame.held = (frame.held + after).saturating_sub(before);
}

/// Charges the difference between `frame`'s measure and what it last
/// charged; returns the measure.
pub fn true_up(budget: &Budget, frame: &mut Frame) -> u64 {
    let now = frame_bytes(frame);
    budget.charge(now as i64 - frame.held as i64);
    frame.held = now;
    now
}

/// Frees what `frame`'s registers hold once a batch is done with them and
/// takes it off the account: a frame lives on across batches on its
/// thread, and one dropped by the thread pool must leave nothing charged.
pub fn release(budget: &Budget, frame: &mut Frame) {
    /// Below this a frame keeps its registers' capacity for the next batch.
    const KEEP: u64 = 1 << 20;
    if frame_bytes(frame) > KEEP {
        frame.s.iter_mut().for_each(|s| *s = String::new());
        frame.af.iter_mut().for_each(|v| *v = Vec::new());
        frame.ai.iter_mut().for_each(|v| *v = Vec::new());
        frame.as_.iter_mut().for_each(|v| *v = Vec::new());
    }
    budget.charge(-(frame.held as i64));
    frame.held = 0;
}
