//! The C API from C and C++: compiles the example host, the C tests and the C++ wrapper test
//! with strict warnings against the library cargo just built, runs them on the Vulkan device
//! with validation on, then runs the C programs again under AddressSanitizer and UBSan.
//!
//! Needs `cc` and `g++` (Debian: gcc, g++; `scripts/install-deps.sh` installs them).

use std::path::{Path, PathBuf};
use std::process::Command;

const C_FLAGS: &[&str] = &["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"];
const CXX_FLAGS: &[&str] = &["-std=c++17", "-Wall", "-Wextra", "-Werror", "-pedantic"];
const SANITIZE: &[&str] = &[
    "-g",
    "-fsanitize=address,undefined",
    "-fno-sanitize-recover=all",
    "-fno-omit-frame-pointer",
];

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The example engine (`examples-c/engine.c`): the frame loop example and the host-device
/// tests run on it.
fn engine() -> PathBuf {
    repo().join("examples-c/engine.c")
}

/// What the host-device tests add to the engine: their checks and shared scenes.
fn checks() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/c/checks.c")
}

/// The directory holding the `libtranslucid_ffi.so` built with this test binary.
fn library_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("test executable path");
    let deps = exe
        .parent()
        .expect("test executable directory")
        .to_path_buf();
    for dir in [deps.clone(), deps.join("..")] {
        if dir.join("libtranslucid_ffi.so").exists() {
            return dir;
        }
    }
    panic!(
        "libtranslucid_ffi.so not found next to {}: is crate-type still cdylib in \
         crates/translucid-ffi/Cargo.toml?",
        exe.display()
    );
}

fn out_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("c_api")
        .join(name);
    std::fs::create_dir_all(&dir).expect("create the test's output directory");
    dir
}

/// Compiles `sources` into `output` with `compiler` and `flags`, linking the library (and
/// `libs` after it).
fn compile(compiler: &str, flags: &[&str], sources: &[PathBuf], output: &Path, libs: &[&str]) {
    let lib = library_dir();
    let result = Command::new(compiler)
        .args(flags)
        .arg(format!("-I{}", repo().join("include").display()))
        .arg(format!("-I{}", repo().join("bindings/cpp").display()))
        .arg(format!("-I{}", repo().join("examples-c").display()))
        .args(sources)
        .arg("-o")
        .arg(output)
        .arg(format!("-L{}", lib.display()))
        .arg("-ltranslucid_ffi")
        .arg(format!("-Wl,-rpath,{}", lib.display()))
        .arg("-lm")
        .args(libs)
        .output()
        .unwrap_or_else(|e| {
            panic!("cannot run {compiler} ({e}): install gcc and g++ (scripts/install-deps.sh)")
        });
    assert!(
        result.status.success(),
        "{compiler} {} failed:\n{}",
        sources[0].display(),
        String::from_utf8_lossy(&result.stderr)
    );
}

/// Runs a compiled program with validation on (synchronization validation too, except under
/// the sanitizers, where the layer's own allocations count as leaks); fails the test with
/// its output otherwise.
fn run(program: &Path, args: &[&Path], sanitized: bool) -> String {
    let mut command = Command::new(program);
    // cargo's LD_LIBRARY_PATH also lists target/<profile>, where an older
    // libtranslucid_ffi.so from `cargo build` may sit; it would win over the rpath.
    command.env("LD_LIBRARY_PATH", library_dir());
    command.args(args).env("TRANSLUCID_VALIDATION", "1");
    if sanitized {
        command
            .env(
                "ASAN_OPTIONS",
                "detect_leaks=1:abort_on_error=0:exitcode=23",
            )
            .env("UBSAN_OPTIONS", "print_stacktrace=1:halt_on_error=1");
    } else {
        command.env("TRANSLUCID_SYNC_VALIDATION", "1");
    }
    let result = command.output().expect("run the compiled program");
    let output = format!(
        "{}{}",
        String::from_utf8_lossy(&result.stdout),
        String::from_utf8_lossy(&result.stderr)
    );
    assert!(
        result.status.success(),
        "{} {}failed ({}):\n{output}",
        program.display(),
        if sanitized { "under ASan/UBSan " } else { "" },
        result.status
    );
    output
}

struct Program {
    name: &'static str,
    /// The program's source, then the sources it shares with others.
    sources: Vec<PathBuf>,
    /// Linked besides translucid.
    libs: &'static [&'static str],
}

fn c_programs() -> Vec<Program> {
    let tests = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/c");
    vec![
        Program {
            name: "example",
            sources: vec![repo().join("examples-c/example.c")],
            libs: &[],
        },
        // The engine's frame loop example: host-device mode, 2 frames in flight.
        Program {
            name: "frame_loop",
            sources: vec![repo().join("examples-c/frame_loop.c"), engine()],
            libs: &["-lvulkan"],
        },
        Program {
            name: "misuse",
            sources: vec![tests.join("misuse.c")],
            libs: &[],
        },
        // Two threads in calls on one context at once: refused, never let in.
        Program {
            name: "threads",
            sources: vec![tests.join("threads.c")],
            libs: &["-lpthread"],
        },
        Program {
            name: "render",
            sources: vec![tests.join("render.c")],
            libs: &[],
        },
        // An engine with its own Vulkan device, in host-device mode.
        Program {
            name: "host",
            sources: vec![tests.join("host.c"), engine(), checks()],
            libs: &["-lvulkan"],
        },
        // The same engine's frame loop: frames in flight, views, moving meshes, projections.
        Program {
            name: "frames",
            sources: vec![tests.join("frames.c"), engine(), checks()],
            libs: &["-lvulkan"],
        },
    ]
}

#[test]
fn c_programs_pass_with_validation() {
    for program in c_programs() {
        let dir = out_dir(program.name);
        let binary = dir.join(program.name);
        compile("cc", C_FLAGS, &program.sources, &binary, program.libs);
        let output = run(&binary, &[&dir], false);
        if program.name == "example" {
            for method in ["blend", "exact"] {
                let png = dir.join(format!("example-{method}.png"));
                assert!(
                    png.exists() || !output.contains(method),
                    "the example did not write {}:\n{output}",
                    png.display()
                );
            }
            assert!(dir.join("example-blend.png").exists(), "{output}");
        }
        if program.name == "frame_loop" {
            for method in ["exact", "blend"] {
                let png = dir.join(format!("frame_loop-{method}.png"));
                let image = image::open(&png)
                    .unwrap_or_else(|e| panic!("{}: {e}\n{output}", png.display()))
                    .to_rgba8();
                assert_eq!(image.dimensions(), (480, 270), "{}", png.display());
                assert!(
                    output.contains(&format!("{method}: median record")),
                    "{output}"
                );
                // Each frame beside the yardstick, the engine's own blend of its draws.
                let summary = output
                    .split(&format!("{method}: median record"))
                    .nth(1)
                    .unwrap_or_default();
                let ratio: f64 = summary
                    .split("(x")
                    .nth(1)
                    .and_then(|r| r.split(' ').next())
                    .and_then(|r| r.parse().ok())
                    .unwrap_or_else(|| panic!("no ratio to the engine's blend:\n{output}"));
                assert!(ratio.is_finite() && ratio > 0.0, "{output}");
            }
            // The engine counts the layer's errors (and prints each as VALIDATION: ...).
            assert!(
                output.contains("frame_loop: 0 validation messages")
                    && !output.contains("VALIDATION:")
                    && !output.contains("Validation Error"),
                "{output}"
            );
            // The loop was prepared with its images' formats: in stereo with 3 frames in
            // flight, no frame builds a pipeline, the first, the streamed pane's and the
            // resized ones included.
            let frames: Vec<&str> = output
                .lines()
                .filter(|l| l.trim_start().starts_with("frame") && l.contains("record"))
                .collect();
            assert!(frames.len() > 4, "{output}");
            for line in &frames {
                assert!(!line.contains("pipelines"), "{line}\n{output}");
            }
            assert!(output.contains("stereo frames"), "{output}");
            // The next level prepared in the background while the loop went on, for each
            // method, and its pane streamed in once ready.
            assert_eq!(
                output
                    .matches("pipelines built in the background over")
                    .count(),
                2,
                "{output}"
            );
            assert_eq!(
                output.matches("a lit pane streamed in").count(),
                2,
                "{output}"
            );
            // The frames of the dynamic resolution build and allocate nothing.
            let resized = output.split("a dynamic resolution from here on").skip(1);
            assert_eq!(resized.clone().count(), 2, "{output}");
            for part in resized {
                let frames = part.split("median record").next().unwrap_or(part);
                assert!(!frames.contains(", built"), "{output}");
            }
        }
    }
}

#[test]
fn c_programs_pass_under_address_sanitizer() {
    let keep_modules = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/c/keep_modules.c");
    for program in c_programs() {
        let dir = out_dir(&format!("{}-asan", program.name));
        let binary = dir.join(program.name);
        let flags: Vec<&str> = C_FLAGS.iter().chain(SANITIZE).copied().collect();
        compile(
            "cc",
            &flags,
            &[
                program.sources.as_slice(),
                std::slice::from_ref(&keep_modules),
            ]
            .concat(),
            &binary,
            program.libs,
        );
        run(&binary, &[&dir], true);
    }
}

#[test]
fn cpp_wrapper_compiles_and_works() {
    let dir = out_dir("cpp");
    let binary = dir.join("wrapper");
    let source = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/cpp/wrapper.cpp");
    compile("g++", CXX_FLAGS, &[source], &binary, &[]);
    run(&binary, &[], false);
}

/// The wrapper on an engine's own device: RAII frames in flight, completed or abandoned
/// (tests/cpp/host_frames.cpp on the example engine, with tests/c/checks.c), with validation
/// and then under the
/// sanitizers; and a frame destroyed in flight stops the program with a message.
#[test]
fn cpp_wrapper_frames_in_flight() {
    let tests = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests");
    let keep_modules = tests.join("c/keep_modules.c");
    for sanitized in [false, true] {
        let dir = out_dir(if sanitized {
            "cpp-host-asan"
        } else {
            "cpp-host"
        });
        let extra: &[&str] = if sanitized { SANITIZE } else { &[] };
        let c_flags: Vec<&str> = C_FLAGS
            .iter()
            .chain(extra)
            .chain(&["-c"])
            .copied()
            .collect();
        let mut objects = Vec::new();
        for (source, object) in [(engine(), "engine.o"), (checks(), "checks.o")] {
            let object = dir.join(object);
            compile_object(&c_flags, &source, &object);
            objects.push(object);
        }
        if sanitized {
            let keep = dir.join("keep_modules.o");
            compile_object(&c_flags, &keep_modules, &keep);
            objects.push(keep);
        }
        let binary = dir.join("host_frames");
        let flags: Vec<&str> = CXX_FLAGS.iter().chain(extra).copied().collect();
        let sources = [vec![tests.join("cpp/host_frames.cpp")], objects].concat();
        compile("g++", &flags, &sources, &binary, &["-lvulkan"]);
        let output = run(&binary, &[], sanitized);
        assert!(
            output.contains("0 failed, 0 validation messages"),
            "{output}"
        );
        if !sanitized {
            let dropped = Command::new(&binary)
                .arg("drop")
                .env("LD_LIBRARY_PATH", library_dir())
                .output()
                .expect("run the compiled program");
            let stderr = String::from_utf8_lossy(&dropped.stderr);
            assert!(
                !dropped.status.success() && stderr.contains("destroyed while in flight"),
                "a Frame dropped in flight must stop the program ({}):\n{}{stderr}",
                dropped.status,
                String::from_utf8_lossy(&dropped.stdout)
            );
        }
    }
}

/// Compiles one C source into an object file (`flags` end in `-c`).
fn compile_object(flags: &[&str], source: &Path, object: &Path) {
    let result = Command::new("cc")
        .args(flags)
        .arg(format!("-I{}", repo().join("include").display()))
        .arg(format!("-I{}", repo().join("examples-c").display()))
        .arg(source)
        .arg("-o")
        .arg(object)
        .output()
        .unwrap_or_else(|e| panic!("cannot run cc ({e}): install gcc (scripts/install-deps.sh)"));
    assert!(
        result.status.success(),
        "cc {} failed:\n{}",
        source.display(),
        String::from_utf8_lossy(&result.stderr)
    );
}

/// The README's C snippets, one after another in a function with the engine's objects
/// declared, compile and link cleanly under the test flags (`-Wall -Wextra -Werror
/// -pedantic`).
#[test]
fn readme_c_snippets_compile_cleanly() {
    let readme = std::fs::read_to_string(repo().join("README.md")).expect("read the README");
    let mut body = String::new();
    let mut in_c = false;
    for line in readme.lines() {
        match (in_c, line) {
            (false, "```c") => in_c = true,
            (true, "```") => in_c = false,
            (true, l) if l.starts_with("#include") => {}
            (true, l) => {
                body.push_str(l);
                body.push('\n');
            }
            _ => {}
        }
    }
    assert!(
        body.contains("translucid_frame_record"),
        "no C snippets found"
    );
    let dir = out_dir("readme");
    let source = dir.join("readme.c");
    std::fs::write(
        &source,
        format!(
            "#include <stdio.h>\n#include \"translucid.h\"\n\
             int main(void) {{\n\
             VkInstance instance = VK_NULL_HANDLE;\n\
             VkPhysicalDevice gpu = VK_NULL_HANDLE;\n\
             VkDevice device = VK_NULL_HANDLE;\n\
             uint32_t family = 0;\n\
             VkPhysicalDeviceFeatures enabled_features = {{0}};\n\
             uint32_t extension_count = 0;\n\
             const char *const *extensions = NULL;\n\
             VkCommandBuffer cmd = VK_NULL_HANDLE;\n\
             VkImage colour = VK_NULL_HANDLE, depth = VK_NULL_HANDLE;\n\
             VkImageLayout current = VK_IMAGE_LAYOUT_GENERAL;\n\
             VkImageLayout wanted_after = VK_IMAGE_LAYOUT_GENERAL;\n\
             {body}\nreturn 0;\n}}\n"
        ),
    )
    .expect("write the snippets");
    compile("cc", C_FLAGS, &[source], &dir.join("readme"), &["-lvulkan"]);
}

#[test]
fn header_compiles_alone_as_c_and_cpp() {
    let dir = out_dir("header");
    let source = dir.join("header_only.c");
    std::fs::write(
        &source,
        "#include \"translucid.h\"\n#include \"translucid.h\"\n\
         int main(void) { return translucid_version() == TRANSLUCID_HEADER_VERSION ? 0 : 1; }\n",
    )
    .expect("write the header test");
    compile(
        "cc",
        C_FLAGS,
        std::slice::from_ref(&source),
        &dir.join("header_c"),
        &[],
    );
    let cpp = dir.join("header_only.cpp");
    std::fs::copy(&source, &cpp).expect("copy the header test");
    compile("g++", CXX_FLAGS, &[cpp], &dir.join("header_cpp"), &[]);
    run(&dir.join("header_c"), &[], false);
}

/// The C API fuzzer (`tests/c/fuzz_calls.c`) on a fixed set of cases, under AddressSanitizer
/// and UBSan with validation on: random call sequences with random and broken arguments,
/// each call held to its documented code; then other cases on four threads at once, each
/// with contexts of its own; then cases on an engine's device (`fuzz_host.c`), frames
/// recorded into its command buffers over images of random formats and layouts, on two
/// threads. About a minute and a half here; `make fuzz` runs it for as long as asked, with a
/// fresh seed.
#[test]
fn c_api_fuzzer_keeps_the_contract_on_fixed_cases() {
    let tests = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/c");
    let dir = out_dir("fuzz_calls");
    let binary = dir.join("fuzz_calls");
    // C11 for `_Thread_local`: each thread's cases draw from their own stream.
    let flags: Vec<&str> = C_FLAGS
        .iter()
        .map(|&f| if f == "-std=c99" { "-std=c11" } else { f })
        .chain(SANITIZE.iter().copied())
        .chain(["-pthread"])
        .collect();
    compile(
        "cc",
        &flags,
        &[
            tests.join("fuzz_calls.c"),
            tests.join("fuzz_host.c"),
            engine(),
            checks(),
            tests.join("keep_modules.c"),
        ],
        &binary,
        &["-lvulkan", "-pthread"],
    );
    let runs: [&[&str]; 3] = [
        &["--seed", "1", "--cases", "40"],
        &["--seed", "2", "--cases", "16", "--threads", "4"],
        &[
            "--seed",
            "3",
            "--cases",
            "12",
            "--threads",
            "2",
            "--host-device",
        ],
    ];
    for args in runs {
        let mut command = Command::new(&binary);
        command
            .args(args)
            .env("LD_LIBRARY_PATH", library_dir())
            .env("TRANSLUCID_VALIDATION", "1")
            .env(
                "ASAN_OPTIONS",
                "detect_leaks=1:abort_on_error=0:exitcode=23",
            )
            .env("UBSAN_OPTIONS", "print_stacktrace=1:halt_on_error=1");
        let result = command.output().expect("run the C API fuzzer");
        let stdout = String::from_utf8_lossy(&result.stdout);
        let stderr = String::from_utf8_lossy(&result.stderr);
        // The last lines: the case that failed and why (stderr lists every case it started).
        let tail: Vec<&str> = stderr.lines().rev().take(40).collect();
        assert!(
            result.status.success() && stdout.contains("every call kept the contract"),
            "the C API fuzzer ({}) failed ({}):\n{stdout}\n{}",
            args.join(" "),
            result.status,
            tail.into_iter().rev().collect::<Vec<_>>().join("\n")
        );
    }
}
