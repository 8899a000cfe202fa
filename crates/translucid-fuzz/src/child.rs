//! The child side: `translucid-fuzz run-one FILE` loads one file the way a host engine would
//! and says how it went through its exit status alone, so that the parent survives whatever
//! happens here (panic, abort, signal, hang, running out of memory).

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, AtomicPtr, Ordering};

/// Loaded and validated.
pub const EXIT_OK: u8 = 0;
/// A clean `Err`: what a malformed file should give.
pub const EXIT_ERROR: u8 = 2;
/// The load returned, but a panic happened on the way (the library's `catch_unwind` turned
/// it into an error): under `panic = "abort"`, which engines often build with, the host
/// would have died.
pub const EXIT_CAUGHT_PANIC: u8 = 3;
/// The file loaded and rendered, but a method's frame had a NaN or infinite pixel, or
/// exact's frame was off the CPU reference (see [`check_frames`]).
pub const EXIT_WRONG_FRAME: u8 = 4;

static PANICKED: AtomicBool = AtomicBool::new(false);

/// The frame size a loaded file is rendered at: small, so that a case stays quick, and odd,
/// so that edges fall on pixel centres' neighbours.
pub const RENDER_SIZE: (u32, u32) = (37, 23);

pub fn run_one(path: &Path, render: bool) -> ExitCode {
    reserve();
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        PANICKED.store(true, Ordering::SeqCst);
        default_hook(info);
    }));
    let result = translucid::scene::gltf::load(path).and_then(|scene| {
        scene.validate()?;
        Ok(scene)
    });
    let panicked = PANICKED.load(Ordering::SeqCst);
    let scene = match (result, panicked) {
        (_, true) => return ExitCode::from(EXIT_CAUGHT_PANIC),
        (Err(e), false) => {
            // Only seen when a case is a finding or is run by hand.
            eprintln!("load error: {e}");
            return ExitCode::from(EXIT_ERROR);
        }
        (Ok(scene), false) => scene,
    };
    if !render {
        return ExitCode::from(EXIT_OK);
    }
    ExitCode::from(match check_frames(&scene) {
        Ok(()) => EXIT_OK,
        Err(Problem::Refused(e)) => {
            eprintln!("render error: {e}");
            EXIT_ERROR
        }
        Err(Problem::Wrong(e)) => {
            eprintln!("wrong frame: {e}");
            EXIT_WRONG_FRAME
        }
    })
}

enum Problem {
    /// A method or the reference refused the scene with an error: what bad input should get.
    Refused(translucid::Error),
    /// A frame that must not happen.
    Wrong(String),
}

/// Renders `scene` with every method at [`RENDER_SIZE`] and checks what a user relies on:
/// every method's pixels are finite, the reference's are, and exact's are within 2/255 of
/// the reference.
fn check_frames(scene: &translucid::scene::Scene) -> Result<(), Problem> {
    use translucid::methods::MethodKind;
    let (width, height) = RENDER_SIZE;
    let gpu = translucid::gpu::Gpu::new(&translucid::gpu::GpuOptions::from_env())
        .map_err(Problem::Refused)?;
    let mut reference = None;
    for kind in MethodKind::ALL {
        let mut renderer = translucid::renderer::Renderer::new(&gpu, scene, kind, width, height)
            .map_err(Problem::Refused)?;
        let frame = renderer.render(true).map_err(Problem::Refused)?;
        let method = kind.name();
        if let Some(i) = frame.image.pixels.iter().position(|p| !p.is_finite()) {
            return Err(Problem::Wrong(format!(
                "{method}: pixel ({}, {}) is {:?}",
                i as u32 % width,
                i as u32 / width,
                frame.image.pixels[i]
            )));
        }
        let Some(opaque) = frame.opaque.as_ref() else {
            return Err(Problem::Wrong(format!(
                "{method}: no opaque layer read back"
            )));
        };
        if reference.is_none() {
            let image = translucid::reference::render(scene, opaque).map_err(Problem::Refused)?;
            if let Some(i) = image.pixels.iter().position(|p| !p.is_finite()) {
                return Err(Problem::Wrong(format!(
                    "the reference: pixel {i} is {:?}",
                    image.pixels[i]
                )));
            }
            reference = Some(image);
        }
        if let (MethodKind::Exact, Some(expected)) = (kind, &reference) {
            let m =
                translucid::metrics::compare(&frame.image, expected).map_err(Problem::Refused)?;
            if !m.within(2.0 / 255.0) {
                return Err(Problem::Wrong(format!(
                    "exact: {:.1}/255 off the reference on {} pixels",
                    m.max_error * 255.0,
                    m.pixels_over
                )));
            }
        }
    }
    Ok(())
}

/// The system allocator, plus a backtrace on stderr the first time an allocation fails:
/// Rust then aborts with only "memory allocation of N bytes failed", which says nothing
/// about which code asked for the memory.
pub struct ReportingAllocator;

/// Address space set aside in the child and given back before a failure is reported:
/// symbolising a backtrace needs memory, and the cap has just been reached.
const RESERVE: Layout = match Layout::from_size_align(128 << 20, 4096) {
    Ok(layout) => layout,
    Err(_) => panic!("invalid reserve layout"),
};
static RESERVED: AtomicPtr<u8> = AtomicPtr::new(std::ptr::null_mut());
static REPORTED: AtomicBool = AtomicBool::new(false);
static REPORTING: AtomicBool = AtomicBool::new(false);

/// Sets the reserve aside (called once, in the child, before loading).
pub fn reserve() {
    // SAFETY: RESERVE has a non-zero size.
    let block = unsafe { System.alloc(RESERVE) };
    RESERVED.store(block, Ordering::SeqCst);
}

fn report_failure(size: usize) {
    if REPORTING.load(Ordering::SeqCst) {
        // A failure while the report is being made: std's handler would wait for the
        // backtrace lock the report holds, and the child would hang instead of dying.
        const MESSAGE: &[u8] =
            b"fuzz: allocation of more memory failed while reporting a failed allocation\n";
        // SAFETY: write(2) on the standard error descriptor with a valid static buffer and
        // its length; the result is deliberately ignored since the process aborts next.
        unsafe { libc::write(2, MESSAGE.as_ptr().cast(), MESSAGE.len()) };
        std::process::abort();
    }
    if REPORTED.swap(true, Ordering::SeqCst) {
        return;
    }
    REPORTING.store(true, Ordering::SeqCst);
    let block = RESERVED.swap(std::ptr::null_mut(), Ordering::SeqCst);
    if !block.is_null() {
        // SAFETY: `block` came from `System.alloc(RESERVE)` and, swapped out, is freed once.
        unsafe { System.dealloc(block, RESERVE) };
    }
    let trace = std::backtrace::Backtrace::force_capture();
    eprintln!("fuzz: allocation of {size} bytes failed at:\n{trace}");
    REPORTING.store(false, Ordering::SeqCst);
}

// SAFETY: every method forwards to `System` with the caller's arguments unchanged and returns
// its result unchanged, so `System`'s guarantees are ours; on a null result it only writes a
// report, which allocates through this allocator again, and the `REPORTING` flag turns a
// failure inside the report into an abort instead of recursion.
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
