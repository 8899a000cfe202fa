//! What a glTF import reads from the file system: the file itself, and the files its URIs
//! name, which must lie inside the file's own folder or a folder the caller allows.
//!
//! A file from a user is hostile: its URIs may name `/etc/passwd`, climb out with `..`, go
//! through a symbolic link, or name a pipe or device that never ends. Every path is made
//! canonical (links and `..` resolved) before it is compared with the allowed folders, and
//! only regular files are read, each up to a byte limit decided before reading.

use std::io::Read;
use std::path::{Path, PathBuf};

/// The folders a file's URIs may reach: its own, then the caller's, all canonical.
#[derive(Debug)]
pub(super) struct UriRoots {
    roots: Vec<PathBuf>,
}

impl UriRoots {
    /// The folder holding `gltf_file` and the `allowed` folders (each of which must exist).
    pub fn new(gltf_file: &Path, allowed: &[PathBuf]) -> Result<Self, String> {
        let own = match gltf_file.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        let mut roots = Vec::with_capacity(allowed.len() + 1);
        for folder in std::iter::once(own).chain(allowed.iter().map(PathBuf::as_path)) {
            let canonical = folder
                .canonicalize()
                .map_err(|e| format!("cannot resolve the folder {}: {e}", shown(folder)))?;
            if !canonical.is_dir() {
                return Err(format!("{} is not a folder", shown(folder)));
            }
            roots.push(canonical);
        }
        Ok(Self { roots })
    }

    /// The bytes of the file a buffer or image URI names (not a `data:` URI), at most
    /// `limit` of them (see [`Longer`]).
    ///
    /// A relative URI is resolved against the glTF file's folder; an absolute path or a
    /// `file://` URI is taken as it is. Either way the file must lie inside an allowed
    /// folder once links and `..` are resolved, and be a regular file.
    pub fn read(&self, uri: &str, limit: u64, longer: Longer) -> Result<Vec<u8>, String> {
        let decoded = percent_decode(uri)?;
        let (path_text, scheme) = match decoded.strip_prefix("file://") {
            Some(rest) => (rest, true),
            None => (decoded.as_str(), false),
        };
        let path = Path::new(path_text);
        if !scheme && has_scheme(path_text) {
            return Err(format!("unsupported URI scheme in {:?}", shortened(uri)));
        }
        let candidate = if path.is_absolute() {
            path.to_path_buf()
        } else if scheme {
            return Err(format!("file URI {:?} is not absolute", shortened(uri)));
        } else {
            self.roots[0].join(path)
        };
        let canonical = candidate
            .canonicalize()
            .map_err(|e| format!("cannot read {}: {e}", shown(&candidate)))?;
        if !self.roots.iter().any(|root| canonical.starts_with(root)) {
            return Err(format!(
                "URI {:?} names {}, outside the glTF file's folder{}; translucid reads only \
                 files inside it unless the caller allows another folder",
                shortened(uri),
                shown(&canonical),
                if self.roots.len() > 1 {
                    " and the allowed folders"
                } else {
                    ""
                }
            ));
        }
        read_regular_file(&canonical, limit, longer)
    }
}

/// A URI scheme (`http:`, `c:`...) at the start of a relative reference. Windows drive
/// letters are absolute paths there, caught by `is_absolute` first.
fn has_scheme(text: &str) -> bool {
    let Some(colon) = text.find(':') else {
        return false;
    };
    let scheme = &text[..colon];
    !scheme.is_empty()
        && !scheme.contains('/')
        && scheme
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c))
}

/// What [`read_regular_file`] does with a file longer than its limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Longer {
    /// Reads the first `limit` bytes (a buffer's bytes past its byteLength are never used).
    Cut,
    /// Refuses the file, before reading when its size says so.
    Refuse,
}

/// At most `limit` bytes of `path`, which must be a regular file (pipes and devices never
/// end; `/proc` files say they are empty and are not). Memory is reserved fallibly.
pub(super) fn read_regular_file(
    path: &Path,
    limit: u64,
    longer: Longer,
) -> Result<Vec<u8>, String> {
    let cannot = |e: std::io::Error| format!("cannot read {}: {e}", shown(path));
    let metadata = std::fs::metadata(path).map_err(cannot)?;
    if !metadata.is_file() {
        return Err(format!("{} is not a regular file", shown(path)));
    }
    let too_long = |size: u64| {
        format!(
            "{} has {size} bytes or more; at most {limit} are read from it",
            shown(path)
        )
    };
    if longer == Longer::Refuse && metadata.len() > limit {
        return Err(too_long(metadata.len()));
    }
    let expected = metadata.len().min(limit);
    let mut bytes = Vec::new();
    bytes
        .try_reserve_exact(expected as usize)
        .map_err(|_| format!("cannot reserve {expected} bytes to read {}", shown(path)))?;
    let file = std::fs::File::open(path).map_err(cannot)?;
    // One byte past the limit tells a file that grew (or lied about its size) from one that
    // fits.
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(cannot)?;
    if bytes.len() as u64 > limit {
        if longer == Longer::Refuse {
            return Err(too_long(bytes.len() as u64));
        }
        bytes.truncate(limit as usize);
    }
    Ok(bytes)
}

/// Decodes `%XX` escapes in a URI (glTF URIs are RFC 3986).
pub(super) fn percent_decode(uri: &str) -> Result<String, String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match (bytes[i], hex) {
            (b'%', Some(byte)) => {
                out.push(byte);
                i += 3;
            }
            (b, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8(out)
        .map_err(|_| format!("URI {:?} is not UTF-8 once decoded", shortened(uri)))
}

fn shown(path: &Path) -> String {
    shortened(&path.display().to_string())
}

/// Text from a file (a URI, a path) cut to its first and last 40 characters, so that a long
/// one cannot flood a message.
pub(super) fn shortened(text: &str) -> String {
    const KEEP: usize = 40;
    let chars: Vec<char> = text.chars().collect();
    if chars.len() <= 2 * KEEP + 1 {
        return text.to_string();
    }
    let head: String = chars[..KEEP].iter().collect();
    let tail: String = chars[chars.len() - KEEP..].iter().collect();
    format!("{head}…{tail} ({} characters)", chars.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percent_escapes_decode() {
        assert_eq!(percent_decode("a%20b.bin").as_deref(), Ok("a b.bin"));
        assert_eq!(percent_decode("100%").as_deref(), Ok("100%"));
        assert!(percent_decode("%FF").is_err());
    }

    #[test]
    fn schemes_are_told_from_paths() {
        assert!(has_scheme("http://example.com/a.bin"));
        assert!(has_scheme("c:a.bin"));
        assert!(!has_scheme("a.bin"));
        assert!(!has_scheme("folder/a:b.bin"));
    }
}
