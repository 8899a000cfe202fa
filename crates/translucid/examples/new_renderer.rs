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
                let pipelines = gpu.pipelines_created();
                let started = Instant::now();
                let mut renderer = Renderer::new(&gpu, &scene, method, 1280, 720)?;
                let made = ms(started);
                let started = Instant::now();
                renderer.render(false)?;
                let first = ms(started);
                let started = Instant::now();
                renderer.render(false)?;
                let second = ms(started);
                println!(
                    "{path} {method:?} renderer {round}: made in {made:.1} ms, first frame \
                     {first:.1} ms, second {second:.1} ms, {} pipelines compiled",
                    gpu.pipelines_created() - pipelines
                );
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
            let started = Instant::now();
            let shared = last.resident().clone();
            let mut renderer = Renderer::sharing(&gpu, shared, &scene, method, shape, &options)?;
            report(
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
            let started = Instant::now();
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

/// Prints the time since `started` (the renderer made) and of its first two frames.
fn report(
    path: &str,
    method: MethodKind,
    what: &str,
    started: Instant,
    renderer: &mut Renderer,
) -> translucid::Result<()> {
    let made = ms(started);
    let started = Instant::now();
    renderer.render(false)?;
    let first = ms(started);
    let started = Instant::now();
    renderer.render(false)?;
    println!(
        "{path} {method:?} renderer {what}: made in {made:.1} ms, first frame {first:.1} ms, \
         second {:.1} ms",
        ms(started)
    );
    Ok(())
}
