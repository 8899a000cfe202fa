//! What a new renderer costs on a device where another one lives: the hitch a C context
//! pays when an asset is created or a view of a new size appears. For each scene and
//! method, three renderers are made one after another, each while the previous one is
//! alive, and the time to make each and draw its first two frames is printed.
//!
//! `cargo run --release -p translucid --example new_renderer -- spheres path/to/scene.gltf`

use std::time::Instant;
use translucid::gpu::{Gpu, GpuOptions};
use translucid::methods::MethodKind;
use translucid::renderer::Renderer;

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
        }
    }
    Ok(())
}
