use super::open_gpu;
use crate::Motion;
use crate::Size;
use indicatif::{ProgressBar, ProgressStyle};
use std::collections::BTreeMap;
use std::time::Instant;
use translucid::renderer::Renderer;
use translucid::scene::{motion::Orbit, FrameInput};

/// Median of the values (upper median for an even count).
fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

struct Result {
    scene: String,
    method: String,
    frames: u32,
    total_ms: f64,
    method_ms: f64,
    stages: Vec<(&'static str, f64)>,
    peak_gpu_bytes: u64,
    fragments: u64,
    /// Triangles left after culling (exact).
    triangles: u64,
    rerenders: u32,
    /// Pipelines the timed frames created, after the warm-up (0 where nothing is rebuilt).
    pipelines_created: u64,
    /// GPU memory the timed frames allocated, after the warm-up.
    bytes_allocated: u64,
    wall_ms: f64,
    /// Median host time per frame in `set_frame` and recording.
    cpu_ms: f64,
}

/// The frame loop a bench times.
pub struct FrameLoop {
    pub size: Size,
    /// Frames timed, after two of warm-up.
    pub frames: u32,
    pub motion: Motion,
}

pub fn run(
    scenes: &[String],
    methods: &[String],
    threshold: f32,
    wavelet: crate::WaveletArgs,
    frame_loop: FrameLoop,
    json: bool,
) -> translucid::Result<()> {
    let FrameLoop {
        size,
        frames,
        motion,
    } = frame_loop;
    let options = super::options(threshold, wavelet)?;
    let frames = frames.max(1);
    let gpu = open_gpu()?;
    // blend is always measured: every ratio is against it, from this same run.
    let mut order: Vec<&str> = vec!["blend"];
    order.extend(methods.iter().map(String::as_str).filter(|m| *m != "blend"));
    let warmup = 2;
    let bar = ProgressBar::new(u64::from(frames + warmup) * (scenes.len() * order.len()) as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} frames  {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut results = Vec::new();
    for spec in scenes {
        let scene = translucid::scene::load(spec)?;
        let orbit = Orbit::new(&scene);
        let mut draws = Vec::new();
        // The frame's host work: the new camera and draws, then recording (and submission).
        let mut next_frame = |renderer: &mut Renderer,
                              index: u32|
         -> translucid::Result<(f64, translucid::renderer::Frame)> {
            let started = Instant::now();
            if motion == Motion::Orbit {
                orbit.transparent(&scene, index, &mut draws);
                renderer.set_frame(&FrameInput {
                    camera: orbit.camera(&scene, index),
                    transparent: &draws,
                    ..scene.frame_input()
                })?;
            }
            let set_ms = started.elapsed().as_secs_f64() * 1e3;
            let frame = renderer.render(false)?;
            Ok((set_ms + frame.record_ms, frame))
        };
        for method in &order {
            bar.set_message(format!("{spec} / {method}"));
            let mut renderer = Renderer::with_options(
                &gpu,
                &scene,
                method.parse()?,
                size.width,
                size.height,
                &options,
            )?;
            // Lavapipe compiles pipelines on first use: warm up before timing.
            for index in 0..warmup {
                next_frame(&mut renderer, index)?;
                bar.inc(1);
            }
            let mut per_stage: BTreeMap<&'static str, Vec<f64>> = BTreeMap::new();
            let mut stage_order = Vec::new();
            let (mut totals, mut method_totals, mut peak) = (Vec::new(), Vec::new(), 0);
            let (mut fragments, mut triangles, mut rerenders, mut pipelines) = (0, 0, 0, 0);
            let (mut walls, mut cpu, mut allocated) = (Vec::new(), Vec::new(), 0);
            for index in warmup..warmup + frames {
                let (cpu_ms, frame) = next_frame(&mut renderer, index)?;
                cpu.push(cpu_ms);
                allocated += frame.bytes_allocated;
                for (name, ms) in &frame.stages {
                    if !stage_order.contains(name) {
                        stage_order.push(*name);
                    }
                    per_stage.entry(name).or_default().push(*ms);
                }
                totals.push(frame.stages.iter().map(|(_, ms)| ms).sum());
                method_totals.push(frame.method_ms());
                peak = peak.max(frame.peak_gpu_bytes);
                fragments = frame.fragments;
                triangles = frame.triangles;
                rerenders += frame.rerenders;
                pipelines += frame.pipelines_created;
                walls.push(frame.wall_ms);
                bar.inc(1);
            }
            results.push(Result {
                scene: spec.clone(),
                method: method.to_string(),
                frames,
                total_ms: median(totals),
                method_ms: median(method_totals),
                stages: stage_order
                    .iter()
                    .map(|s| (*s, median(per_stage.remove(s).unwrap_or_default())))
                    .collect(),
                peak_gpu_bytes: peak,
                fragments,
                triangles,
                rerenders,
                pipelines_created: pipelines,
                bytes_allocated: allocated,
                wall_ms: median(walls),
                cpu_ms: median(cpu),
            });
        }
    }
    bar.finish_and_clear();
    for r in results.iter().filter(|r| methods.contains(&r.method)) {
        let blend = results
            .iter()
            .find(|b| b.scene == r.scene && b.method == "blend");
        let ratio = r.method_ms / blend.map_or(f64::NAN, |b| b.method_ms);
        let wall_ratio = r.wall_ms / blend.map_or(f64::NAN, |b| b.wall_ms);
        if json {
            let stages: serde_json::Map<String, serde_json::Value> = r
                .stages
                .iter()
                .map(|(n, ms)| (n.to_string(), serde_json::json!(ms)))
                .collect();
            let line = serde_json::json!({
                "scene": r.scene,
                "method": r.method,
                "threshold": threshold,
                "wavelet": super::wavelet_json(&r.method, wavelet),
                "fragments": r.fragments,
                "triangles": r.triangles,
                "rerenders": r.rerenders,
                "wall_ms": r.wall_ms,
                "wall_ratio_to_blend": wall_ratio,
                "width": size.width,
                "height": size.height,
                "frames": r.frames,
                "median_ms": r.total_ms,
                "method_ms": r.method_ms,
                "stages": stages,
                "ratio_to_blend": ratio,
                "peak_gpu_bytes": r.peak_gpu_bytes,
                "pipelines_created": r.pipelines_created,
                "bytes_allocated": r.bytes_allocated,
                "cpu_record_ms": r.cpu_ms,
                "motion": format!("{motion:?}").to_lowercase(),
            });
            println!("{line}");
        } else {
            println!(
                "{:<40} {:<8} total {:>9.3} ms  method {:>9.3} ms  x{:.2} blend  \
                 frame wall {:>9.3} ms  x{:.2} blend  CPU record {:.3} ms  peak {:.1} MB  \
                 pipelines created {}  bytes allocated {}",
                r.scene,
                r.method,
                r.total_ms,
                r.method_ms,
                ratio,
                r.wall_ms,
                wall_ratio,
                r.cpu_ms,
                r.peak_gpu_bytes as f64 / (1 << 20) as f64,
                r.pipelines_created,
                r.bytes_allocated
            );
            println!("{:<40} {}", "", super::stage_text(&r.stages));
        }
    }
    Ok(())
}
