//! One module per subcommand.

pub mod bench;
pub mod compare;
pub mod info;
pub mod render;

use translucid::gpu::{Gpu, GpuOptions};

/// The device chosen by `TRANSLUCID_DEVICE` / `TRANSLUCID_VALIDATION`, named on stderr.
pub fn open_gpu() -> translucid::Result<Gpu> {
    let gpu = Gpu::new(&GpuOptions::from_env())?;
    eprintln!("device: {} ({})", gpu.info().name, gpu.info().kind);
    Ok(gpu)
}

/// A renderer for one scene on the chosen device.
pub fn open_renderer(
    scene: &translucid::scene::Scene,
    method: &str,
    threshold: f32,
    wavelet: crate::WaveletArgs,
    size: crate::Size,
) -> translucid::Result<translucid::renderer::Renderer> {
    let options = options(threshold, wavelet)?;
    let gpu = open_gpu()?;
    translucid::renderer::Renderer::with_options(
        &gpu,
        scene,
        method,
        size.width,
        size.height,
        &options,
    )
}

/// Stage timings as "name 1.234 ms, ..." text.
pub fn stage_text(stages: &[(&str, f64)]) -> String {
    stages
        .iter()
        .map(|(name, ms)| format!("{name} {ms:.3} ms"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Method options from the command line, checked.
pub fn options(
    threshold: f32,
    wavelet: crate::WaveletArgs,
) -> translucid::Result<translucid::methods::MethodOptions> {
    if !(0.0..=1.0).contains(&threshold) {
        return Err(translucid::Error::InvalidScene(format!(
            "--threshold {threshold} is not in [0, 1]"
        )));
    }
    Ok(translucid::methods::MethodOptions {
        threshold,
        rank: wavelet.rank,
        noise: wavelet.noise,
        precision: match wavelet.precision {
            crate::Precision::Half => translucid::methods::wavelet::Precision::Half,
            crate::Precision::Single => translucid::methods::wavelet::Precision::Single,
        },
        storage: match wavelet.storage {
            crate::Storage::Images => translucid::methods::wavelet::Storage::Images,
            crate::Storage::Bins => translucid::methods::wavelet::Storage::Bins,
        },
        ..Default::default()
    })
}

/// The wavelet settings as JSON fields, for the method's output lines.
pub fn wavelet_json(method: &str, wavelet: crate::WaveletArgs) -> serde_json::Value {
    if method != "wavelet" {
        return serde_json::Value::Null;
    }
    serde_json::json!({
        "rank": wavelet.rank.unwrap_or(translucid::methods::wavelet::DEFAULT_RANK),
        "noise": wavelet.noise,
        // Only the images have a storage precision.
        "precision": (wavelet.storage == crate::Storage::Images)
            .then(|| format!("{:?}", wavelet.precision).to_lowercase()),
        "storage": format!("{:?}", wavelet.storage).to_lowercase(),
    })
}
