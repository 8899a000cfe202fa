use super::{open_gpu, open_gpu_quietly};
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

/// One method's frame loop over one scene: medians of its timed frames.
pub struct Measured {
    pub scene: String,
    pub method: String,
    pub motion: Motion,
    frames: u32,
    total_ms: f64,
    /// GPU time of the method's own stages.
    pub method_ms: f64,
    stages: Vec<(&'static str, f64)>,
    peak_gpu_bytes: u64,
    fragments: u64,
    /// Triangles left after culling (exact).
    triangles: u64,
    /// The most any timed frame left out of its order: linked_list's fragments past its
    /// pool, depth_peeling's pixels past its passes (0 when every frame was exact).
    tail_fragments: u64,
    unpeeled_pixels: u64,
    rerenders: u32,
    /// Pipelines the timed frames created, after the warm-up (0 where nothing is rebuilt).
    pipelines_created: u64,
    /// GPU memory the timed frames allocated, after the warm-up.
    bytes_allocated: u64,
    /// Host time from submission to completion of the whole frame.
    pub wall_ms: f64,
    /// Median host time per frame in `set_frame` and recording.
    cpu_ms: f64,
}

/// The frame loop a bench times.
pub struct FrameLoop {
    pub size: Size,
    /// Frames timed, after two of warm-up.
    pub frames: u32,
    /// Each motion is run with every method, all taking turns.
    pub motion: Vec<Motion>,
}

/// One method's timed frames of one scene.
#[derive(Default)]
struct Timings {
    per_stage: BTreeMap<&'static str, Vec<f64>>,
    stage_order: Vec<&'static str>,
    totals: Vec<f64>,
    method_totals: Vec<f64>,
    walls: Vec<f64>,
    cpu: Vec<f64>,
    peak: u64,
    fragments: u64,
    triangles: u64,
    tail_fragments: u64,
    unpeeled_pixels: u64,
    rerenders: u32,
    pipelines: u64,
    allocated: u64,
}

impl Timings {
    fn add(&mut self, cpu_ms: f64, frame: &translucid::renderer::Frame) {
        self.cpu.push(cpu_ms);
        self.allocated += frame.bytes_allocated;
        for (name, ms) in &frame.stages {
            if !self.stage_order.contains(name) {
                self.stage_order.push(*name);
            }
            self.per_stage.entry(name).or_default().push(*ms);
        }
        self.totals
            .push(frame.stages.iter().map(|(_, ms)| ms).sum());
        self.method_totals.push(frame.method_ms());
        self.peak = self.peak.max(frame.peak_gpu_bytes);
        self.fragments = frame.fragments;
        self.triangles = frame.triangles;
        self.tail_fragments = self.tail_fragments.max(frame.tail_fragments);
        self.unpeeled_pixels = self.unpeeled_pixels.max(frame.unpeeled_pixels);
        self.rerenders += frame.rerenders;
        self.pipelines += frame.pipelines_created;
        self.walls.push(frame.wall_ms);
    }

    fn result(mut self, scene: &str, method: &str, motion: Motion, frames: u32) -> Measured {
        Measured {
            scene: scene.to_string(),
            method: method.to_string(),
            motion,
            frames,
            total_ms: median(self.totals),
            method_ms: median(self.method_totals),
            stages: self
                .stage_order
                .iter()
                .map(|s| (*s, median(self.per_stage.remove(s).unwrap_or_default())))
                .collect(),
            peak_gpu_bytes: self.peak,
            fragments: self.fragments,
            triangles: self.triangles,
            tail_fragments: self.tail_fragments,
            unpeeled_pixels: self.unpeeled_pixels,
            rerenders: self.rerenders,
            pipelines_created: self.pipelines,
            bytes_allocated: self.allocated,
            wall_ms: median(self.walls),
            cpu_ms: median(self.cpu),
        }
    }
}

/// What a bench runs: the methods (blend always too, for the ratios), their settings, how
/// scenes are drawn, and the frame loop.
pub struct Bench<'a> {
    pub methods: &'a [String],
    pub threshold: f32,
    pub method_args: crate::MethodArgs,
    pub scene_args: crate::SceneArgs,
    pub frame_loop: FrameLoop,
}

pub fn run(scenes: &[String], bench: &Bench<'_>, json: bool) -> translucid::Result<()> {
    let results = measure(scenes, bench, bench.frame_loop.size)?;
    print_results(&results, bench, json);
    Ok(())
}

/// Runs the frame loop of every scene at `size`, every method taking turns: blend first,
/// then `bench.methods`, for each motion.
pub fn measure(
    scenes: &[String],
    bench: &Bench<'_>,
    size: Size,
) -> translucid::Result<Vec<Measured>> {
    let methods = bench.methods;
    let FrameLoop { frames, motion, .. } = &bench.frame_loop;
    let options = super::options(bench.threshold, bench.method_args)?;
    let frames = *frames;
    // blend is always measured: every ratio is against it, from this same run.
    let mut names: Vec<&str> = vec!["blend"];
    names.extend(methods.iter().map(String::as_str).filter(|m| *m != "blend"));
    let mut motions: Vec<Motion> = Vec::new();
    for &m in motion {
        if !motions.contains(&m) {
            motions.push(m);
        }
    }
    // Every (method, motion) pair, on a device of its own so that its memory and pipeline
    // counts are its own while they take turns.
    let order: Vec<(&str, Motion)> = motions
        .iter()
        .flat_map(|&m| names.iter().map(move |&n| (n, m)))
        .collect();
    let gpus = order
        .iter()
        .enumerate()
        .map(|(i, _)| {
            if i == 0 {
                open_gpu()
            } else {
                open_gpu_quietly()
            }
        })
        .collect::<translucid::Result<Vec<_>>>()?;
    let warmup = 2;
    let bar = ProgressBar::new(u64::from(frames + warmup) * (scenes.len() * order.len()) as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} frames  {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut results = Vec::new();
    for spec in scenes {
        let scene = super::load_scene(spec, bench.scene_args)?;
        let orbit = Orbit::new(&scene);
        let mut draws = Vec::new();
        // The frame's host work: the new camera and draws, then recording (and submission).
        let mut next_frame = |renderer: &mut Renderer,
                              motion: Motion,
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
        bar.set_message(spec.clone());
        let mut renderers = order
            .iter()
            .zip(&gpus)
            .map(|((method, _), gpu)| {
                Renderer::with_options(
                    gpu,
                    &scene,
                    method.parse()?,
                    size.width,
                    size.height,
                    &options,
                )
            })
            .collect::<translucid::Result<Vec<_>>>()?;
        // The methods take turns frame by frame, so that the machine's drift (other loads,
        // clocks) falls on all of them alike and the ratios compare frames of the same moment.
        // Lavapipe compiles pipelines on first use: warm up before timing.
        for index in 0..warmup {
            for (renderer, (_, motion)) in renderers.iter_mut().zip(&order) {
                next_frame(renderer, *motion, index)?;
                bar.inc(1);
            }
        }
        let mut timings: Vec<Timings> = order.iter().map(|_| Timings::default()).collect();
        for index in warmup..warmup + frames {
            for ((renderer, timing), (_, motion)) in
                renderers.iter_mut().zip(&mut timings).zip(&order)
            {
                let (cpu_ms, frame) = next_frame(renderer, *motion, index)?;
                timing.add(cpu_ms, &frame);
                bar.inc(1);
            }
        }
        for ((method, motion), timing) in order.iter().zip(timings) {
            results.push(timing.result(spec, method, *motion, frames));
        }
    }
    bar.finish_and_clear();
    Ok(results)
}

/// One line (or JSON object) per scene and method of `bench.methods`, with ratios to blend.
fn print_results(results: &[Measured], bench: &Bench<'_>, json: bool) {
    let (methods, threshold, method_args) = (bench.methods, bench.threshold, bench.method_args);
    let size = bench.frame_loop.size;
    for r in results.iter().filter(|r| methods.contains(&r.method)) {
        let blend = results
            .iter()
            .find(|b| b.scene == r.scene && b.method == "blend" && b.motion == r.motion);
        let ratio = r.method_ms / blend.map_or(f64::NAN, |b| b.method_ms);
        let wall_ratio = r.wall_ms / blend.map_or(f64::NAN, |b| b.wall_ms);
        // The method's own memory: its peak over blend's, which holds the same scene and
        // frame targets (each pair runs on a device of its own).
        let over_blend = blend.map(|b| r.peak_gpu_bytes as i64 - b.peak_gpu_bytes as i64);
        // Moving over static from the same run, when both were.
        let over_static = results
            .iter()
            .find(|s| {
                r.motion == Motion::Orbit
                    && s.scene == r.scene
                    && s.method == r.method
                    && s.motion == Motion::Static
            })
            .map(|s| r.wall_ms / s.wall_ms);
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
                "wavelet": super::wavelet_json(&r.method, method_args),
                "fragments": r.fragments,
                "triangles": r.triangles,
                "tail_fragments": r.tail_fragments,
                "unpeeled_pixels": r.unpeeled_pixels,
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
                "peak_over_blend_bytes": over_blend,
                "pipelines_created": r.pipelines_created,
                "bytes_allocated": r.bytes_allocated,
                "cpu_record_ms": r.cpu_ms,
                "motion": format!("{:?}", r.motion).to_lowercase(),
                "moving_over_static_wall": over_static,
            });
            println!("{line}");
        } else {
            let motion = match over_static {
                Some(x) => format!("orbit (x{x:.2} static)"),
                None => format!("{:?}", r.motion).to_lowercase(),
            };
            println!(
                "{:<40} {:<8} {motion}  total {:>9.3} ms  method {:>9.3} ms  x{:.2} blend  \
                 frame wall {:>9.3} ms  x{:.2} blend  CPU record {:.3} ms  peak {:.1} MB \
                 ({:+.1} over blend)  pipelines created {}  bytes allocated {}",
                r.scene,
                r.method,
                r.total_ms,
                r.method_ms,
                ratio,
                r.wall_ms,
                wall_ratio,
                r.cpu_ms,
                r.peak_gpu_bytes as f64 / (1 << 20) as f64,
                over_blend.map_or(f64::NAN, |b| b as f64 / (1 << 20) as f64),
                r.pipelines_created,
                r.bytes_allocated
            );
            println!("{:<40} {}", "", super::stage_text(&r.stages));
            if r.tail_fragments > 0 {
                println!(
                    "{:<40} not exact: {} fragments past the node pool, blended unsorted",
                    "", r.tail_fragments
                );
            }
            if r.unpeeled_pixels > 0 {
                println!(
                    "{:<40} not exact: {} pixels with more layers than the passes",
                    "", r.unpeeled_pixels
                );
            }
        }
    }
}
