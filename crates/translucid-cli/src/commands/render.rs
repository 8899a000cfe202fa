use super::{open_gpu, stage_text};
use crate::Size;
use std::path::Path;
use translucid::renderer::Renderer;

pub fn run(scene: &str, method: &str, size: Size, output: &Path) -> translucid::Result<()> {
    let scene = translucid::scene::load(scene)?;
    let gpu = open_gpu()?;
    let mut renderer = Renderer::new(&gpu, &scene, method, size.width, size.height)?;
    let frame = renderer.render(false)?;
    frame.image.save_png(output)?;
    println!("wrote {}", output.display());
    println!("GPU time: {}", stage_text(&frame.stages));
    Ok(())
}
