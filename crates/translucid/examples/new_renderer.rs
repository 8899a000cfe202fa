//! What a new renderer costs on a device where another one lives: the hitch a C context
//! pays when an asset is created or a view of a new size appears. For each scene and
//! method: three renderers made one after another, each uploading the scene while the
//! previous one is alive; one sharing the last one's uploads at another size; and one over
//! those uploads extended by a copy of its smallest transparent mesh (as when the engine
//! creates one). Each line
//! gives the time to make the renderer and draw its first two frames.
//!
//! `cargo run --release -p translucid --example new_renderer -- spheres path/to/scene.gltf`

use std::sync::Arc;
use std::time::Instant;
use translucid::gpu::{Gpu, GpuOptions};
use translucid::methods::{MethodKind, MethodOptions};
use translucid::renderer::{FrameShape, Renderer};

fn ms(since: Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}

fn main() -> translucid::Result<()> {
    let gpu = Gpu::new(&GpuOptions::from_env())?;
    for path in std::env::args().skip(1) {
        let scene = translucid::scene::load(&path)?;
        for method in [MethodKind::Exact, MethodKind::Wavelet, MethodKind::Blend] {
            let mut previous: Option<Renderer> = None;
            for round in 0..3 {
                let started = start(&gpu);
                let mut renderer = Renderer::new(&gpu, &scene, method, 1280, 720)?;
                let what = format!("{round}, uploading the scene");
                report(&gpu, &path, method, &what, started, &mut renderer)?;
                // The next renderer is made while this one lives, as in the C API.
                previous.replace(renderer);
            }
            let Some(last) = previous.as_ref() else {
                continue;
            };
            let shape = FrameShape {
                width: 960,
                height: 540,
                frames_in_flight: 1,
            };
            let options = MethodOptions::default();
            let started = start(&gpu);
            let shared = last.resident().clone();
            let mut renderer = Renderer::sharing(&gpu, shared, &scene, method, shape, &options)?;
            report(
                &gpu,
                &path,
                method,
                "sharing the uploads, 960x540",
                started,
                &mut renderer,
            )?;
            let mut grown = scene.clone();
            // The smallest transparent mesh, copied: an asset streamed in.
            let smallest = (0..scene.transparent.len())
                .min_by_key(|&i| scene.meshes[scene.transparent[i].mesh].positions.len());
            if let Some(i) = smallest {
                grown
                    .meshes
                    .push(scene.meshes[scene.transparent[i].mesh].clone());
                grown.transparent[i].mesh = scene.meshes.len();
            }
            let started = start(&gpu);
            let Some(extended) = last.resident().extended(&gpu, &grown)? else {
                println!("{path} {method:?}: no room to extend the uploads");
                continue;
            };
            let shape = FrameShape {
                width: 1280,
                height: 720,
                ..shape
            };
            let mut renderer =
                Renderer::sharing(&gpu, Arc::new(extended), &grown, method, shape, &options)?;
            report(
                &gpu,
                &path,
                method,
                "over the uploads and one more mesh",
                started,
                &mut renderer,
            )?;
        }
    }
    Ok(())
}

/// When a renderer began to be made, and the device's pipelines then.
struct Started {
    at: Instant,
    pipelines: u64,
}

fn start(gpu: &Gpu) -> Started {
    Started {
        at: Instant::now(),
        pipelines: gpu.pipelines_created(),
    }
}

/// Prints the time since `started` (the renderer made) and of its first two frames, and the
/// pipelines compiled since.
fn report(
    gpu: &Gpu,
    path: &str,
    method: MethodKind,
    what: &str,
    started: Started,
    renderer: &mut Renderer,
) -> translucid::Result<()> {
    let made = ms(started.at);
    let started_frame = Instant::now();
    renderer.render(false)?;
    let first = ms(started_frame);
    let started_frame = Instant::now();
    renderer.render(false)?;
    println!(
        "{path} {method:?} renderer {what}: made in {made:.1} ms, first frame {first:.1} ms, \
         second {:.1} ms, {} pipelines compiled",
        ms(started_frame),
        gpu.pipelines_created() - started.pipelines
    );
    Ok(())
}
