//! The one place where raw pointers from C become Rust references.
//!
//! Every export reaches its arguments through these helpers, which reject NULL and misaligned
//! pointers with an error instead of crashing. What they cannot check is the C side of the
//! contract, stated once in the header: every non-NULL pointer points to live memory of the
//! documented extent for the duration of the call, and nothing else mutates it meanwhile.
//! Each `unsafe` block below relies on exactly that.

use crate::context::Context;
use crate::result::{translucid_result, Failure, FfiResult};
use crate::structure::translucid_structure_type;
use std::ffi::{c_char, c_void, CStr};
use std::mem::MaybeUninit;

/// The context as C sees it: opaque, only ever behind a pointer.
#[allow(non_camel_case_types)]
pub struct translucid_context {
    _private: [u8; 0],
}

/// A reference to the `T` at `ptr`.
pub(crate) fn try_ref<'a, T>(ptr: *const T, what: &str) -> FfiResult<&'a T> {
    check_pointer(ptr, what)?;
    // SAFETY: non-NULL and aligned (checked above); valid for reads of a T by the C contract.
    Ok(unsafe { &*ptr })
}

/// A slice of `len` values at `ptr`; NULL is accepted when `len` is 0.
pub(crate) fn try_slice<'a, T>(ptr: *const T, len: usize, what: &str) -> FfiResult<&'a [T]> {
    if len == 0 {
        return Ok(&[]);
    }
    check_pointer(ptr, what)?;
    check_extent::<T>(len, what)?;
    // SAFETY: non-NULL, aligned, extent fits in isize (checked above); valid for reads of
    // `len` values by the C contract.
    Ok(unsafe { std::slice::from_raw_parts(ptr, len) })
}

/// An output array of `len` values at `ptr`, to be written (never read).
pub(crate) fn try_out_slice<'a, T>(
    ptr: *mut T,
    len: usize,
    what: &str,
) -> FfiResult<&'a mut [MaybeUninit<T>]> {
    check_pointer(ptr, what)?;
    check_extent::<T>(len, what)?;
    // SAFETY: non-NULL, aligned, extent fits in isize; valid for writes of `len` values by the
    // C contract. MaybeUninit means nothing is read from it.
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr.cast::<MaybeUninit<T>>(), len) })
}

/// An out-parameter, checked before the work starts and written only once it succeeded.
pub(crate) fn try_out<'a, T>(ptr: *mut T, what: &str) -> FfiResult<&'a mut MaybeUninit<T>> {
    check_pointer(ptr, what)?;
    // SAFETY: non-NULL and aligned; valid for writes of a T by the C contract. MaybeUninit
    // means nothing is read from it.
    Ok(unsafe { &mut *ptr.cast::<MaybeUninit<T>>() })
}

/// Writes `value` to an optional out-parameter: nothing where it is NULL.
pub(crate) fn write_optional<T>(ptr: *mut T, what: &str, value: T) -> FfiResult {
    if !ptr.is_null() {
        try_out(ptr, what)?.write(value);
    }
    Ok(())
}

/// An optional NUL-terminated UTF-8 string; NULL gives `None`.
pub(crate) fn try_str<'a>(ptr: *const c_char, what: &str) -> FfiResult<Option<&'a str>> {
    if ptr.is_null() {
        return Ok(None);
    }
    // SAFETY: non-NULL; NUL-terminated and live for the call by the C contract.
    let s = unsafe { CStr::from_ptr(ptr) };
    s.to_str()
        .map(Some)
        .map_err(|_| Failure::argument(format!("{what} is not valid UTF-8")))
}

/// The header every extensible struct starts with; used to read `next` chains.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct translucid_base_in_structure {
    /// A `translucid_structure_type` value.
    pub s_type: u32,
    /// The next structure in the chain, or NULL.
    pub next: *const translucid_base_in_structure,
}

/// An enum value's name as the header spells it: `prefix`, then the Rust variant's words in
/// capitals (`MeshCreateInfo` -> `PREFIX_MESH_CREATE_INFO`), as cbindgen writes them.
pub(crate) fn c_enum_name(prefix: &str, variant: &str) -> String {
    let mut name = String::from(prefix);
    for c in variant.chars() {
        if c.is_ascii_uppercase() {
            name.push('_');
        }
        name.push(c.to_ascii_uppercase());
    }
    name
}

/// Checks a struct's `s_type` and that its `next` chain is empty, for a structure that takes
/// no extension structure (those that do walk their chains themselves).
pub(crate) fn check_header(
    s_type: u32,
    next: *const c_void,
    expected: translucid_structure_type,
    what: &str,
) -> FfiResult {
    check_type(s_type, expected, what)?;
    if next.is_null() {
        return Ok(());
    }
    let link = try_ref(next.cast::<translucid_base_in_structure>(), "next")?;
    Err(Failure::new(
        translucid_result::ErrorInvalidStructureType,
        format!(
            "{what}.next holds structure type {}, which {what} does not accept in this \
             version; set next to NULL",
            link.s_type
        ),
    ))
}

/// Checks that `s_type` is `expected`, for a structure whose `next` chain its reader walks.
pub(crate) fn check_type(
    s_type: u32,
    expected: translucid_structure_type,
    what: &str,
) -> FfiResult {
    if s_type != expected as u32 {
        let found = translucid_structure_type::from_raw(s_type).map_or_else(
            || format!("{s_type} (no such structure type)"),
            |t| format!("{} ({s_type})", t.c_name()),
        );
        return Err(Failure::new(
            translucid_result::ErrorInvalidStructureType,
            format!(
                "{what}.s_type is {found}; set it to {} ({})",
                expected.c_name(),
                expected as u32
            ),
        ));
    }
    Ok(())
}

/// A struct translucid fills in whose `s_type` and `next` the caller sets.
pub(crate) trait OutStructure {
    const TYPE: translucid_structure_type;
    const NAME: &'static str;
    /// The caller-set `s_type` and `next` of the struct at `ptr`, read field by field: the
    /// rest is the caller's uninitialised memory, which no reference may cover.
    ///
    /// # Safety
    /// `ptr` is non-NULL, aligned and valid for reads of those two fields.
    unsafe fn header(ptr: *const Self) -> (u32, *mut c_void);
}

/// An out-struct at `ptr`: its caller-set `s_type` and `next` checked and returned (to be
/// written back unchanged), and the struct to write once the work succeeded.
pub(crate) fn try_out_structure<'a, T: OutStructure>(
    ptr: *mut T,
    what: &str,
) -> FfiResult<((u32, *mut c_void), &'a mut MaybeUninit<T>)> {
    let out = try_out(ptr, what)?;
    // SAFETY: `try_out` checked that `ptr` is non-NULL and aligned; the C contract makes it
    // valid for a T, whose `s_type` and `next` the caller set.
    let header = unsafe { T::header(out.as_ptr()) };
    check_header(header.0, header.1.cast_const(), T::TYPE, T::NAME)?;
    Ok((header, out))
}

/// Moves a context to C.
pub(crate) fn context_into_raw(context: Box<Context>) -> *mut translucid_context {
    Box::into_raw(context).cast()
}

/// Takes a context back from C to drop it; NULL gives `None`.
pub(crate) fn context_from_raw(ptr: *mut translucid_context) -> Option<Box<Context>> {
    // SAFETY: a non-NULL pointer came from `context_into_raw` and is not used after
    // `translucid_context_destroy` (C contract).
    (!ptr.is_null()).then(|| unsafe { Box::from_raw(ptr.cast::<Context>()) })
}

/// The context behind a pointer from `translucid_context_create`: shared, since other
/// threads may hold it too; a call works on it through `Context::enter`.
pub(crate) fn context_shared<'a>(ptr: *const translucid_context) -> FfiResult<&'a Context> {
    let ptr = ptr.cast::<Context>();
    check_pointer(ptr, "context")?;
    // SAFETY: came from `context_into_raw` and is not destroyed while a call uses it (C
    // contract; `translucid_context_destroy` refuses while another call is in); only
    // shared references to a `Context` are ever made from it.
    Ok(unsafe { &*ptr })
}

/// As [`context_shared`]; `None` for NULL or a misaligned pointer.
pub(crate) fn context_ref<'a>(ptr: *const translucid_context) -> Option<&'a Context> {
    context_shared(ptr).ok()
}

fn check_pointer<T>(ptr: *const T, what: &str) -> FfiResult {
    if ptr.is_null() {
        return Err(Failure::null(what));
    }
    if !ptr.is_aligned() {
        return Err(Failure::argument(format!(
            "{what} is not aligned to {} bytes",
            std::mem::align_of::<T>()
        )));
    }
    Ok(())
}

fn check_extent<T>(len: usize, what: &str) -> FfiResult {
    match len.checked_mul(std::mem::size_of::<T>()) {
        Some(bytes) if bytes <= isize::MAX.unsigned_abs() => Ok(()),
        _ => Err(Failure::size(format!("{what}: {len} elements is too many"))),
    }
}
