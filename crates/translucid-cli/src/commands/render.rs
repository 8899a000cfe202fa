use super::{open_renderer, stage_text};
use crate::Size;
use std::path::Path;
use std::time::Instant;

/// Renders `scene` and writes the image to `output`; with `warm`, renders it once more and
/// reports that frame's stage times, which leave out building pipelines and compiling shaders
/// (with a cold shader cache, most of a first frame's time on lavapipe).
pub fn run(
    (scene, scene_args): (&str, crate::SceneArgs),
    method: &str,
    threshold: f32,
    method_args: crate::MethodArgs,
    size: Size,
    output: &Path,
    warm: bool,
) -> translucid::Result<()> {
    let scene = super::load_scene(scene, scene_args)?;
    let mut renderer = open_renderer(&scene, method, threshold, method_args, size)?;
    let start = Instant::now();
    let frame = renderer.render(false)?;
    let first_ms = start.elapsed().as_secs_f64() * 1000.0;
    frame.image.save_png(output)?;
    println!("wrote {}", output.display());
    if warm {
        let warm_frame = renderer.render(false)?;
        println!("first frame: {first_ms:.0} ms, pipelines and shader compilation included");
        println!(
            "GPU time of a warm frame: {}",
            stage_text(&warm_frame.stages)
        );
    } else {
        println!(
            "GPU time of this first frame (with pipeline and shader compilation; --warm for a \
             warm frame's): {}",
            stage_text(&frame.stages)
        );
    }
    Ok(())
}
