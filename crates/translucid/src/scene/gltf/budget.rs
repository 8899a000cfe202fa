//! How much a glTF import may read and make, for the whole file.
//!
//! Limits per accessor or per buffer are not enough: a 7 KB file can name one 16 M-element
//! accessor from forty primitives, or one buffer a thousand times. So every amount is
//! counted across the file as it is imported, and each is refused before the memory for it is
//! taken, with a message that names the limit.

use std::path::PathBuf;

/// What a glTF import may read and how much: see [`super::load_with`].
#[derive(Clone, Debug, Default)]
#[non_exhaustive]
pub struct ImportOptions {
    /// Folders, besides the glTF file's own, that its buffer and image URIs may name files
    /// in (absolute paths and `file://` URIs included). Empty by default: a file reads only
    /// what lies in its own folder.
    pub allowed_dirs: Vec<PathBuf>,
    /// The amounts the whole file may take.
    pub limits: ImportLimits,
}

impl ImportOptions {
    /// The defaults, with `dirs` allowed beside the file's folder.
    pub fn allowing(dirs: impl IntoIterator<Item = PathBuf>) -> Self {
        Self {
            allowed_dirs: dirs.into_iter().collect(),
            ..Self::default()
        }
    }
}

/// Amounts one glTF import may take in all. The defaults are well above every real scene
/// we have (the largest shared one reads 3 M elements and 60 MB) and keep what an import
/// allocates within a few GB.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct ImportLimits {
    /// Bytes read in all: the file, its buffers (as declared) and its image files.
    pub bytes: u64,
    /// Accessor elements read in all, over every primitive (a vertex's position, normal,
    /// colour and uv are four; an index is one). Default 64 M.
    pub elements: u64,
    /// Node instances the hierarchy expands to (a node reached along two paths counts
    /// twice). Default 4 M.
    pub node_instances: u64,
    /// Triangles in all, each mesh counted once however many nodes draw it. Default 32 M.
    pub triangles: u64,
    /// Texels of the textures the materials use, in all. Default two 8192x8192 textures.
    pub texels: u64,
}

impl Default for ImportLimits {
    fn default() -> Self {
        Self {
            bytes: 4 << 30,
            elements: 1 << 26,
            node_instances: 1 << 22,
            triangles: 1 << 25,
            texels: crate::scene::MAX_SCENE_TEXELS,
        }
    }
}

/// One amount [`ImportLimits`] bounds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Amount {
    Bytes,
    Elements,
    NodeInstances,
    Triangles,
    Texels,
}

impl Amount {
    fn describe(self) -> (&'static str, &'static str) {
        match self {
            Amount::Bytes => ("bytes read", "bytes"),
            Amount::Elements => ("accessor elements read", "elements"),
            Amount::NodeInstances => ("node instances", "node_instances"),
            Amount::Triangles => ("triangles", "triangles"),
            Amount::Texels => ("texture texels", "texels"),
        }
    }
}

/// The amounts an import has taken so far against its limits.
#[derive(Debug)]
pub(super) struct Budget {
    limits: ImportLimits,
    used: [u64; 5],
}

impl Budget {
    pub fn new(limits: ImportLimits) -> Self {
        Self {
            limits,
            used: [0; 5],
        }
    }

    fn limit(&self, amount: Amount) -> u64 {
        match amount {
            Amount::Bytes => self.limits.bytes,
            Amount::Elements => self.limits.elements,
            Amount::NodeInstances => self.limits.node_instances,
            Amount::Triangles => self.limits.triangles,
            Amount::Texels => self.limits.texels,
        }
    }

    /// Takes `n` of `amount` for `what`, or says which limit that would pass.
    pub fn take(&mut self, amount: Amount, n: u64, what: &str) -> Result<(), String> {
        let total = self.used[amount as usize].saturating_add(n);
        let limit = self.limit(amount);
        if total > limit {
            let (name, field) = amount.describe();
            return Err(format!(
                "{what}: the file's {name} would reach {total}, over the import's limit of \
                 {limit} (ImportLimits::{field})"
            ));
        }
        self.used[amount as usize] = total;
        Ok(())
    }
}

/// Collects an iterator of `count` items into a vector whose memory is reserved fallibly, so
/// that a huge count the budget allowed is an error on a small machine, not an abort.
pub(super) fn collect_fallibly<T>(
    count: usize,
    items: impl Iterator<Item = T>,
    what: &str,
) -> Result<Vec<T>, String> {
    let mut out = Vec::new();
    out.try_reserve_exact(count).map_err(|_| {
        format!(
            "cannot reserve memory for {count} {what} ({} bytes)",
            count.saturating_mul(std::mem::size_of::<T>())
        )
    })?;
    out.extend(items.take(count));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_budget_holds_across_takes_and_names_its_limit() {
        let mut budget = Budget::new(ImportLimits {
            elements: 10,
            ..ImportLimits::default()
        });
        budget.take(Amount::Elements, 6, "POSITION").expect("fits");
        let err = budget
            .take(Amount::Elements, 6, "NORMAL")
            .expect_err("over");
        assert!(
            err.contains("ImportLimits::elements") && err.contains("12"),
            "{err}"
        );
        budget
            .take(Amount::Elements, 4, "indices")
            .expect("a refused take takes nothing");
        budget
            .take(Amount::Bytes, 1 << 20, "file")
            .expect("amounts are apart");
    }

    #[test]
    fn a_huge_collection_is_an_error() {
        let err = collect_fallibly(usize::MAX / 2, std::iter::repeat(0u64), "items")
            .expect_err("cannot reserve");
        assert!(err.contains("cannot reserve"), "{err}");
    }
}
