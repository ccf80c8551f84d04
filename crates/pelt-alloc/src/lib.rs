//! The global allocator: the system allocator, optionally asking Linux for transparent huge
//! pages on large blocks.
//!
//! A bake is dominated by a few large arrays (attributes, indices, topology) that are written
//! once. With 4 KiB pages every first touch of such an array is a page fault. Where THP is set
//! to `madvise` (the Debian default), `madvise(MADV_HUGEPAGE)` on the 2 MiB-aligned middle of
//! each block of at least [`THRESHOLD`] bytes lets the kernel back it with 2 MiB pages: 512
//! times fewer faults. The hint is off by default (`PELT_HUGE_PAGES=1` turns it on): on the
//! project's 2-core VM it made the median bake about 10 % faster but the slow runs much
//! slower (p90/p50 of 20 runs 1.13 to 1.67 against 1.04 to 1.24 without), because each huge page
//! is memory the kernel (and the hypervisor under it) must find and zero in one piece. The
//! steadier choice is the default; the fresh memory a bake touches was cut instead (fins are
//! the topology's own edge list, large inputs are mapped, not read).
//!
//! [`Counting`] wraps it with byte counters (held now, peak) for the tests and the fuzz
//! harness that bound memory by the input's real size.

#![expect(
    unsafe_code,
    reason = "a GlobalAlloc forwarding to System, plus one madvise hint; see the SAFETY notes"
)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Blocks at least this large are advised.
pub const THRESHOLD: usize = 4 << 20;

/// Size and alignment of a transparent huge page on x86-64 and aarch64 (4 KiB base pages).
const HUGE_PAGE: usize = 2 << 20;

/// Whether the hint is given (off unless `PELT_HUGE_PAGES=1`; see [`configure_from_env`]).
static ENABLED: AtomicBool = AtomicBool::new(false);

/// Reads `PELT_HUGE_PAGES`: `1` turns the hint on, `0` off (the default).
pub fn configure_from_env() {
    match std::env::var_os("PELT_HUGE_PAGES") {
        Some(v) if v == "1" => ENABLED.store(true, Ordering::Relaxed),
        Some(v) if v == "0" => ENABLED.store(false, Ordering::Relaxed),
        _ => {}
    }
}

/// Turns the huge-page hint on or off (what `PELT_HUGE_PAGES` does).
pub fn set_huge_pages(on: bool) {
    ENABLED.store(on, Ordering::Relaxed);
}

/// [`System`] plus the huge-page hint.
pub struct HugePageAlloc;

/// The whole 2 MiB pages inside `[start, start + len)`, as (address, length).
pub fn huge_span(start: usize, len: usize) -> Option<(usize, usize)> {
    let first = start.checked_next_multiple_of(HUGE_PAGE)?;
    let end = (start.checked_add(len)? / HUGE_PAGE) * HUGE_PAGE;
    (end > first).then(|| (first, end - first))
}

#[cfg(target_os = "linux")]
fn advise(ptr: *mut u8, len: usize) {
    if ptr.is_null() || len < THRESHOLD || !ENABLED.load(Ordering::Relaxed) {
        return;
    }
    if let Some((start, span)) = huge_span(ptr as usize, len) {
        // SAFETY: [start, start + span) lies inside the block the allocator just returned to us,
        // which nothing else uses yet; MADV_HUGEPAGE changes no contents, only how the kernel
        // backs the pages. The result is ignored: the hint may be refused.
        unsafe {
            libc::madvise(start as *mut libc::c_void, span, libc::MADV_HUGEPAGE);
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise(_ptr: *mut u8, _len: usize) {}

// SAFETY: every call is forwarded to `System` with the caller's arguments; `advise` only hints.
unsafe impl GlobalAlloc for HugePageAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: forwarded with the caller's guarantees.
        let p = unsafe { System.alloc(layout) };
        advise(p, layout.size());
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: forwarded with the caller's guarantees.
        let p = unsafe { System.alloc_zeroed(layout) };
        advise(p, layout.size());
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded with the caller's guarantees.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: forwarded with the caller's guarantees.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        advise(p, new_size);
        p
    }
}

/// [`HugePageAlloc`] that also counts the bytes it holds and the peak since the last
/// [`reset_peak`]: for tests and the fuzz harness, which check that no input makes pelt
/// allocate more than a small multiple of the input's real size.
pub struct Counting;

static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

/// Bytes held now through [`Counting`].
pub fn current() -> usize {
    CURRENT.load(Ordering::Relaxed)
}

/// The most bytes held at once through [`Counting`] since the last [`reset_peak`].
pub fn peak() -> usize {
    PEAK.load(Ordering::Relaxed)
}

/// Starts a new peak measurement from what is held now; returns that.
pub fn reset_peak() -> usize {
    let now = current();
    PEAK.store(now, Ordering::Relaxed);
    now
}

fn grew(by: usize) {
    let now = CURRENT.fetch_add(by, Ordering::Relaxed) + by;
    PEAK.fetch_max(now, Ordering::Relaxed);
}

fn shrank(by: usize) {
    CURRENT.fetch_sub(by, Ordering::Relaxed);
}

// SAFETY: every call is forwarded to `HugePageAlloc` with the caller's arguments; the counters
// are only bookkeeping.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: forwarded with the caller's guarantees.
        let p = unsafe { HugePageAlloc.alloc(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: forwarded with the caller's guarantees.
        let p = unsafe { HugePageAlloc.alloc_zeroed(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded with the caller's guarantees.
        unsafe { HugePageAlloc.dealloc(ptr, layout) };
        shrank(layout.size());
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: forwarded with the caller's guarantees.
        let p = unsafe { HugePageAlloc.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            if new_size >= layout.size() {
                grew(new_size - layout.size());
            } else {
                shrank(layout.size() - new_size);
            }
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[global_allocator]
    static GLOBAL: HugePageAlloc = HugePageAlloc;

    #[test]
    fn span_covers_only_whole_aligned_huge_pages() {
        assert_eq!(huge_span(0, HUGE_PAGE), Some((0, HUGE_PAGE)));
        assert_eq!(huge_span(16, HUGE_PAGE), None);
        // [16, 16 + 3 pages) holds the whole pages [1, 3).
        assert_eq!(
            huge_span(16, 3 * HUGE_PAGE),
            Some((HUGE_PAGE, 2 * HUGE_PAGE))
        );
        assert_eq!(
            huge_span(HUGE_PAGE - 1, 2 * HUGE_PAGE + 2),
            Some((HUGE_PAGE, 2 * HUGE_PAGE))
        );
        assert_eq!(huge_span(usize::MAX - 8, 4), None);
    }

    #[test]
    fn advised_blocks_keep_their_contents() {
        // Runs under the global allocator, with the hint on: large vectors grown, zeroed and
        // copied.
        set_huge_pages(true);
        let mut v: Vec<u64> = (0..(THRESHOLD as u64)).collect();
        v.extend(0..1000);
        let z = vec![0u32; THRESHOLD];
        assert!(z.iter().all(|&x| x == 0));
        assert_eq!(v[THRESHOLD - 1], THRESHOLD as u64 - 1);
        assert_eq!(v[THRESHOLD + 999], 999);
    }
}
