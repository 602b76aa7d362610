//! Unit tests only: the global allocator of the library's test build, which
//! counts the bytes each thread holds, so that a test can compare a memory
//! estimate with what a computation really allocates
//! ([`peak_above_start`]). The counts are per thread: a computation measured
//! this way must allocate and free on the calling thread (no rayon tasks).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// The system allocator, counting.
struct Meter;

thread_local! {
    /// Bytes this thread holds now, and the most since the last reset.
    static HELD: Cell<(isize, isize)> = const { Cell::new((0, 0)) };
}

fn add(bytes: isize) {
    // A thread being torn down has no counters left: nothing to measure.
    let _ = HELD.try_with(|held| {
        let (now, peak) = held.get();
        held.set((now + bytes, peak.max(now + bytes)));
    });
}

// SAFETY: every call is forwarded unchanged to the system allocator; the
// counting touches only a thread-local cell, which does not allocate.
unsafe impl GlobalAlloc for Meter {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        add(layout.size() as isize);
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        add(layout.size() as isize);
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        add(-(layout.size() as isize));
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        add(new_size as isize - layout.size() as isize);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static METER: Meter = Meter;

/// Runs `f` and returns its result, the most bytes the calling thread held
/// during it beyond what it held before, and those it still holds after.
pub(crate) fn peak_above_start<R>(f: impl FnOnce() -> R) -> (R, usize, usize) {
    let start = HELD.with(|held| {
        let (now, _) = held.get();
        held.set((now, now));
        now
    });
    let result = f();
    let (now, peak) = HELD.with(Cell::get);
    (
        result,
        (peak - start) as usize,
        (now - start).max(0) as usize,
    )
}
