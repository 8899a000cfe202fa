//! The boundary every export's body runs inside: errors become a code plus a last-error
//! message, and a panic never unwinds into C. After a panic the context's state may be
//! half-updated, so the context refuses all further work (it can still be destroyed).

use crate::cast::{self, translucid_context};
use crate::context::{Context, Objects};
use crate::result::{translucid_result, FfiResult};
use std::cell::RefCell;
use std::ffi::{c_char, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Per-context bookkeeping of the boundary.
#[derive(Default)]
pub struct CallState {
    poisoned: bool,
    last_error: CString,
}

impl CallState {
    pub fn last_error(&self) -> *const c_char {
        self.last_error.as_ptr()
    }

    fn set_error(&mut self, message: &str) {
        self.last_error = to_c_string(message);
    }
}

thread_local! {
    /// The last error of a call that had no context to keep it (creation, NULL context).
    static THREAD_ERROR: RefCell<CString> = RefCell::new(CString::default());
    /// The context this thread's last call on it was refused (another thread was in a
    /// call), and why: that call could not keep its error in the context.
    static REFUSED: RefCell<Option<(usize, CString)>> = const { RefCell::new(None) };
}

/// Refuses a call on `context`, which another thread is in a call on: the thread keeps the
/// message (after `prefix`), for `translucid_context_get_last_error` on this thread.
pub fn refuse_busy(context: *const translucid_context, prefix: &str) -> translucid_result {
    let message = format!(
        "{prefix}another thread is in a call on this context; calls on one context must not \
         overlap (use a context per thread, or hold a lock around each call); nothing was done"
    );
    REFUSED.with(|r| *r.borrow_mut() = Some((context as usize, to_c_string(&message))));
    set_thread_error(&message);
    translucid_result::ErrorContextBusy
}

/// `translucid_context_get_last_error` of `context`: the refusal of this thread's last call
/// on it if it was refused, else the context's own last error (a fixed message while another
/// thread is in a call, which may be changing it).
pub fn last_error_of(context: *const translucid_context, shared: &Context) -> *const c_char {
    let refused = REFUSED.with(|r| match &*r.borrow() {
        Some((refused, message)) if *refused == context as usize => Some(message.as_ptr()),
        _ => None,
    });
    if let Some(message) = refused {
        return message;
    }
    match shared.enter() {
        Some(entered) => entered.state.last_error(),
        None => c"translucid_context_get_last_error: another thread is in a call on this \
                  context, which may change its last error"
            .as_ptr(),
    }
}

/// The message of the last failed context-less call on this thread. The pointer stays valid
/// until the next such failure on this thread.
pub fn thread_last_error() -> *const c_char {
    THREAD_ERROR.with(|e| e.borrow().as_ptr())
}

fn set_thread_error(message: &str) {
    THREAD_ERROR.with(|e| *e.borrow_mut() = to_c_string(message));
}

/// Runs `body` on the context behind `ptr`.
pub fn with_context(
    ptr: *mut translucid_context,
    body: impl FnOnce(&mut Objects) -> FfiResult<translucid_result>,
) -> translucid_result {
    match cast::context_shared(ptr) {
        Ok(context) => {
            let Some(mut entered) = context.enter() else {
                return refuse_busy(ptr, "");
            };
            REFUSED.with(|r| {
                let mut r = r.borrow_mut();
                if r.as_ref()
                    .is_some_and(|(refused, _)| *refused == ptr as usize)
                {
                    *r = None;
                }
            });
            let calls = &mut *entered;
            guarded(&mut calls.state, &mut calls.objects, body)
        }
        Err(failure) => {
            set_thread_error(&failure.message);
            failure.code
        }
    }
}

/// Runs `body` for a call that has no context yet; its error message goes to the thread.
pub fn without_context(body: impl FnOnce() -> FfiResult<translucid_result>) -> translucid_result {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(code)) => code,
        Ok(Err(failure)) => {
            set_thread_error(&failure.message);
            failure.code
        }
        Err(payload) => {
            set_thread_error(&panic_message(payload.as_ref()));
            translucid_result::ErrorPanic
        }
    }
}

/// For queries that return a value rather than a code: a panic gives `fallback`.
pub fn or_fallback<T>(fallback: T, body: impl FnOnce() -> T) -> T {
    catch_unwind(AssertUnwindSafe(body)).unwrap_or(fallback)
}

/// The boundary itself, generic so it can be tested without a device.
fn guarded<T>(
    state: &mut CallState,
    inner: &mut T,
    body: impl FnOnce(&mut T) -> FfiResult<translucid_result>,
) -> translucid_result {
    if state.poisoned {
        return translucid_result::ErrorContextPoisoned;
    }
    match catch_unwind(AssertUnwindSafe(|| body(inner))) {
        Ok(Ok(code)) => code,
        Ok(Err(failure)) => {
            state.set_error(&failure.message);
            failure.code
        }
        Err(payload) => {
            state.poisoned = true;
            state.set_error(&panic_message(payload.as_ref()));
            translucid_result::ErrorPanic
        }
    }
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    let detail = payload
        .downcast_ref::<&str>()
        .copied()
        .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
        .unwrap_or("(no message)");
    format!("internal error (a bug in translucid, please report it): {detail}; the context is unusable now, destroy it")
}

/// A C string of `message`, with any NUL replaced so nothing is cut off silently.
fn to_c_string(message: &str) -> CString {
    CString::new(message.replace('\0', "\u{FFFD}")).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::result::Failure;

    #[test]
    fn a_panic_becomes_an_error_and_poisons_the_state() {
        let mut state = CallState::default();
        let mut inner = 0;
        let ok = guarded(&mut state, &mut inner, |i| {
            *i += 1;
            Ok(translucid_result::Success)
        });
        assert_eq!(ok, translucid_result::Success);
        let failed = guarded(&mut state, &mut inner, |_| {
            Err(Failure::argument("bad value"))
        });
        assert_eq!(failed, translucid_result::ErrorInvalidArgument);
        assert_eq!(state.last_error.to_str(), Ok("bad value"));
        let panicked = guarded(&mut state, &mut inner, |_| -> FfiResult<_> {
            panic!("boom")
        });
        assert_eq!(panicked, translucid_result::ErrorPanic);
        assert!(state.last_error.to_string_lossy().contains("boom"));
        let refused = guarded(&mut state, &mut inner, |i| {
            *i += 1;
            Ok(translucid_result::Success)
        });
        assert_eq!(refused, translucid_result::ErrorContextPoisoned);
        assert_eq!(inner, 1, "no work after the panic");
    }
}
