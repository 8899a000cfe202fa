use super::{measure, metrics_json, open_renderer, stage_text, Expected};
use crate::Size;
use std::path::Path;
use std::process::ExitCode;
use translucid::metrics;

pub fn run(
    (scene_spec, scene_args): (&str, crate::SceneArgs),
    method: &str,
    threshold: f32,
    method_args: crate::MethodArgs,
    size: Size,
    output: Option<&Path>,
    json: bool,
) -> translucid::Result<ExitCode> {
    let scene = super::load_scene(scene_spec, scene_args)?;
    let mut renderer = open_renderer(&scene, method, threshold, method_args, size)?;
    // Every method against the exact answer: how far it is from right, threshold included.
    let against = Expected::Reference;
    let measured = measure(&mut renderer, &scene, &against)?;
    let (frame, m, reference_s) = (
        &measured.frame,
        &measured.metrics,
        measured.expected_seconds,
    );
    if let Some(path) = output {
        let heat = metrics::heat_map(&frame.image, &measured.expected)?;
        metrics::side_by_side(&[&frame.image, &measured.expected, &heat]).save_png(path)?;
    }
    if json {
        let mut fields = metrics_json(m);
        fields.extend(
            [
                ("scene", serde_json::json!(scene_spec)),
                ("method", serde_json::json!(method)),
                ("threshold", serde_json::json!(threshold)),
                (
                    "wavelet",
                    super::wavelet_json(method, method_args, super::renderer_storage(&renderer)),
                ),
                ("width", serde_json::json!(size.width)),
                ("height", serde_json::json!(size.height)),
                ("reference_seconds", serde_json::json!(reference_s)),
                ("tail_fragments", serde_json::json!(frame.tail_fragments)),
                ("unpeeled_pixels", serde_json::json!(frame.unpeeled_pixels)),
            ]
            .map(|(k, v)| (k.to_string(), v)),
        );
        println!("{}", serde_json::Value::Object(fields));
    } else {
        println!(
            "{scene_spec} with {method} at {}x{} against {}:",
            size.width,
            size.height,
            against.description()
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
        if frame.tail_fragments > 0 {
            println!(
                "  unsorted    {} fragments past the node budget",
                frame.tail_fragments
            );
        }
        if frame.unpeeled_pixels > 0 {
            println!(
                "  unpeeled    {} pixels with more layers than the passes",
                frame.unpeeled_pixels
            );
        }
        println!("  GPU time    {}", stage_text(&frame.stages));
        println!("  reference   {reference_s:.2} s on the CPU");
        if let Some(path) = output {
            println!("wrote {} (method | reference | error)", path.display());
        }
    }
    // A NaN or infinite pixel is never a close match, whatever the other figures say.
    if m.non_finite > 0 {
        eprintln!(
            "translucid: {} pixels are NaN or infinite in the frame or the reference",
            m.non_finite
        );
        return Ok(ExitCode::FAILURE);
    }
    Ok(ExitCode::SUCCESS)
}
