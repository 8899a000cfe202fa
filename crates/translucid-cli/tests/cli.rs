//! The `translucid` binary as users run it: JSON shapes, exit codes, messages.

use std::process::Command;

fn translucid(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_translucid"))
        .args(args)
        .env("TRANSLUCID_VALIDATION", "1")
        .output()
        .expect("run translucid");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn json_lines(stdout: &str) -> Vec<serde_json::Value> {
    stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("not JSON ({e}): {l}")))
        .collect()
}

#[test]
fn compare_json_has_the_documented_fields() {
    let (ok, stdout, stderr) = translucid(&[
        "compare", "layers", "--method", "blend", "--size", "97x61", "--json",
    ]);
    assert!(ok, "compare failed: {stderr}");
    let v = &json_lines(&stdout)[0];
    for key in [
        "scene",
        "method",
        "width",
        "height",
        "max_error",
        "rmse",
        "psnr",
        "pixels_over",
        "share_over",
    ] {
        assert!(v.get(key).is_some(), "compare --json lacks {key}: {v}");
    }
    assert_eq!(v["width"], 97);
    assert_eq!(v["method"], "blend");
}

#[test]
fn bench_json_has_one_line_per_scene_and_method() {
    let (ok, stdout, stderr) = translucid(&[
        "bench", "layers", "boxes", "--method", "blend", "--size", "64x48", "--frames", "2",
        "--json",
    ]);
    assert!(ok, "bench failed: {stderr}");
    let lines = json_lines(&stdout);
    assert_eq!(lines.len(), 2, "{stdout}");
    for v in &lines {
        for key in [
            "scene",
            "method",
            "frames",
            "median_ms",
            "whole_pass_ms",
            "native_blend_ms",
            "ratio_to_native_blend",
            "frames_in_flight",
            "overflowed_frames",
            "dispatches",
            "stages",
            "ratio_to_blend",
            "wall_ms",
            "wall_ratio_to_blend",
            "peak_gpu_bytes",
            "peak_over_blend_bytes",
            "pipelines_created",
            "bytes_allocated",
            "cpu_record_ms",
            "motion",
        ] {
            assert!(v.get(key).is_some(), "bench --json lacks {key}: {v}");
        }
        // The default frame loop moves the camera and draws: still nothing built or grown.
        assert_eq!(v["motion"], "orbit", "{v}");
        assert_eq!(v["pipelines_created"], 0, "after warm-up: {v}");
        assert_eq!(v["bytes_allocated"], 0, "after warm-up: {v}");
        assert!(
            v["stages"]["blend"].as_f64().is_some_and(|ms| ms >= 0.0),
            "{v}"
        );
        assert!(
            (v["ratio_to_blend"].as_f64().expect("ratio") - 1.0).abs() < 1e-9,
            "blend over blend is 1: {v}"
        );
        // The whole pass, everything recorded into the engine's frame, over the yardstick's.
        let whole = v["whole_pass_ms"].as_f64().expect("whole pass");
        let native = v["native_blend_ms"].as_f64().expect("native_blend");
        assert!(whole > 0.0 && native > 0.0, "{v}");
        let ratio = v["ratio_to_native_blend"].as_f64().expect("ratio");
        assert!((ratio - whole / native).abs() < 1e-9, "{v}");
        // blend draws straight into the engine's images: its whole pass is its one stage.
        let stages: f64 = v["stages"]
            .as_object()
            .expect("stages")
            .values()
            .filter_map(serde_json::Value::as_f64)
            .sum();
        assert!((whole - stages).abs() < 1e-6, "{v}");
        assert_eq!(v["stages"].as_object().map(|s| s.len()), Some(1), "{v}");
        assert!(v["peak_gpu_bytes"].as_u64().is_some_and(|b| b > 0));
        assert_eq!(v["peak_over_blend_bytes"], 0, "blend over itself: {v}");
    }
}

#[test]
fn render_writes_a_png() {
    let path =
        std::env::temp_dir().join(format!("translucid-cli-render-{}.png", std::process::id()));
    let p = path.to_str().expect("utf-8 temp path");
    let (ok, stdout, stderr) = translucid(&["render", "spheres", "--size", "80x60", "-o", p]);
    assert!(ok, "render failed: {stderr}");
    assert!(
        stdout.contains("wrote") && stdout.contains("GPU time"),
        "{stdout}"
    );
    let bytes = std::fs::read(&path).expect("png written");
    assert_eq!(&bytes[1..4], b"PNG");
    let _ = std::fs::remove_file(path);
}

/// `--warm` (what `make demo` passes) reports a second frame's stage times, not the first's,
/// which include building pipelines.
#[test]
fn render_warm_reports_a_warm_frame() {
    let path = std::env::temp_dir().join(format!("translucid-cli-warm-{}.png", std::process::id()));
    let p = path.to_str().expect("utf-8 temp path");
    let (ok, stdout, stderr) =
        translucid(&["render", "spheres", "--size", "80x60", "-o", p, "--warm"]);
    assert!(ok, "render failed: {stderr}");
    assert!(stdout.contains("first frame: "), "{stdout}");
    assert!(
        stdout.contains("GPU time of a warm frame: ") && stdout.contains("raster"),
        "{stdout}"
    );
    let _ = std::fs::remove_file(path);
}

#[test]
fn bad_input_fails_with_a_clear_message() {
    let cases: &[(&[&str], &str)] = &[
        (
            &["render", "/no/such/scene.gltf", "-o", "/tmp/x.png"],
            "scene",
        ),
        (
            &["render", "no-such-generated-scene"],
            "no-such-generated-scene",
        ),
        (&["render", "layers", "--size", "0x10"], "0x10"),
        (&["render", "layers", "--size", "100000x10"], "100000x10"),
        (&["render", "layers", "--method", "magic"], "magic"),
        (&["render", "layers", "--size", "12"], "WIDTHxHEIGHT"),
    ];
    for (args, expected) in cases {
        let (ok, _, stderr) = translucid(args);
        assert!(!ok, "{args:?} should fail");
        assert!(
            stderr.contains(expected),
            "{args:?}: message should name {expected:?}: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
    }
}

/// The vendored scenes, in the repository root.
fn vendored_scenes() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes")
}

/// The `.gltf` and `.glb` files under `folder`, counted apart from the tool's own search.
fn count_gltf(folder: &std::path::Path) -> usize {
    std::fs::read_dir(folder)
        .expect("readable folder")
        .map(|entry| entry.expect("entry").path())
        .map(|path| {
            if path.is_dir() {
                count_gltf(&path)
            } else {
                let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
                usize::from(matches!(ext.to_ascii_lowercase().as_str(), "gltf" | "glb"))
            }
        })
        .sum()
}

/// An empty folder of its own for one test.
fn temp_folder(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("translucid-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp folder");
    dir
}

/// `conformance --json`'s one document, and its rows by path.
fn conformance_json(args: &[&str]) -> (bool, serde_json::Value, String) {
    let mut all = vec!["conformance", "--size", "160x90", "--json"];
    all.extend_from_slice(args);
    let (ok, stdout, stderr) = translucid(&all);
    let doc = serde_json::from_str(&stdout)
        .unwrap_or_else(|e| panic!("not one JSON document ({e}): {stdout}\n{stderr}"));
    (ok, doc, stderr)
}

fn rows(doc: &serde_json::Value) -> &Vec<serde_json::Value> {
    doc["files"].as_array().expect("files array")
}

#[test]
fn conformance_passes_on_the_vendored_scenes() {
    let scenes = vendored_scenes();
    let expected_files = count_gltf(&scenes);
    assert!(
        expected_files > 0,
        "no vendored scenes in {}",
        scenes.display()
    );
    let (ok, doc, stderr) = conformance_json(&[scenes.to_str().expect("utf-8 path")]);
    assert!(ok, "conformance failed: {doc}\n{stderr}");
    assert_eq!(doc["method"], "exact");
    assert_eq!(doc["against"], "the CPU reference");
    assert_eq!(doc["size"]["width"], 160);
    assert_eq!(doc["size"]["height"], 90);
    assert_eq!(rows(&doc).len(), expected_files, "{doc}");
    for row in rows(&doc) {
        assert_eq!(row["pass"], true, "{row}");
        assert!(row["error"].is_null(), "{row}");
        assert!(
            row["max_error"].as_f64().is_some_and(|e| e <= 2.0 / 255.0),
            "{row}"
        );
        for key in ["path", "rmse", "psnr", "pixels_over", "share_over"] {
            assert!(!row[key].is_null(), "row lacks {key}: {row}");
        }
        // Relative to the folder argument.
        let path = row["path"].as_str().expect("path");
        assert!(scenes.join(path).is_file(), "{path}");
    }
    assert_eq!(doc["passed"], expected_files);
    assert_eq!(doc["failed"], 0);
}

/// `--declare` draws with a declared loop's widest shaders: the vendored scenes as right, and
/// an unknown content refused as a usage error.
#[test]
fn conformance_passes_with_every_content_declared() {
    let scenes = vendored_scenes();
    let folder = scenes.to_str().expect("utf-8 path");
    let (ok, doc, stderr) = conformance_json(&[folder, "--declare", "all"]);
    assert!(ok, "conformance failed: {doc}\n{stderr}");
    assert_eq!(doc["failed"], 0, "{doc}");
    assert!(doc["passed"].as_u64().is_some_and(|n| n > 0), "{doc}");
    let (ok, _, stderr) = translucid(&["conformance", folder, "--declare", "textures,glitter"]);
    assert!(
        !ok && stderr.contains("unknown content \"glitter\""),
        "{stderr}"
    );
}

#[test]
fn conformance_reports_a_broken_file_and_goes_on() {
    let dir = temp_folder("conformance-broken");
    std::fs::write(dir.join("broken.gltf"), "{ this is not JSON").expect("write");
    std::fs::copy(
        vendored_scenes().join("AttenuationTest/AttenuationTest.glb"),
        dir.join("good.glb"),
    )
    .expect("copy");
    let (ok, doc, stderr) = conformance_json(&[dir.to_str().expect("utf-8 path")]);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(!ok, "a broken file must fail the run: {doc}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let row = |name: &str| {
        rows(&doc)
            .iter()
            .find(|r| r["path"] == name)
            .unwrap_or_else(|| panic!("no row for {name}: {doc}"))
            .clone()
    };
    let broken = row("broken.gltf");
    assert_eq!(broken["pass"], false, "{broken}");
    assert!(
        broken["error"]
            .as_str()
            .is_some_and(|e| e.contains("broken.gltf")),
        "{broken}"
    );
    let good = row("good.glb");
    assert_eq!(good["pass"], true, "{good}");
    assert!(good["error"].is_null(), "{good}");
    assert_eq!(doc["passed"], 1);
    assert_eq!(doc["failed"], 1);
}

#[test]
fn conformance_without_gltf_files_fails_clearly() {
    let dir = temp_folder("conformance-empty");
    std::fs::write(dir.join("notes.txt"), "no scenes here").expect("write");
    let (ok, stdout, stderr) = translucid(&["conformance", dir.to_str().expect("utf-8 path")]);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(!ok, "no glTF file should fail: {stdout}");
    assert!(
        stderr.contains("no .gltf or .glb file") && stderr.contains("conformance-empty"),
        "{stderr}"
    );
    let (ok, _, stderr) = translucid(&["conformance", "/no/such/folder"]);
    assert!(!ok);
    assert!(stderr.contains("/no/such/folder"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn conformance_holds_wavelet_to_its_cpu_model() {
    let scene = vendored_scenes().join("GlassVaseFlowers/GlassVaseFlowers.glb");
    let scene = scene.to_str().expect("utf-8 path");
    let (ok, doc, stderr) = conformance_json(&["--method", "wavelet", scene]);
    assert!(ok, "wavelet conformance failed: {doc}\n{stderr}");
    assert_eq!(doc["against"], "its CPU model");
    assert_eq!(doc["wavelet"]["rank"], 3);
    let rows = rows(&doc);
    assert_eq!(rows.len(), 1, "{doc}");
    // A file argument is named as given.
    assert_eq!(rows[0]["path"], scene);
    assert_eq!(rows[0]["pass"], true, "{doc}");
}

/// blend is unsorted: the teapot's back faces blend over its front, far off the reference,
/// and the rows say so, but that never fails the run.
#[test]
fn conformance_reports_blend_without_failing_on_its_error() {
    let scene = vendored_scenes().join("utah_teapot/utah_teapot_blend.gltf");
    let (ok, stdout, stderr) = translucid(&[
        "conformance",
        "--method",
        "blend",
        "--size",
        "160x90",
        scene.to_str().expect("utf-8 path"),
    ]);
    assert!(
        ok,
        "blend's image error must not fail the run: {stdout}\n{stderr}"
    );
    assert!(stdout.contains("FAIL"), "{stdout}");
    assert!(
        stdout.contains("1 file, 0 pass, 1 fail: blend at 160x90 against the CPU reference"),
        "{stdout}"
    );
}

/// A sweep prints, per method, its GPU time at every point and the log-log slope, and plots
/// them: over triangles (a sized scene) and over square frame sizes (a scene whose opaque
/// surfaces are blended).
#[test]
fn bench_sweeps_report_slopes_and_write_a_plot() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("sweeps");
    let _ = std::fs::remove_dir_all(&dir);
    for (args, points) in [
        (
            vec!["hairball", "--sweep", "triangles=2k,8k"],
            [2_000.0, 8_000.0],
        ),
        (
            vec!["boxes", "--blend-alpha", "0.5", "--sweep", "size=32,64"],
            [1024.0, 4096.0],
        ),
    ] {
        let plot = dir.join(format!("{}.svg", args[0]));
        let mut all = vec![
            "bench", "--method", "exact", "--size", "64x48", "--frames", "2",
        ];
        all.extend(&args);
        all.extend(["--json", "--plot", plot.to_str().expect("utf-8 path")]);
        let (ok, stdout, stderr) = translucid(&all);
        assert!(ok, "{args:?}: {stderr}");
        let lines = json_lines(&stdout);
        let methods: Vec<&str> = lines.iter().filter_map(|v| v["method"].as_str()).collect();
        assert_eq!(methods, ["blend", "exact"], "{stdout}");
        for v in &lines {
            let xs: Vec<f64> = v["points"]
                .as_array()
                .expect("points")
                .iter()
                .map(|p| {
                    assert!(p["method_ms"].as_f64().is_some_and(|ms| ms > 0.0), "{v}");
                    p["x"].as_f64().expect("x")
                })
                .collect();
            assert_eq!(xs, points, "{v}");
            assert!(v["slope"].as_f64().is_some_and(f64::is_finite), "{v}");
        }
        let svg = std::fs::read_to_string(&plot).expect("the plot was written");
        assert!(
            svg.starts_with("<svg") && svg.contains("exact (slope") && svg.contains("blend"),
            "{}",
            plot.display()
        );
    }
}

#[test]
fn bad_sweeps_and_blend_alphas_are_refused() {
    for (args, says) in [
        (
            vec!["boxes", "--sweep", "triangles=1k,2k"],
            "hairball, particles",
        ),
        (
            vec!["hairball", "--sweep", "triangles=1k"],
            "at least two points",
        ),
        (
            vec!["hairball", "--sweep", "pixels=1,2"],
            "triangles or size",
        ),
        (vec!["hairball", "--sweep", "size=64,x"], "not a count"),
        (vec!["boxes", "--blend-alpha", "0"], "not an alpha"),
        (vec!["hairball:0"], "hairball takes"),
    ] {
        let mut all = vec!["bench", "--frames", "1", "--size", "32x32"];
        all.extend(&args);
        let (ok, _, stderr) = translucid(&all);
        assert!(!ok, "{args:?} was accepted");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
    }
}

/// A frame count the frame counter cannot hold is a usage error: 4294967295 once wrapped
/// it, and bench exited 0 with all-zero times and NaN ratios.
#[test]
fn bench_refuses_frame_counts_out_of_range() {
    for frames in ["4294967295", "100001", "0"] {
        let out = Command::new(env!("CARGO_BIN_EXE_translucid"))
            .args(["bench", "boxes", "--size", "32x32", "--frames", frames])
            .output()
            .expect("run translucid");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{frames}: {stderr}");
        assert!(stderr.contains("1..=100000"), "{frames}: {stderr}");
    }
}

/// Blended opaque surfaces are right with exact, as compare measures it.
#[test]
fn compare_takes_a_blend_alpha() {
    let (ok, stdout, stderr) = translucid(&[
        "compare",
        "boxes",
        "--blend-alpha",
        "0.5",
        "--size",
        "80x60",
        "--json",
    ]);
    assert!(ok, "{stderr}");
    let v = &json_lines(&stdout)[0];
    assert!(
        v["max_error"].as_f64().is_some_and(|e| e <= 2.0 / 255.0),
        "{v}"
    );
}

/// A folder of hostile files: a glTF whose buffer URI leads out of its folder, a pipe named
/// `.gltf` and a link to `/dev/zero` named `.glb`. `conformance` reports each and goes on
/// (the pipe hung it, the link ran it out of memory, the URI was read); `--allow-dir`
/// lets the URI reach the folder it names.
#[cfg(unix)]
#[test]
fn conformance_refuses_files_outside_the_folder_pipes_and_devices() {
    let dir = temp_folder("conformance-hostile");
    let teapot = vendored_scenes().join("utah_teapot");
    let buffer = teapot
        .join("utah_teapot.bin")
        .canonicalize()
        .expect("buffer");
    let json = std::fs::read_to_string(teapot.join("utah_teapot_blend.gltf"))
        .expect("teapot")
        .replace(
            "\"utah_teapot.bin\"",
            &format!("{:?}", buffer.display().to_string()),
        );
    assert!(json.contains(&buffer.display().to_string()));
    std::fs::write(dir.join("teapot.gltf"), json).expect("write");
    let made = Command::new("mkfifo")
        .arg(dir.join("b.gltf"))
        .status()
        .expect("mkfifo");
    assert!(made.success());
    std::os::unix::fs::symlink("/dev/zero", dir.join("z.glb")).expect("symlink");
    let folder = dir.to_str().expect("utf-8 path");

    let (ok, doc, stderr) = conformance_json(&[folder]);
    assert!(!ok, "hostile files must fail the run: {doc}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let error = |name: &str| {
        let row = rows(&doc)
            .iter()
            .find(|r| r["path"] == name)
            .unwrap_or_else(|| panic!("no row for {name}: {doc}"));
        row["error"].as_str().unwrap_or_default().to_string()
    };
    assert!(error("teapot.gltf").contains("outside"), "{doc}");
    assert!(error("b.gltf").contains("not a regular file"), "{doc}");
    assert!(error("z.glb").contains("not a regular file"), "{doc}");

    let allowed = teapot.to_str().expect("utf-8 path");
    let teapot_file = dir.join("teapot.gltf");
    let (ok, doc, stderr) =
        conformance_json(&["--allow-dir", allowed, teapot_file.to_str().expect("utf-8")]);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(ok, "an allowed folder is read: {doc}\n{stderr}");
}
