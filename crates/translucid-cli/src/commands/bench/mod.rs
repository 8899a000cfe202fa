//! `translucid bench`: every method's frame loop on an engine's device (`engine.rs`), the
//! methods taking turns frame by frame, each frame's whole pass timed beside the yardstick,
//! `native_blend`, over the same frame.

mod engine;

use super::{open_gpu, open_gpu_quietly};
use crate::Motion;
use crate::Size;
use engine::{EngineFrame, EngineLoop};
use indicatif::{ProgressBar, ProgressStyle};
use std::collections::{BTreeMap, HashMap};
use std::time::Instant;
use translucid::renderer::{FrameShape, HostFrame, Renderer};
use translucid::scene::{motion::Orbit, FrameInput, Scene};
use translucid::OpaqueLayer;

/// Frames the engine keeps in flight: each method's renderer has as many frame slots, which
/// its frames take in turn.
const FRAMES_IN_FLIGHT: u32 = 2;

/// A moving frame's camera and transparent draws.
type FrameChange = (translucid::scene::Camera, Vec<translucid::scene::Draw>);

/// Median of the values (upper median for an even count).
fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// One method's frame loop over one scene, on the bench's engine (`engine.rs`): medians of
/// its timed frames.
pub struct Measured {
    pub scene: String,
    pub method: String,
    pub motion: Motion,
    /// Where the wavelet method's coefficients lived (its renderer's storage).
    wavelet_storage: translucid::methods::wavelet::Storage,
    frames: u32,
    /// GPU time of everything the method recorded into the engine's frame (copies in and out
    /// included): its whole pass.
    whole_ms: f64,
    /// GPU time of the method's own stages.
    pub method_ms: f64,
    /// GPU time of the yardstick, `native_blend`, over the same frame.
    pub native_ms: f64,
    stages: Vec<(&'static str, f64)>,
    peak_gpu_bytes: u64,
    fragments: u64,
    /// Triangles left after culling (the bin methods).
    triangles: u64,
    /// The most any timed frame left out of its order: linked_list's fragments past its
    /// pool, depth_peeling's pixels past its passes (0 when every frame was exact).
    tail_fragments: u64,
    unpeeled_pixels: u64,
    /// Timed frames whose one recording was not all right (the buffers grew after them).
    overflowed_frames: u32,
    /// Compute dispatches the last timed frame recorded.
    dispatches: u64,
    /// Pipelines the timed frames created, after the warm-up (0 where nothing is rebuilt).
    pipelines_created: u64,
    /// GPU memory the timed frames allocated, after the warm-up.
    bytes_allocated: u64,
    /// Host time from submission to completion of the method's frame.
    pub wall_ms: f64,
    /// The same for the yardstick's frame.
    native_wall_ms: f64,
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
    wholes: Vec<f64>,
    method_totals: Vec<f64>,
    natives: Vec<f64>,
    walls: Vec<f64>,
    native_walls: Vec<f64>,
    cpu: Vec<f64>,
    peak: u64,
    fragments: u64,
    triangles: u64,
    tail_fragments: u64,
    unpeeled_pixels: u64,
    overflowed: u32,
    dispatches: u64,
}

/// GPU time of every stage of a frame.
fn whole_pass(frame: &HostFrame) -> f64 {
    frame.stages.iter().map(|(_, ms)| ms).sum()
}

impl Timings {
    fn add(&mut self, cpu_ms: f64, frame: &EngineFrame) {
        let m = &frame.method;
        self.cpu.push(cpu_ms);
        for (name, ms) in &m.stages {
            if !self.stage_order.contains(name) {
                self.stage_order.push(*name);
            }
            self.per_stage.entry(name).or_default().push(*ms);
        }
        self.wholes.push(whole_pass(m));
        self.method_totals.push(m.method_ms);
        self.natives.push(whole_pass(&frame.native));
        self.peak = self.peak.max(m.peak_gpu_bytes);
        self.fragments = m.fragments;
        self.triangles = m.triangles;
        self.tail_fragments = self.tail_fragments.max(m.tail_fragments);
        self.unpeeled_pixels = self.unpeeled_pixels.max(m.unpeeled_pixels);
        self.overflowed += u32::from(m.overflowed);
        self.dispatches = m.dispatches;
        self.walls.push(frame.method_wall_ms);
        self.native_walls.push(frame.native_wall_ms);
    }

    fn result(
        mut self,
        (scene, method, motion): (&str, &str, Motion),
        frames: u32,
        (pipelines_created, bytes_allocated): (u64, u64),
        wavelet_storage: translucid::methods::wavelet::Storage,
    ) -> Measured {
        Measured {
            scene: scene.to_string(),
            method: method.to_string(),
            motion,
            wavelet_storage,
            frames,
            whole_ms: median(self.wholes),
            method_ms: median(self.method_totals),
            native_ms: median(self.natives),
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
            overflowed_frames: self.overflowed,
            dispatches: self.dispatches,
            pipelines_created,
            bytes_allocated,
            wall_ms: median(self.walls),
            native_wall_ms: median(self.native_walls),
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
    // blend is always measured: the ratios to translucid's own blend are from this same run.
    let mut names: Vec<&str> = vec!["blend"];
    names.extend(methods.iter().map(String::as_str).filter(|m| *m != "blend"));
    let mut motions: Vec<Motion> = Vec::new();
    for &m in motion {
        if !motions.contains(&m) {
            motions.push(m);
        }
    }
    // Every (method, motion) pair, on an engine device of its own so that its memory and
    // pipeline counts are its own while they take turns.
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
    let shape = FrameShape {
        width: size.width,
        height: size.height,
        frames_in_flight: FRAMES_IN_FLIGHT,
    };
    let mut results = Vec::new();
    for spec in scenes {
        let scene = super::load_scene(spec, bench.scene_args)?;
        let orbit = Orbit::new(&scene);
        let mut draws = Vec::new();
        // The frame's camera and draws.
        let mut frame_input = |motion: Motion, index: u32| -> Option<FrameChange> {
            if motion == Motion::Orbit {
                orbit.transparent(&scene, index, &mut draws);
                Some((orbit.camera(&scene, index), draws.clone()))
            } else {
                None
            }
        };
        bar.set_message(spec.clone());
        // The engine's opaque pass of each frame, rendered once for every method.
        let layers = opaque_layers(&gpus[0], &scene, size, &motions, warmup + frames, |m, i| {
            frame_input(m, i)
        })?;
        let mut loops = order
            .iter()
            .zip(&gpus)
            .map(|((method, _), gpu)| {
                let kind = method.parse()?;
                EngineLoop::new(gpu.clone(), (size.width, size.height), |host| {
                    Renderer::with_frames_in_flight(
                        host,
                        &scene,
                        kind,
                        shape.width,
                        shape.height,
                        &options,
                        shape.frames_in_flight,
                    )
                })
            })
            .collect::<translucid::Result<Vec<_>>>()?;
        let mut next_frame =
            |run: &mut EngineLoop, motion: Motion, index: u32| -> translucid::Result<_> {
                let started = Instant::now();
                if let Some((camera, draws)) = frame_input(motion, index) {
                    run.renderer.set_frame(&FrameInput {
                        camera,
                        transparent: &draws,
                        ..scene.frame_input()
                    })?;
                }
                let set_ms = started.elapsed().as_secs_f64() * 1e3;
                let layer = &layers[&layer_key(motion, index)];
                let frame = run.frame(layer)?;
                Ok((set_ms + frame.record_ms, frame))
            };
        // The methods take turns frame by frame, so that the machine's drift (other loads,
        // clocks) falls on all of them alike and the ratios compare frames of the same moment.
        // Lavapipe compiles pipelines on first use: warm up before timing.
        for index in 0..warmup {
            for (run, (_, motion)) in loops.iter_mut().zip(&order) {
                next_frame(run, *motion, index)?;
                bar.inc(1);
            }
        }
        let counted: Vec<(u64, u64)> = loops
            .iter()
            .map(|r| (r.host.pipelines_created(), r.host.bytes_allocated()))
            .collect();
        let mut timings: Vec<Timings> = order.iter().map(|_| Timings::default()).collect();
        for index in warmup..warmup + frames {
            for ((run, timing), (_, motion)) in loops.iter_mut().zip(&mut timings).zip(&order) {
                let (cpu_ms, frame) = next_frame(run, *motion, index)?;
                timing.add(cpu_ms, &frame);
                bar.inc(1);
            }
        }
        for (((method, motion), timing), (run, before)) in
            order.iter().zip(timings).zip(loops.iter().zip(counted))
        {
            let built = (
                run.host.pipelines_created() - before.0,
                run.host.bytes_allocated() - before.1,
            );
            let storage = super::renderer_storage(&run.renderer);
            results.push(timing.result((spec, method, *motion), frames, built, storage));
        }
    }
    bar.finish_and_clear();
    Ok(results)
}

/// The opaque layer of each (motion, frame index) the loop draws, rendered on `gpu`: for a
/// moving camera one per frame, for a static one only frame 0's ([`layer_key`]).
fn opaque_layers(
    gpu: &translucid::gpu::Gpu,
    scene: &Scene,
    size: Size,
    motions: &[Motion],
    frames: u32,
    mut frame_input: impl FnMut(Motion, u32) -> Option<FrameChange>,
) -> translucid::Result<HashMap<(Motion, u32), OpaqueLayer>> {
    let mut renderer = Renderer::new(
        gpu,
        scene,
        translucid::methods::MethodKind::Blend,
        size.width,
        size.height,
    )?;
    let mut layers = HashMap::new();
    for &motion in motions {
        for index in 0..frames {
            let key = layer_key(motion, index);
            if layers.contains_key(&key) {
                continue;
            }
            if let Some((camera, draws)) = frame_input(motion, index) {
                renderer.set_frame(&FrameInput {
                    camera,
                    transparent: &draws,
                    ..scene.frame_input()
                })?;
            }
            let layer = renderer
                .render(true)?
                .opaque
                .ok_or_else(|| translucid::Error::HostFrame("no opaque layer read back".into()))?;
            layers.insert(key, layer);
        }
    }
    Ok(layers)
}

/// Where frame `index` of `motion` finds its opaque layer.
fn layer_key(motion: Motion, index: u32) -> (Motion, u32) {
    match motion {
        Motion::Static => (motion, 0),
        Motion::Orbit => (motion, index),
    }
}

/// One line (or JSON object) per scene and method of `bench.methods`: its whole pass over
/// `native_blend`'s, and its own stages over translucid's blend's.
fn print_results(results: &[Measured], bench: &Bench<'_>, json: bool) {
    let (methods, threshold, method_args) = (bench.methods, bench.threshold, bench.method_args);
    let size = bench.frame_loop.size;
    for r in results.iter().filter(|r| methods.contains(&r.method)) {
        let blend = results
            .iter()
            .find(|b| b.scene == r.scene && b.method == "blend" && b.motion == r.motion);
        let native_ratio = r.whole_ms / r.native_ms;
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
                "wavelet": super::wavelet_json(&r.method, method_args, r.wavelet_storage),
                "fragments": r.fragments,
                "triangles": r.triangles,
                "tail_fragments": r.tail_fragments,
                "unpeeled_pixels": r.unpeeled_pixels,
                "overflowed_frames": r.overflowed_frames,
                "dispatches": r.dispatches,
                "frames_in_flight": FRAMES_IN_FLIGHT,
                "whole_pass_ms": r.whole_ms,
                "native_blend_ms": r.native_ms,
                "ratio_to_native_blend": native_ratio,
                "wall_ms": r.wall_ms,
                "native_blend_wall_ms": r.native_wall_ms,
                "wall_ratio_to_blend": wall_ratio,
                "width": size.width,
                "height": size.height,
                "frames": r.frames,
                "median_ms": r.whole_ms,
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
                "{:<40} {:<8} {motion}  whole pass {:>9.3} ms  x{:.2} native_blend ({:.3} ms)  \
                 method {:>9.3} ms  x{:.2} blend  frame wall {:>9.3} ms  CPU record {:.3} ms  \
                 peak {:.1} MB ({:+.1} over blend)  dispatches {}  pipelines created {}  \
                 bytes allocated {}",
                r.scene,
                r.method,
                r.whole_ms,
                native_ratio,
                r.native_ms,
                r.method_ms,
                ratio,
                r.wall_ms,
                r.cpu_ms,
                r.peak_gpu_bytes as f64 / (1 << 20) as f64,
                over_blend.map_or(f64::NAN, |b| b as f64 / (1 << 20) as f64),
                r.dispatches,
                r.pipelines_created,
                r.bytes_allocated
            );
            println!("{:<40} {}", "", super::stage_text(&r.stages));
            if r.overflowed_frames > 0 {
                println!(
                    "{:<40} not right: {} frames overflowed on their one recording",
                    "", r.overflowed_frames
                );
            }
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
