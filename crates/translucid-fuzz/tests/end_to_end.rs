//! The binary end to end: the child's exit codes, replaying one case, and a short run that
//! ends with the summary line.

use std::path::PathBuf;
use std::process::Command;

const EXE: &str = env!("CARGO_BIN_EXE_translucid-fuzz");

fn scenes() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("translucid-fuzz-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

#[test]
fn child_exit_codes_say_loaded_or_clean_error() {
    let good = scenes().join("spot/spot_blend.gltf");
    let status = Command::new(EXE)
        .arg("run-one")
        .arg(&good)
        .status()
        .expect("run child");
    assert_eq!(status.code(), Some(0));
    let rendered = Command::new(EXE)
        .args(["run-one", "--render"])
        .arg(&good)
        .output()
        .expect("run child");
    assert_eq!(
        rendered.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&rendered.stderr)
    );

    let dir = scratch("child");
    let bad = dir.join("bad.gltf");
    std::fs::write(
        &bad,
        br#"{"asset":{"version":"2.0"},"scenes":[{"nodes":[7]}]}"#,
    )
    .expect("write");
    let out = Command::new(EXE)
        .arg("run-one")
        .arg(&bad)
        .output()
        .expect("run child");
    assert_eq!(
        out.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_case_replays_and_a_short_run_summarises() {
    let dir = scratch("run");
    let replay = Command::new(EXE)
        .args(["gltf", "--seed", "5", "--case", "3", "--corpus"])
        .arg(scenes())
        .arg("--out")
        .arg(dir.join("findings"))
        .output()
        .expect("replay");
    let text = String::from_utf8_lossy(&replay.stdout);
    assert!(text.contains("case 3: seed "), "{text}");
    assert!(text.contains("outcome: "), "{text}");

    let run = Command::new(EXE)
        .args([
            "gltf",
            "--load-only",
            "--seconds",
            "2",
            "--jobs",
            "1",
            "--seed",
            "5",
            "--corpus",
        ])
        .arg(scenes())
        .arg("--out")
        .arg(dir.join("findings"))
        .output()
        .expect("short run");
    let text = String::from_utf8_lossy(&run.stdout);
    // Exit 1 means the run found something: still a working fuzzer.
    assert!(matches!(run.status.code(), Some(0 | 1)), "{text}");
    let summary = text.lines().last().unwrap_or("");
    assert!(
        summary.contains(" cases in ") && summary.contains("clean errors"),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// Runs cases 0 to `cases - 1` of `seed` over the vendored scenes with `extra` arguments,
/// and requires that none is a finding.
fn fixed_run_finds_nothing(name: &str, extra: &[&str], cases: u32, seed: u32) {
    let dir = scratch(name);
    let (cases, seed) = (cases.to_string(), seed.to_string());
    let run = Command::new(EXE)
        .arg("gltf")
        .args(extra)
        .args([
            "--cases", &cases, "--jobs", "2", "--seed", &seed, "--corpus",
        ])
        .arg(scenes())
        .arg("--out")
        .arg(dir.join("findings"))
        .output()
        .expect("fixed run");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(
        run.status.success(),
        "findings (saved under {}):\n{text}",
        dir.display()
    );
    assert!(text.contains(&format!("{cases} cases in ")), "{text}");
    let _ = std::fs::remove_dir_all(dir);
}

/// The bounded run `make test` makes: a fixed seed's first cases over the vendored scenes,
/// loaded only, every one a clean error or a loaded scene (about a minute on two cores).
#[test]
fn fixed_cases_find_nothing() {
    fixed_run_finds_nothing("fixed", &["--load-only"], 1200, 1);
}

/// A few fixed cases rendered as the fuzzer renders what loads: every method at a small
/// size, frames finite, exact on the reference (a few seconds a case).
#[test]
fn fixed_cases_render_right() {
    fixed_run_finds_nothing("rendered", &[], 48, 2);
}
