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
            "stages",
            "ratio_to_blend",
            "wall_ms",
            "wall_ratio_to_blend",
            "peak_gpu_bytes",
        ] {
            assert!(v.get(key).is_some(), "bench --json lacks {key}: {v}");
        }
        assert!(
            v["stages"]["blend"].as_f64().is_some_and(|ms| ms >= 0.0),
            "{v}"
        );
        assert!(
            (v["ratio_to_blend"].as_f64().expect("ratio") - 1.0).abs() < 1e-9,
            "blend over blend is 1: {v}"
        );
        assert!(v["peak_gpu_bytes"].as_u64().is_some_and(|b| b > 0));
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
