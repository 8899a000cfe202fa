//! Engines find translucid with pkg-config or CMake: the files in `examples-c/` are installed
//! into a temporary prefix with the library cargo just built, and the C example is built
//! against that prefix both ways (and run once, through pkg-config's flags).
//!
//! Needs `cc`, `pkg-config` and `cmake` (Debian: gcc, pkg-config, cmake;
//! `scripts/install-deps.sh` installs them).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The directory holding the `libtranslucid_ffi.so` built with this test binary.
fn library_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("test executable path");
    let deps = exe.parent().expect("test executable directory");
    [deps.to_path_buf(), deps.join("..")]
        .into_iter()
        .find(|d| d.join("libtranslucid_ffi.so").exists())
        .unwrap_or_else(|| panic!("libtranslucid_ffi.so not found next to {}", exe.display()))
}

/// A fresh prefix laid out as an install would be: include/, lib/, lib/pkgconfig/,
/// lib/cmake/translucid/.
fn install(name: &str) -> PathBuf {
    let prefix = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("packaging")
        .join(name);
    let _ = std::fs::remove_dir_all(&prefix);
    let cmake_dir = prefix.join("lib/cmake/translucid");
    for dir in [
        prefix.join("include"),
        prefix.join("lib/pkgconfig"),
        cmake_dir.clone(),
    ] {
        std::fs::create_dir_all(dir).expect("create the prefix");
    }
    let copy = |from: PathBuf, to: PathBuf| {
        std::fs::copy(&from, &to)
            .unwrap_or_else(|e| panic!("copy {} to {}: {e}", from.display(), to.display()));
    };
    copy(
        repo().join("include/translucid.h"),
        prefix.join("include/translucid.h"),
    );
    copy(
        library_dir().join("libtranslucid_ffi.so"),
        prefix.join("lib/libtranslucid_ffi.so"),
    );
    copy(
        repo().join("examples-c/cmake/translucidConfig.cmake"),
        cmake_dir.join("translucidConfig.cmake"),
    );
    let pc = std::fs::read_to_string(repo().join("examples-c/translucid.pc.in"))
        .expect("read examples-c/translucid.pc.in")
        .replace("@PREFIX@", &prefix.display().to_string())
        .replace("@VERSION@", env!("CARGO_PKG_VERSION"));
    std::fs::write(prefix.join("lib/pkgconfig/translucid.pc"), pc).expect("write translucid.pc");
    prefix
}

fn run(command: &mut Command, what: &str) -> Output {
    let output = command
        .output()
        .unwrap_or_else(|e| panic!("cannot run {what} ({e}): run scripts/install-deps.sh"));
    assert!(
        output.status.success(),
        "{what} failed ({}):\n{}{}",
        output.status,
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

fn pkg_config(prefix: &Path, args: &[&str]) -> String {
    let out = run(
        Command::new("pkg-config")
            .args(args)
            .arg("translucid")
            .env("PKG_CONFIG_PATH", prefix.join("lib/pkgconfig")),
        "pkg-config",
    );
    String::from_utf8_lossy(&out.stdout).trim().to_string()
}

#[test]
fn example_builds_and_runs_with_pkg_config() {
    let prefix = install("pkg-config");
    assert_eq!(
        pkg_config(&prefix, &["--modversion"]),
        env!("CARGO_PKG_VERSION"),
        "translucid.pc's version"
    );
    let flags = pkg_config(&prefix, &["--cflags", "--libs"]);
    assert!(
        flags.contains(&format!("-L{}/lib", prefix.display())),
        "pkg-config --libs does not point into the prefix: {flags}"
    );
    let binary = prefix.join("example");
    run(
        Command::new("cc")
            .args(["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"])
            .arg(repo().join("examples-c/example.c"))
            .arg("-o")
            .arg(&binary)
            .args(flags.split_whitespace())
            .arg("-lm"),
        "cc with pkg-config's flags",
    );
    let out_dir = prefix.join("out");
    run(
        Command::new(&binary)
            .arg(&out_dir)
            .env("LD_LIBRARY_PATH", prefix.join("lib"))
            .env("TRANSLUCID_VALIDATION", "1"),
        "the example built with pkg-config",
    );
    assert!(out_dir.join("example-blend.png").exists());
}

#[test]
fn example_builds_with_the_cmake_package() {
    let prefix = install("cmake");
    let build = prefix.join("build");
    let configure = run(
        Command::new("cmake")
            .arg("-S")
            .arg(repo().join("examples-c"))
            .arg("-B")
            .arg(&build)
            .arg(format!("-DCMAKE_PREFIX_PATH={}", prefix.display())),
        "cmake (configure)",
    );
    let log = String::from_utf8_lossy(&configure.stdout);
    let config = prefix.join("lib/cmake/translucid/translucidConfig.cmake");
    assert!(
        log.contains(&format!("translucid: package config {}", config.display())),
        "CMake did not use the installed package config:\n{log}"
    );
    run(
        Command::new("cmake").arg("--build").arg(&build),
        "cmake --build",
    );
    for example in ["example", "frame_loop"] {
        assert!(
            build.join(example).exists(),
            "no {example} in {}",
            build.display()
        );
    }
}
