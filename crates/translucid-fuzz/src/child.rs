//! The child side: `translucid-fuzz run-one FILE` loads one file the way a host engine would
//! and says how it went through its exit status alone, so that the parent survives whatever
//! happens here (panic, abort, signal, hang, running out of memory).

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

/// Loaded and validated.
pub const EXIT_OK: u8 = 0;
/// A clean `Err`: what a malformed file should give.
pub const EXIT_ERROR: u8 = 2;
/// The load returned, but a panic happened on the way (the library's `catch_unwind` turned
/// it into an error): under `panic = "abort"`, which engines often build with, the host
/// would have died.
pub const EXIT_CAUGHT_PANIC: u8 = 3;

static PANICKED: AtomicBool = AtomicBool::new(false);

pub fn run_one(path: &Path) -> ExitCode {
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        PANICKED.store(true, Ordering::SeqCst);
        default_hook(info);
    }));
    let result = translucid::scene::gltf::load(path).and_then(|scene| scene.validate());
    let panicked = PANICKED.load(Ordering::SeqCst);
    if let Err(e) = &result {
        // Only seen when a case is a finding or is run by hand.
        eprintln!("load error: {e}");
    }
    ExitCode::from(match (result, panicked) {
        (_, true) => EXIT_CAUGHT_PANIC,
        (Ok(()), false) => EXIT_OK,
        (Err(_), false) => EXIT_ERROR,
    })
}

/// The system allocator, plus a backtrace on stderr the first time an allocation fails:
/// Rust then aborts with only "memory allocation of N bytes failed", which says nothing
/// about which code asked for the memory.
pub struct ReportingAllocator;

static REPORTED: AtomicBool = AtomicBool::new(false);

fn report_failure(size: usize) {
    // Once: capturing allocates, and a second failure while capturing must not recurse.
    if !REPORTED.swap(true, Ordering::SeqCst) {
        let trace = std::backtrace::Backtrace::force_capture();
        eprintln!("fuzz: allocation of {size} bytes failed at:\n{trace}");
    }
}

// SAFETY: every method forwards to `System` with the caller's arguments unchanged and returns
// its result unchanged, so `System`'s guarantees are ours; on a null result it only writes a
// report, which allocates through this allocator again, and the `REPORTED` flag keeps that
// from recursing.
unsafe impl GlobalAlloc for ReportingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller upholds `GlobalAlloc::alloc`'s contract, which `System` shares.
        let p = unsafe { System.alloc(layout) };
        if p.is_null() {
            report_failure(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as for `alloc`.
        let p = unsafe { System.alloc_zeroed(layout) };
        if p.is_null() {
            report_failure(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `System` through this allocator with this `layout`.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: `ptr` came from `System` with `layout`; the caller upholds the rest.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if p.is_null() {
            report_failure(new_size);
        }
        p
    }
}
