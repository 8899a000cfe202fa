use super::{open_gpu, stage_text};
use crate::Size;
use std::path::Path;
use translucid::renderer::Renderer;

pub fn run(
    scene: &str,
    method: &str,
    threshold: f32,
    size: Size,
    output: &Path,
) -> translucid::Result<()> {
    let scene = translucid::scene::load(scene)?;
    let gpu = open_gpu()?;
    let mut renderer = Renderer::with_options(
        &gpu,
        &scene,
        method,
        size.width,
        size.height,
        &super::options(threshold)?,
    )?;
    let frame = renderer.render(false)?;
    frame.image.save_png(output)?;
    println!("wrote {}", output.display());
    println!("GPU time: {}", stage_text(&frame.stages));
    Ok(())
}
