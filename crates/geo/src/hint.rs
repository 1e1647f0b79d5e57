//! Cache hints for kernels whose loops wait on memory rather than
//! arithmetic: the one place outside the allocator with `unsafe`, because a
//! prefetch is an intrinsic the compiler cannot prove harmless.

/// Asks the processor to bring the cache line at `at` close; results never
/// depend on it, and any address is allowed (a prefetch never faults).
/// Worth it only where the next few addresses are known well ahead of their
/// use and each would otherwise miss every cache (measured: sample
/// elimination's removal loop at 5M candidates, 4.6 s without, 1.1 s with).
#[inline(always)]
pub fn prefetch<T>(at: *const T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch never faults, reads nothing the program sees and
    // changes no memory, whatever the address.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        _mm_prefetch::<_MM_HINT_T0>(at.cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = at;
}
