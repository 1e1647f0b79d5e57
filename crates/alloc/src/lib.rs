//! The allocator of geode's binaries: the system allocator, with every
//! block of 2 MiB or more advised to use transparent huge pages. Geometry
//! columns are large and written once right after they are allocated; with
//! 4 KiB pages the first touch of each page faults into the kernel, which
//! bounds a 190 MB column write at ~2.5 GB/s on the reference machine (a
//! transform of 7.9M points with normals: 60 ms, 26-31 ms with huge pages).
//! The same hint glibc gives with `GLIBC_TUNABLES=glibc.malloc.hugetlb=1`,
//! without asking users to set it. Elsewhere than Linux, the system
//! allocator unchanged.
//!
//! Binaries opt in with
//! `#[global_allocator] static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;`.

use std::alloc::{GlobalAlloc, Layout, System};

/// The system allocator with huge pages for large blocks.
pub struct HugePages;

/// A huge page, and the smallest block advised to use them.
const HUGE: usize = 2 << 20;

/// Advises the whole huge pages inside `[p, p + len)`.
#[cfg(target_os = "linux")]
fn advise(p: *mut u8, len: usize) {
    if p.is_null() || len < HUGE {
        return;
    }
    let start = (p as usize).next_multiple_of(HUGE);
    let end = (p as usize).saturating_add(len) / HUGE * HUGE;
    if end > start {
        // SAFETY: the range lies inside a block this process owns; the
        // advice changes how its pages are backed, never their contents.
        unsafe {
            libc::madvise(start as *mut libc::c_void, end - start, libc::MADV_HUGEPAGE);
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise(_: *mut u8, _: usize) {}

// SAFETY: every call is forwarded to the system allocator unchanged; the
// advice only concerns pages of the block just returned.
unsafe impl GlobalAlloc for HugePages {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract is passed on unchanged.
        let p = unsafe { System.alloc(layout) };
        advise(p, layout.size());
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as `alloc`.
        let p = unsafe { System.alloc_zeroed(layout) };
        advise(p, layout.size());
        p
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        // SAFETY: as `alloc`.
        unsafe { System.dealloc(p, layout) }
    }

    unsafe fn realloc(&self, p: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: as `alloc`.
        let q = unsafe { System.realloc(p, layout, new_size) };
        advise(q, new_size);
        q
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_of_every_size_round_trip() {
        for size in [1usize, 64, 4096, HUGE - 1, HUGE, 3 * HUGE + 123] {
            let layout = Layout::from_size_align(size, 16).unwrap();
            // SAFETY: a non-zero layout, freed with the same layout.
            unsafe {
                let p = HugePages.alloc(layout);
                assert!(!p.is_null());
                p.write_bytes(0xAB, size);
                let q = HugePages.realloc(p, layout, size * 2);
                assert!(!q.is_null());
                assert_eq!(*q.add(size - 1), 0xAB);
                HugePages.dealloc(q, Layout::from_size_align(size * 2, 16).unwrap());
                let z = HugePages.alloc_zeroed(layout);
                assert!((0..size).step_by(4093).all(|i| *z.add(i) == 0));
                HugePages.dealloc(z, layout);
            }
        }
    }
}
