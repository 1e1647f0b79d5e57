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

use crate::builtins::Val;
use crate::exec::Frame;

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
        if delta >= 0 {
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

impl Val {
    /// Bytes the value holds on the heap.
    pub fn heap_bytes(&self) -> u64 {
        match self {
            Val::I(_) | Val::F(..) => 0,
            Val::S(s) => s.capacity() as u64,
            Val::AF(v, _) => (v.capacity() * 4) as u64,
            Val::AI(v) => (v.capacity() * 4) as u64,
            Val::AS(v) => strings_bytes(v),
        }
    }
}

/// Bytes a string array holds: its slots and every string's characters.
pub fn strings_bytes(v: &[String]) -> u64 {
    let slots = std::mem::size_of_val(v) as u64;
    slots + v.iter().map(|s| s.capacity() as u64).sum::<u64>()
}

/// Bytes `frame`'s string and array registers hold on the heap.
pub fn frame_bytes(frame: &Frame) -> u64 {
    let strings: u64 = frame.s.iter().map(|s| s.capacity() as u64).sum();
    let floats: u64 = frame.af.iter().map(|v| (v.capacity() * 4) as u64).sum();
    let ints: u64 = frame.ai.iter().map(|v| (v.capacity() * 4) as u64).sum();
    let texts: u64 = frame.as_.iter().map(|v| strings_bytes(v)).sum();
    strings + floats + ints + texts
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
