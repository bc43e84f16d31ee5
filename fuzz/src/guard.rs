//! Watching one case at a time for the two failures `catch_unwind` cannot see: a
//! memory blow-up and a hang.
//!
//! Memory: [`CountingAlloc`] is a global allocator over the system's that keeps the
//! live byte count of the whole process. [`begin`] sets a ceiling of the live count at
//! the case's start plus the limit; an allocation (or growth) that would pass it is
//! not made: the allocating thread records how much the case tried to hold and then
//! sleeps for good, so the case stops where it blew up (the driver's watchdog sees the
//! record, saves the input, reports and ends the process). Blocking, not failing the
//! allocation: a failed allocation aborts the process through `handle_alloc_error`
//! before anything could be reported, and unwinding out of an allocator is undefined
//! behaviour. The watchdog's own thread is exempt ([`exempt_this_thread`]). The count
//! is of live bytes (what a case holds at once), not of bytes ever allocated, so a
//! long loop that frees as it goes is no blow-up.
//!
//! Time: [`begin`] stamps the case's start and [`end`] clears it; the watchdog reads
//! [`running_for`].

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Bytes live through [`CountingAlloc`].
static LIVE: AtomicUsize = AtomicUsize::new(0);
/// The live count no allocation of a case may pass (`usize::MAX` between cases).
static CEILING: AtomicUsize = AtomicUsize::new(usize::MAX);
/// The live count a blocked allocation would have reached, else 0.
static BLOWN: AtomicUsize = AtomicUsize::new(0);
/// Nanoseconds from [`epoch`] to the running case's start, plus one; 0 between cases.
static STARTED: AtomicU64 = AtomicU64::new(0);

thread_local! {
    static EXEMPT: Cell<bool> = const { Cell::new(false) };
}

/// The instant the guard's clock counts from.
fn epoch() -> Instant {
    static EPOCH: OnceLock<Instant> = OnceLock::new();
    *EPOCH.get_or_init(Instant::now)
}

/// The counting allocator (module doc). Install it in a binary with
/// `#[global_allocator] static A: CountingAlloc = CountingAlloc;`.
pub struct CountingAlloc;

impl CountingAlloc {
    /// Counts `n` more live bytes, or blocks the thread for good when that passes the
    /// ceiling.
    fn admit(n: usize) {
        let live = LIVE.fetch_add(n, Ordering::Relaxed).saturating_add(n);
        if live > CEILING.load(Ordering::Relaxed) && !EXEMPT.with(Cell::get) {
            LIVE.fetch_sub(n, Ordering::Relaxed);
            BLOWN.fetch_max(live, Ordering::SeqCst);
            loop {
                std::thread::sleep(Duration::from_secs(3600));
            }
        }
    }

    fn release(n: usize) {
        LIVE.fetch_sub(n, Ordering::Relaxed);
    }
}

// SAFETY: every call is forwarded to `System` with the same arguments; the counters
// only watch, and a blocked allocation never returns.
unsafe impl GlobalAlloc for CountingAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        Self::admit(layout.size());
        // SAFETY: the caller's contract is passed on unchanged.
        let p = unsafe { System.alloc(layout) };
        if p.is_null() {
            Self::release(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        Self::admit(layout.size());
        // SAFETY: the caller's contract is passed on unchanged.
        let p = unsafe { System.alloc_zeroed(layout) };
        if p.is_null() {
            Self::release(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract is passed on unchanged.
        unsafe { System.dealloc(ptr, layout) };
        Self::release(layout.size());
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let old = layout.size();
        if new_size > old {
            Self::admit(new_size - old);
        }
        // SAFETY: the caller's contract is passed on unchanged.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        match (p.is_null(), new_size > old) {
            (true, true) => Self::release(new_size - old),
            (false, false) => Self::release(old - new_size),
            _ => {}
        }
        p
    }
}

/// Lets the calling thread allocate past the ceiling (the watchdog's).
pub fn exempt_this_thread() {
    EXEMPT.with(|e| e.set(true));
}

/// A case starts: it may hold `limit` bytes more than are live now (when
/// [`CountingAlloc`] is the global allocator; else nothing is counted).
pub fn begin(limit: usize) {
    CEILING.store(LIVE.load(Ordering::Relaxed).saturating_add(limit), Ordering::SeqCst);
    STARTED.store(epoch().elapsed().as_nanos() as u64 + 1, Ordering::SeqCst);
}

/// The case has ended.
pub fn end() {
    STARTED.store(0, Ordering::SeqCst);
    CEILING.store(usize::MAX, Ordering::SeqCst);
}

/// How long the running case has run, `None` between cases.
#[must_use]
pub fn running_for() -> Option<Duration> {
    match STARTED.load(Ordering::SeqCst) {
        0 => None,
        t => Some(epoch().elapsed().saturating_sub(Duration::from_nanos(t - 1))),
    }
}

/// The live bytes a blocked allocation would have reached, if one was blocked.
#[must_use]
pub fn blown() -> Option<usize> {
    match BLOWN.load(Ordering::SeqCst) {
        0 => None,
        n => Some(n),
    }
}

/// Bytes live now.
#[must_use]
pub fn live() -> usize {
    LIVE.load(Ordering::Relaxed)
}
