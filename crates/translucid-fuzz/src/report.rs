//! Counting outcomes, grouping findings by cause, saving each finding's files with a
//! `what.txt`, and the end-of-run summary.

use crate::runner::{Finding, Kind, Outcome};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Examples saved per distinct cause; later ones are only counted. Hangs leave no message
/// to tell their causes apart, so more of them are kept for triage.
const SAVED_PER_CAUSE: usize = 3;
const SAVED_HANGS: usize = 10;

/// One distinct cause and its examples.
#[derive(Debug)]
pub struct Group {
    pub kind: Kind,
    pub signature: String,
    pub count: usize,
    pub first_case: u64,
    pub first_mutant: String,
    pub first_stderr: String,
    pub saved: Vec<PathBuf>,
}

#[derive(Debug, Default)]
pub struct Report {
    pub cases: u64,
    pub loaded: u64,
    pub clean_errors: u64,
    pub by_kind: BTreeMap<Kind, u64>,
    /// Keyed by signature.
    pub groups: BTreeMap<String, Group>,
}

/// What a saved finding needs besides the outcome.
pub struct Case<'a> {
    pub seed: u64,
    pub number: u64,
    pub mutant: &'a str,
    /// Command line rebuilding this very case.
    pub replay: String,
    /// Files to save: (name in the finding folder, path now).
    pub files: Vec<(PathBuf, PathBuf)>,
    pub main_file: String,
}

impl Report {
    pub fn findings(&self) -> u64 {
        self.by_kind.values().sum()
    }

    /// Counts an outcome; a finding's files are saved under `out` while its cause has fewer
    /// than [`SAVED_PER_CAUSE`] examples. Returns the folder written, if any.
    pub fn record(&mut self, outcome: &Outcome, case: &Case, out: &Path) -> Option<PathBuf> {
        self.cases += 1;
        let finding = match outcome {
            Outcome::Loaded => {
                self.loaded += 1;
                return None;
            }
            Outcome::CleanError => {
                self.clean_errors += 1;
                return None;
            }
            Outcome::Finding(f) => f,
        };
        *self.by_kind.entry(finding.kind).or_default() += 1;
        let signature = signature(finding);
        let group = self
            .groups
            .entry(signature.clone())
            .or_insert_with(|| Group {
                kind: finding.kind,
                signature,
                count: 0,
                first_case: case.number,
                first_mutant: case.mutant.to_string(),
                first_stderr: finding.stderr.clone(),
                saved: Vec::new(),
            });
        group.count += 1;
        let keep = match finding.kind {
            Kind::Timeout => SAVED_HANGS,
            _ => SAVED_PER_CAUSE,
        };
        if group.saved.len() >= keep {
            return None;
        }
        match save(finding, &group.signature, case, out) {
            Ok(dir) => {
                group.saved.push(dir.clone());
                Some(dir)
            }
            Err(e) => {
                eprintln!("cannot save finding of case {}: {e}", case.number);
                None
            }
        }
    }

    /// One line: cases, rate, clean errors, successes, findings by kind.
    pub fn summary(&self, seconds: f64) -> String {
        let kinds: Vec<String> = Kind::ALL
            .iter()
            .map(|k| format!("{} {}", k.name(), self.by_kind.get(k).copied().unwrap_or(0)))
            .collect();
        format!(
            "{} cases in {seconds:.0} s ({:.1}/s): {} clean errors, {} loaded; {} findings ({}) in {} distinct causes",
            self.cases,
            self.cases as f64 / seconds.max(1e-9),
            self.clean_errors,
            self.loaded,
            self.findings(),
            kinds.join(", "),
            self.groups.len()
        )
    }

    /// Every distinct cause: kind, count, signature, first example.
    pub fn causes(&self) -> String {
        let mut out = String::new();
        let mut groups: Vec<&Group> = self.groups.values().collect();
        groups.sort_by_key(|g| (g.kind, std::cmp::Reverse(g.count)));
        for g in groups {
            let _ = writeln!(out, "{} x{}: {}", g.kind.name(), g.count, g.signature);
            let _ = writeln!(
                out,
                "    first: case {}: {}",
                g.first_case,
                shorten(&g.first_mutant, 300)
            );
            for line in excerpt(&g.first_stderr) {
                let _ = writeln!(out, "    stderr: {}", shorten(line, 300));
            }
            if let Some(dir) = g.saved.first() {
                let _ = writeln!(out, "    saved: {}", dir.display());
            }
        }
        out
    }
}

/// The lines of a child's stderr that say what happened: a panic's site and message, a
/// failed allocation and its first callers, else the last lines.
fn excerpt(stderr: &str) -> Vec<&str> {
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    let key = lines
        .iter()
        .position(|l| l.contains("panicked at ") || l.contains("allocation of"));
    match key {
        Some(i) => lines[i..].iter().take(2).copied().collect(),
        None => lines[lines.len().saturating_sub(2)..].to_vec(),
    }
}

fn shorten(text: &str, keep: usize) -> String {
    if text.chars().count() <= keep {
        return text.to_string();
    }
    let head: String = text.chars().take(keep).collect();
    format!("{head}…")
}

/// What identifies a cause: a panic's location and message (digits dropped, since they are
/// the file's values), or for aborts the first frames of the failing allocation's backtrace
/// outside the standard library, or the last line the child printed.
pub fn signature(finding: &Finding) -> String {
    let kind = finding.kind.name();
    let stderr = &finding.stderr;
    if let Some((location, message)) = panic_site(stderr) {
        return format!("{kind} at {location}: {}", without_digits(&message));
    }
    if finding.kind == Kind::Timeout {
        return kind.to_string();
    }
    let frames = user_frames(stderr);
    if !frames.is_empty() {
        return format!("{kind} ({}) in {}", finding.status, frames.join(" <- "));
    }
    let last = stderr
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("");
    format!("{kind} ({}): {}", finding.status, without_digits(last))
}

/// "panicked at FILE:LINE:COL:" and the message's first line.
fn panic_site(stderr: &str) -> Option<(String, String)> {
    let at = stderr.find("panicked at ")?;
    let rest = &stderr[at + "panicked at ".len()..];
    let (location, message) = rest.split_once('\n')?;
    let location = location.trim_end_matches(':');
    // A dependency's path from the registry: its crate and version say enough.
    let location = match location.find("/registry/src/") {
        Some(at) => {
            let rest = &location[at + "/registry/src/".len()..];
            rest.split_once('/').map_or(rest, |(_, path)| path)
        }
        None => location,
    }
    .to_string();
    let message = message.lines().next().unwrap_or("").trim().to_string();
    Some((location, message))
}

/// The first two backtrace frames that are neither the standard library nor the fuzzer.
fn user_frames(stderr: &str) -> Vec<String> {
    const SKIP: &[&str] = &[
        "std::",
        "core::",
        "alloc::",
        "<alloc::",
        "<core::",
        "<std::",
        "translucid_fuzz::",
        "<translucid_fuzz::",
        "__rust",
        "rust_",
        "__libc",
        "_start",
        "main",
        "<unknown>",
    ];
    stderr
        .lines()
        .filter_map(|l| {
            let (number, name) = l.trim().split_once(": ")?;
            number.parse::<u32>().ok()?;
            Some(name.trim())
        })
        .filter(|name| !SKIP.iter().any(|s| name.starts_with(s)))
        .take(2)
        .map(|name| {
            // Drop the symbol hash.
            match name.rfind("::h") {
                Some(i) if name.len() - i == 19 => name[..i].to_string(),
                _ => name.to_string(),
            }
        })
        .collect()
}

fn without_digits(text: &str) -> String {
    let mut out = String::new();
    for c in text.chars() {
        if c.is_ascii_digit() {
            if !out.ends_with('N') {
                out.push('N');
            }
        } else {
            out.push(c);
        }
    }
    out
}

/// `<out>/<kind>-<n>/`, `n` the first free number, with the case's files and `what.txt`.
fn save(finding: &Finding, signature: &str, case: &Case, out: &Path) -> std::io::Result<PathBuf> {
    std::fs::create_dir_all(out)?;
    let dir = (0..)
        .map(|n| out.join(format!("{}-{n}", finding.kind.name())))
        .find(|d| !d.exists())
        .unwrap_or_else(|| out.join(finding.kind.name()));
    std::fs::create_dir_all(&dir)?;
    for (name, from) in &case.files {
        let to = dir.join(name);
        if let Some(parent) = to.parent() {
            std::fs::create_dir_all(parent)?;
        }
        std::fs::copy(from, to)?;
    }
    let what = format!(
        "kind: {kind}\n\
         cause: {signature}\n\
         child: {status} ({seconds:.2} s)\n\
         seed: {seed}\ncase: {number}\n\
         mutant: {mutant}\n\n\
         Reproduce:\n  translucid-fuzz run-one {file}    (these files; exit 0 loaded, 2 clean error)\n  \
         {replay}    (rebuilds the case from the seed)\n\n\
         Child's stderr:\n{stderr}\n",
        kind = finding.kind.name(),
        status = finding.status,
        seconds = finding.seconds,
        seed = case.seed,
        number = case.number,
        mutant = case.mutant,
        file = dir.join(&case.main_file).display(),
        replay = case.replay,
        stderr = finding.stderr,
    );
    std::fs::write(dir.join("what.txt"), what)?;
    Ok(dir)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn finding(kind: Kind, stderr: &str) -> Finding {
        Finding {
            kind,
            status: "exit code 101 (panic)".into(),
            stderr: stderr.into(),
            seconds: 0.1,
        }
    }

    #[test]
    fn panics_are_grouped_by_site_not_by_values() {
        let a = finding(
            Kind::Panic,
            "thread 'main' panicked at src/a.rs:10:5:\nindex 7 out of range for 3\nnote: ...",
        );
        let b = finding(
            Kind::Panic,
            "thread 'main' panicked at src/a.rs:10:5:\nindex 12 out of range for 4\n",
        );
        assert_eq!(signature(&a), signature(&b));
        assert_eq!(
            signature(&a),
            "panic at src/a.rs:10:5: index N out of range for N"
        );
    }

    #[test]
    fn allocation_failures_are_grouped_by_caller() {
        let stderr = "fuzz: allocation of 8 bytes failed at:\n   0: std::backtrace::Backtrace::create\n   1: translucid_fuzz::child::report_failure\n   2: alloc::raw_vec::finish_grow\n   3: gltf::accessor::util::Iter::new::h0123456789abcdef\n   4: translucid::scene::gltf::read_primitive\n";
        let f = Finding {
            kind: Kind::Memory,
            status: "signal 6 (SIGABRT)".into(),
            stderr: stderr.into(),
            seconds: 1.0,
        };
        assert_eq!(
            signature(&f),
            "memory (signal 6 (SIGABRT)) in gltf::accessor::util::Iter::new <- translucid::scene::gltf::read_primitive"
        );
    }
}
