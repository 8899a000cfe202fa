//! Work done on a worker thread beside the frames (a context's preparation in the
//! background): what it builds and allocates is its own, not counted in the
//! `pipelines_created` and `bytes_allocated` of the frames recorded meanwhile on the
//! engine's thread. Its allocations still count against the device's memory budget.

use std::cell::Cell;

thread_local! {
    /// Pipelines built by this thread's background work so far; `None` off it.
    static BACKGROUND_PIPELINES: Cell<Option<u64>> = const { Cell::new(None) };
}

/// Runs `work` as background work on this thread; its result and the pipelines it built.
pub fn in_background<T>(work: impl FnOnce() -> T) -> (T, u64) {
    let outer = BACKGROUND_PIPELINES.replace(Some(0));
    let result = work();
    let built = BACKGROUND_PIPELINES.replace(outer).unwrap_or(0);
    (result, built)
}

/// Counts a pipeline built by background work; false when this thread is not doing any.
pub(crate) fn count_background_pipeline() -> bool {
    BACKGROUND_PIPELINES.with(|built| match built.get() {
        Some(n) => {
            built.set(Some(n + 1));
            true
        }
        None => false,
    })
}

/// Whether this thread is doing background work.
pub(crate) fn is_background() -> bool {
    BACKGROUND_PIPELINES.with(|built| built.get().is_some())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn background_work_counts_its_own_pipelines_and_only_on_its_thread() {
        assert!(!is_background());
        let ((), built) = in_background(|| {
            assert!(is_background());
            assert!(count_background_pipeline());
            assert!(count_background_pipeline());
            let other = std::thread::spawn(|| (is_background(), count_background_pipeline()));
            assert_eq!(other.join().ok(), Some((false, false)));
        });
        assert_eq!(built, 2);
        assert!(!is_background());
        assert!(!count_background_pipeline());
    }
}
