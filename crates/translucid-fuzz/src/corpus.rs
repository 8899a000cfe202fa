//! The seed files: every `.gltf`/`.glb` under the corpus folders, read once, with the files
//! their relative URIs name (buffers, images), so that those can be mutated too and copied
//! beside each mutant.

use crate::glb::Glb;
use serde_json::Value;
use std::path::{Component, Path, PathBuf};

/// Larger files are not read into memory (nor mutated); they are still copied.
const MAX_SIBLING_BYTES: u64 = 256 << 20;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Gltf,
    Glb,
}

impl Format {
    pub fn extension(self) -> &'static str {
        match self {
            Format::Gltf => "gltf",
            Format::Glb => "glb",
        }
    }
}

/// A file a seed references, by its path relative to the seed's folder.
#[derive(Debug)]
pub struct Sibling {
    pub rel: PathBuf,
    pub bytes: Vec<u8>,
}

#[derive(Debug)]
pub struct Seed {
    pub path: PathBuf,
    pub dir: PathBuf,
    pub format: Format,
    pub bytes: Vec<u8>,
    /// The glTF JSON (the JSON chunk of a GLB), when it parses.
    pub json: Option<Value>,
    /// The parsed container of a GLB, when it is well formed.
    pub glb: Option<Glb>,
    /// Files named by relative URIs that exist, read.
    pub siblings: Vec<Sibling>,
    /// Every regular file of the seed's folder and its siblings, relative: what the work
    /// folder gets a copy of, so that any relative URI a mutant invents resolves as it would
    /// beside the original.
    pub copies: Vec<PathBuf>,
}

/// Every `.gltf`/`.glb` under `dirs` (recursively; a file may be named directly), sorted
/// so that a seed picks the same files in the same order on every run.
pub fn find_files(dirs: &[PathBuf]) -> Vec<PathBuf> {
    fn walk(path: &Path, out: &mut Vec<PathBuf>) {
        let Ok(meta) = std::fs::metadata(path) else {
            return;
        };
        if meta.is_dir() {
            let Ok(entries) = std::fs::read_dir(path) else {
                return;
            };
            for entry in entries.flatten() {
                walk(&entry.path(), out);
            }
        } else if meta.is_file() && is_scene(path) {
            out.push(path.to_path_buf());
        }
    }
    let mut out = Vec::new();
    for dir in dirs {
        walk(dir, &mut out);
    }
    out.sort();
    out.dedup();
    out
}

fn is_scene(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
}

/// Reads every seed under `dirs`; a corpus without any is an error.
pub fn load(dirs: &[PathBuf]) -> Result<Vec<Seed>, String> {
    let files = find_files(dirs);
    if files.is_empty() {
        let shown: Vec<_> = dirs.iter().map(|d| d.display().to_string()).collect();
        return Err(format!("no .gltf or .glb file under {}", shown.join(", ")));
    }
    files.into_iter().map(|p| load_seed(&p)).collect()
}

fn load_seed(path: &Path) -> Result<Seed, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let is_glb = bytes.starts_with(crate::glb::MAGIC);
    let glb = if is_glb { Glb::parse(&bytes) } else { None };
    let json_text = match &glb {
        Some(glb) => glb.json(),
        None if is_glb => None,
        None => Some(&bytes[..]),
    };
    let json: Option<Value> = json_text.and_then(|t| serde_json::from_slice(t).ok());
    let mut siblings = Vec::new();
    for uri in json.as_ref().map(relative_uris).unwrap_or_default() {
        let Some(rel) = uri_to_relative(&uri) else {
            continue;
        };
        let file = dir.join(&rel);
        let fits =
            std::fs::metadata(&file).is_ok_and(|m| m.is_file() && m.len() <= MAX_SIBLING_BYTES);
        if fits && !siblings.iter().any(|s: &Sibling| s.rel == rel) {
            let bytes =
                std::fs::read(&file).map_err(|e| format!("cannot read {}: {e}", file.display()))?;
            siblings.push(Sibling { rel, bytes });
        }
    }
    let mut copies: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map_err(|e| format!("cannot list {}: {e}", dir.display()))?
        .flatten()
        .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
        .map(|e| PathBuf::from(e.file_name()))
        .collect();
    copies.extend(siblings.iter().map(|s| s.rel.clone()));
    copies.sort();
    copies.dedup();
    Ok(Seed {
        path: path.to_path_buf(),
        dir,
        format: if is_glb { Format::Glb } else { Format::Gltf },
        bytes,
        json,
        glb,
        siblings,
        copies,
    })
}

/// The `uri` of every buffer and image that is not a `data:` URI.
pub fn relative_uris(json: &Value) -> Vec<String> {
    ["buffers", "images"]
        .iter()
        .filter_map(|key| json.get(key)?.as_array())
        .flatten()
        .filter_map(|item| item.get("uri")?.as_str())
        .filter(|uri| !uri.starts_with("data:"))
        .map(str::to_string)
        .collect()
}

/// A URI as a path below the seed's folder: percent-decoded, and only if it stays inside
/// (no scheme, no absolute path, no `..`).
pub fn uri_to_relative(uri: &str) -> Option<PathBuf> {
    if uri.contains(':') {
        return None;
    }
    let mut bytes = Vec::with_capacity(uri.len());
    let raw = uri.as_bytes();
    let mut i = 0;
    while i < raw.len() {
        let hex = raw
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match (raw[i], hex) {
            (b'%', Some(b)) => {
                bytes.push(b);
                i += 3;
            }
            (b, _) => {
                bytes.push(b);
                i += 1;
            }
        }
    }
    let path = PathBuf::from(String::from_utf8(bytes).ok()?);
    let inside = path
        .components()
        .all(|c| matches!(c, Component::Normal(_) | Component::CurDir));
    (inside && path.components().next().is_some()).then_some(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uris_stay_inside_the_seed_folder() {
        assert_eq!(uri_to_relative("a%20b.bin"), Some(PathBuf::from("a b.bin")));
        assert_eq!(
            uri_to_relative("tex/a.png"),
            Some(PathBuf::from("tex/a.png"))
        );
        assert_eq!(uri_to_relative("../a.bin"), None);
        assert_eq!(uri_to_relative("/dev/zero"), None);
        assert_eq!(uri_to_relative("file:///etc/passwd"), None);
        assert_eq!(uri_to_relative(""), None);
    }

    #[test]
    fn vendored_seeds_load_with_their_buffers() {
        let scenes = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes");
        let seeds = load(&[scenes]).expect("vendored corpus loads");
        assert!(seeds.iter().all(|s| s.json.is_some()));
        let gltf = seeds
            .iter()
            .find(|s| s.format == Format::Gltf)
            .expect("a .gltf seed");
        assert!(!gltf.siblings.is_empty(), "its .bin was not found");
        assert!(seeds
            .iter()
            .filter(|s| s.format == Format::Glb)
            .all(|s| s.glb.is_some()));
    }
}
