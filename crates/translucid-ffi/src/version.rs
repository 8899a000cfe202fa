//! Versions: the library's, the header's, and the rule that says whether they fit together.

use crate::result::{translucid_result, Failure, FfiResult};
use std::ffi::c_char;

pub const TRANSLUCID_VERSION_MAJOR: u32 = 0;
pub const TRANSLUCID_VERSION_MINOR: u32 = 8;
pub const TRANSLUCID_VERSION_PATCH: u32 = 0;
/// The version of the header in use, packed as `major << 22 | minor << 12 | patch` (like
/// `VK_MAKE_API_VERSION` without the variant). Put it in
/// `translucid_context_create_info.header_version`.
pub const TRANSLUCID_HEADER_VERSION: u32 =
    (TRANSLUCID_VERSION_MAJOR << 22) | (TRANSLUCID_VERSION_MINOR << 12) | TRANSLUCID_VERSION_PATCH;

fn unpack(v: u32) -> (u32, u32, u32) {
    (v >> 22, (v >> 12) & 0x3ff, v & 0xfff)
}

/// A header fits when its major version equals the library's and its minor version is not
/// newer (structs only ever grow at the end, behind new structure types or zero defaults).
/// Before 1.0 every minor version may break the ABI, so the minor must match exactly.
pub fn check_header_version(header: u32) -> FfiResult {
    let (hmaj, hmin, hpat) = unpack(header);
    let (lmaj, lmin, lpat) = unpack(TRANSLUCID_HEADER_VERSION);
    let fits = hmaj == lmaj
        && if lmaj == 0 {
            hmin == lmin
        } else {
            hmin <= lmin
        };
    if fits {
        return Ok(());
    }
    Err(Failure::new(
        translucid_result::ErrorHeaderVersionMismatch,
        format!(
            "compiled against translucid.h {hmaj}.{hmin}.{hpat} ({header:#x}), but the library \
             is {lmaj}.{lmin}.{lpat}: rebuild with the header that ships with this library \
             (was header_version set to TRANSLUCID_HEADER_VERSION?)"
        ),
    ))
}

/// The library's version, packed like `TRANSLUCID_HEADER_VERSION`.
#[no_mangle]
pub extern "C" fn translucid_version() -> u32 {
    TRANSLUCID_HEADER_VERSION
}

/// The library's version as a static string, e.g. "0.8.0".
#[no_mangle]
pub extern "C" fn translucid_version_string() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr().cast()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_version_constants_match_the_crate_version() {
        let cargo = env!("CARGO_PKG_VERSION");
        let ours = format!(
            "{TRANSLUCID_VERSION_MAJOR}.{TRANSLUCID_VERSION_MINOR}.{TRANSLUCID_VERSION_PATCH}"
        );
        assert_eq!(
            ours, cargo,
            "the version in Cargo.toml changed: update TRANSLUCID_VERSION_* in \
             crates/translucid-ffi/src/version.rs and regenerate include/translucid.h"
        );
    }

    #[test]
    fn only_a_compatible_header_is_accepted() {
        assert!(check_header_version(TRANSLUCID_HEADER_VERSION).is_ok());
        assert!(check_header_version(0).is_err() || TRANSLUCID_HEADER_VERSION == 0);
        assert!(check_header_version(TRANSLUCID_HEADER_VERSION + (1 << 12)).is_err());
        assert!(check_header_version(TRANSLUCID_HEADER_VERSION + (1 << 22)).is_err());
        assert!(
            check_header_version(TRANSLUCID_HEADER_VERSION + 1).is_ok(),
            "patch differs"
        );
    }
}
