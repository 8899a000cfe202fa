//! Compiles every GLSL entry point under `shaders/` to SPIR-V with `glslc`.
//!
//! `shaders/<folder>/<name>.<stage>` becomes `$OUT_DIR/shaders/<folder>/<name>.<stage>.spv`,
//! loaded with `include_bytes!`. `.glsl` files are includes, not entry points: those under
//! `shaders/common/`, a stage folder's own (found beside the stage that includes them), and
//! those this script writes from `src/interface/` (the shader interface, declared once in
//! Rust) into `$OUT_DIR/interface/`.

#[allow(dead_code)]
#[path = "src/interface/mod.rs"]
mod interface;

use std::path::{Path, PathBuf};
use std::process::Command;

const STAGES: &[&str] = &["comp", "vert", "geom", "frag"];

fn main() {
    let manifest = std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    let root = Path::new(&manifest).join("../../shaders");
    let root = root
        .canonicalize()
        .unwrap_or_else(|e| panic!("shader folder {} is missing: {e}", root.display()));
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("shaders");
    println!("cargo:rerun-if-changed={}", root.display());
    let generated = write_interface(&out);

    let glslc = std::env::var("GLSLC").unwrap_or_else(|_| "glslc".into());
    if Command::new(&glslc).arg("--version").output().is_err() {
        panic!(
            "`{glslc}` (the GLSL to SPIR-V compiler) was not found. Install it \
             (Debian/Ubuntu: `apt-get install glslc`, or the Vulkan SDK), or set GLSLC to its path. \
             `make test` and `make demo` install it for you."
        );
    }

    let mut failures = Vec::new();
    for folder in sorted_entries(&root) {
        if !folder.is_dir() {
            continue;
        }
        println!("cargo:rerun-if-changed={}", folder.display());
        let name = folder.file_name().expect("folder name").to_owned();
        if name == "common" {
            for inc in sorted_entries(&folder) {
                println!("cargo:rerun-if-changed={}", inc.display());
            }
            continue;
        }
        let target_dir = out.join(&name);
        std::fs::create_dir_all(&target_dir).expect("create shader output folder");
        for src in sorted_entries(&folder) {
            let ext = src.extension().and_then(|e| e.to_str()).unwrap_or("");
            if !STAGES.contains(&ext) {
                continue;
            }
            println!("cargo:rerun-if-changed={}", src.display());
            let file = src
                .file_name()
                .expect("file name")
                .to_string_lossy()
                .into_owned();
            let spv = target_dir.join(format!("{file}.spv"));
            let result = Command::new(&glslc)
                .args(["--target-env=vulkan1.2", "-O", "-Werror"])
                .arg(format!("-I{}", root.join("common").display()))
                .arg(format!("-I{}", generated.display()))
                .arg(&src)
                .arg("-o")
                .arg(&spv)
                .output()
                .expect("run glslc");
            if !result.status.success() {
                failures.push(format!(
                    "{}:\n{}",
                    src.display(),
                    String::from_utf8_lossy(&result.stderr)
                ));
            }
        }
    }
    if !failures.is_empty() {
        panic!("shader compilation failed:\n{}", failures.join("\n"));
    }
}

fn sorted_entries(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("read {}: {e}", dir.display()))
        .map(|e| e.expect("dir entry").path())
        .collect();
    v.sort();
    v
}

/// Writes the shader interface's includes; the folder they are in.
fn write_interface(out: &Path) -> PathBuf {
    println!("cargo:rerun-if-changed=src/interface");
    let folder = out.with_file_name("interface");
    std::fs::create_dir_all(&folder).expect("create the interface's folder");
    for include in interface::includes() {
        let path = folder.join(include.file);
        let text = interface::glsl(&include);
        // Unchanged files keep their time, so nothing that includes them looks stale.
        if std::fs::read_to_string(&path).ok().as_deref() != Some(text.as_str()) {
            std::fs::write(&path, text).expect("write an interface include");
        }
    }
    folder
}
