use super::{open_renderer, stage_text};
use crate::Size;
use std::path::Path;
use translucid::{metrics, reference};

pub fn run(
    scene_spec: &str,
    method: &str,
    threshold: f32,
    wavelet: crate::WaveletArgs,
    size: Size,
    output: Option<&Path>,
    json: bool,
) -> translucid::Result<()> {
    let scene = translucid::scene::load(scene_spec)?;
    let mut renderer = open_renderer(&scene, method, threshold, wavelet, size)?;
    let frame = renderer.render(true)?;
    let opaque = frame
        .opaque
        .as_ref()
        .expect("render(true) reads the opaque layer back");
    let started = std::time::Instant::now();
    let expected = reference::render(&scene, opaque)?;
    let reference_s = started.elapsed().as_secs_f64();
    let m = metrics::compare(&frame.image, &expected)?;
    if let Some(path) = output {
        let heat = metrics::heat_map(&frame.image, &expected)?;
        metrics::side_by_side(&[&frame.image, &expected, &heat]).save_png(path)?;
    }
    if json {
        let value = serde_json::json!({
            "scene": scene_spec,
            "method": method,
            "threshold": threshold,
            "wavelet": super::wavelet_json(method, wavelet),
            "width": size.width,
            "height": size.height,
            "max_error": m.max_error,
            "rmse": m.rmse,
            "psnr": if m.psnr.is_finite() { serde_json::json!(m.psnr) } else { serde_json::json!("inf") },
            "pixels_over": m.pixels_over,
            "share_over": m.share_over,
            "reference_seconds": reference_s,
        });
        println!("{value}");
    } else {
        println!(
            "{scene_spec} with {method} at {}x{} against the CPU reference:",
            size.width, size.height
        );
        println!(
            "  max error   {:.4} ({:.1}/255)",
            m.max_error,
            m.max_error * 255.0
        );
        println!("  RMSE        {:.5}", m.rmse);
        println!("  PSNR        {:.2} dB", m.psnr);
        println!(
            "  over 2/255  {} pixels ({:.3} %)",
            m.pixels_over,
            m.share_over * 100.0
        );
        println!("  GPU time    {}", stage_text(&frame.stages));
        println!("  reference   {reference_s:.2} s on the CPU");
        if let Some(path) = output {
            println!("wrote {} (method | reference | error)", path.display());
        }
    }
    Ok(())
}
