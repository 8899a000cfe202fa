use super::{open_renderer, stage_text};
use crate::Size;
use std::path::Path;

pub fn run(
    scene: &str,
    method: &str,
    threshold: f32,
    wavelet: crate::WaveletArgs,
    size: Size,
    output: &Path,
) -> translucid::Result<()> {
    let scene = translucid::scene::load(scene)?;
    let mut renderer = open_renderer(&scene, method, threshold, wavelet, size)?;
    let frame = renderer.render(false)?;
    frame.image.save_png(output)?;
    println!("wrote {}", output.display());
    println!("GPU time: {}", stage_text(&frame.stages));
    Ok(())
}
