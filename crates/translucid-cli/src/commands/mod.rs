//! One module per subcommand.

pub mod bench;
pub mod compare;
pub mod conformance;
pub mod info;
pub mod render;
pub mod sweep;

use std::sync::OnceLock;
use translucid::gpu::{Gpu, GpuOptions};
use translucid::methods::wavelet::{model::Model, Settings};
use translucid::methods::{wboit, MethodOptions};
use translucid::metrics::{self, Metrics};
use translucid::renderer::{Frame, Renderer};
use translucid::scene::gltf::ImportOptions;
use translucid::scene::Scene;
use translucid::{reference, Image, OpaqueLayer};

/// The device chosen by `TRANSLUCID_DEVICE` / `TRANSLUCID_VALIDATION`, named on stderr.
pub fn open_gpu() -> translucid::Result<Gpu> {
    let gpu = open_gpu_quietly()?;
    eprintln!("device: {} ({})", gpu.info().name, gpu.info().kind);
    Ok(gpu)
}

/// [`open_gpu`] without naming the device.
pub fn open_gpu_quietly() -> translucid::Result<Gpu> {
    Gpu::new(&GpuOptions::from_env())
}

/// How every command imports glTF files (`--allow-dir`), set once from the command line.
static IMPORT_OPTIONS: OnceLock<ImportOptions> = OnceLock::new();

pub fn set_import_options(options: ImportOptions) {
    // Set once, before any command runs; a second call would be a bug here, not input.
    let _ = IMPORT_OPTIONS.set(options);
}

pub fn import_options() -> &'static ImportOptions {
    IMPORT_OPTIONS.get_or_init(ImportOptions::default)
}

/// The scene `spec` names (a generated name, `hairball:100k`, or a glTF path), drawn as
/// `args` say.
pub fn load_scene(spec: &str, args: crate::SceneArgs) -> translucid::Result<Scene> {
    let scene = translucid::scene::load_with(spec, import_options())?;
    match args.blend_alpha {
        Some(alpha) => scene.opaque_as_transparent(alpha),
        None => Ok(scene),
    }
}

pub fn open_renderer(
    scene: &translucid::scene::Scene,
    method: &str,
    threshold: f32,
    method_args: crate::MethodArgs,
    size: crate::Size,
) -> translucid::Result<translucid::renderer::Renderer> {
    let options = options(threshold, method_args)?;
    let gpu = open_gpu()?;
    translucid::renderer::Renderer::with_options(
        &gpu,
        scene,
        method.parse()?,
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
    method_args: crate::MethodArgs,
) -> translucid::Result<translucid::methods::MethodOptions> {
    if !(0.0..=1.0).contains(&threshold) {
        return Err(translucid::Error::InvalidOption(format!(
            "--threshold {threshold} is not in [0, 1]"
        )));
    }
    Ok(translucid::methods::MethodOptions {
        exact: translucid::methods::exact::ExactOptions {
            threshold,
            ..Default::default()
        },
        wavelet: translucid::methods::wavelet::WaveletOptions {
            rank: method_args.rank,
            noise: method_args.noise,
            precision: match method_args.precision {
                crate::Precision::Half => translucid::methods::wavelet::Precision::Half,
                crate::Precision::Single => translucid::methods::wavelet::Precision::Single,
            },
            storage: method_args.storage.map(|s| match s {
                crate::Storage::Images => translucid::methods::wavelet::Storage::Images,
                crate::Storage::Bins => translucid::methods::wavelet::Storage::Bins,
            }),
        },
        depth_peeling: translucid::methods::depth_peeling::DepthPeelingOptions {
            passes: method_args.passes,
            ..Default::default()
        },
        bins: translucid::methods::bins::BinOptions {
            declared: method_args.declare.unwrap_or_default(),
            prepared: method_args.declare.is_some(),
            ..Default::default()
        },
        ..Default::default()
    })
}

/// The wavelet settings as JSON fields, for the method's output lines. `storage` is where the
/// coefficients lived: the renderer's ([`renderer_storage`]), which `--storage` names or the
/// device's profile picks.
pub fn wavelet_json(
    method: &str,
    method_args: crate::MethodArgs,
    storage: translucid::methods::wavelet::Storage,
) -> serde_json::Value {
    use translucid::methods::wavelet::Storage;
    if method != "wavelet" {
        return serde_json::Value::Null;
    }
    serde_json::json!({
        "rank": method_args.rank.unwrap_or(translucid::methods::wavelet::DEFAULT_RANK),
        "noise": method_args.noise,
        // Only the images have a storage precision.
        "precision": (storage == Storage::Images)
            .then(|| format!("{:?}", method_args.precision).to_lowercase()),
        "storage": storage.name(),
    })
}

/// Where `renderer` keeps the wavelet coefficients (the storage its last frame ran on): the
/// option's, else the device profile's, or the images after a fallback.
pub fn renderer_storage(renderer: &Renderer) -> translucid::methods::wavelet::Storage {
    renderer
        .learned_options(&MethodOptions::default())
        .wavelet
        .storage
        .unwrap_or(translucid::methods::wavelet::Storage::Bins)
}

/// An image computed on the CPU that a method's frame is measured against.
#[derive(Clone, Copy, Debug)]
pub enum Expected {
    /// The exact reference: every fragment, composited in depth order.
    Reference,
    /// The reference with the exact method's early stop at this transmittance.
    ReferenceUntil(f32),
    /// The wavelet method's CPU model, with the settings the method runs with: [`measure`]
    /// takes the storage from the renderer (the device's, unless an option names one, or the
    /// images a crowded frame fell back to).
    WaveletModel(Settings),
    /// The wboit method's CPU model.
    WboitModel,
}

impl Expected {
    /// What `method` promises to match within 2/255, or `None` for `blend`, which is right
    /// only when the draws happen to be sorted.
    pub fn promised(method: &str, options: &MethodOptions) -> translucid::Result<Option<Self>> {
        Ok(Some(match method {
            "exact" if options.exact.threshold > 0.0 => {
                Self::ReferenceUntil(options.exact.threshold)
            }
            "exact" | "linked_list" | "depth_peeling" => Self::Reference,
            // Checked here, before any file is loaded; the storage is the renderer's.
            "wavelet" => Self::WaveletModel(Settings::from_options(
                &options.wavelet,
                translucid::gpu::Profile::CpuDriver,
            )?),
            "wboit" => Self::WboitModel,
            "blend" => return Ok(None),
            // The renderer's own message, before any file is loaded.
            other => {
                return Err(translucid::Error::UnknownMethod(
                    other.to_string(),
                    translucid::methods::NAMES.join(", "),
                ))
            }
        }))
    }

    /// What it is, for "... against {description}".
    pub fn description(&self) -> String {
        match self {
            Self::Reference => "the CPU reference".into(),
            Self::ReferenceUntil(t) => {
                format!("the CPU reference stopping under transmittance {t}")
            }
            Self::WaveletModel(_) | Self::WboitModel => "its CPU model".into(),
        }
    }

    /// The expected image of `scene` over `opaque`.
    pub fn render(&self, scene: &Scene, opaque: &OpaqueLayer) -> translucid::Result<Image> {
        match *self {
            Self::Reference => reference::render(scene, opaque),
            Self::ReferenceUntil(t) => reference::render_until(scene, opaque, t),
            Self::WaveletModel(settings) => {
                Model::new(settings, scene, opaque.width, opaque.height).render(scene, opaque)
            }
            Self::WboitModel => wboit::model::render(scene, opaque),
        }
    }
}

/// One frame of a method next to the image expected of it.
pub struct Measured {
    pub frame: Frame,
    pub expected: Image,
    pub metrics: Metrics,
    /// CPU time taken by the expected image.
    pub expected_seconds: f64,
}

/// Renders one frame, then the expected image from that frame's own opaque layer (so that
/// only the transparent layer can differ), and compares them.
pub fn measure(
    renderer: &mut Renderer,
    scene: &Scene,
    expected: &Expected,
) -> translucid::Result<Measured> {
    let frame = renderer.render(true)?;
    let opaque = frame
        .opaque
        .as_ref()
        .expect("render(true) reads the opaque layer back");
    let expected = match *expected {
        // The storage the frame ran on.
        Expected::WaveletModel(settings) => Expected::WaveletModel(Settings {
            storage: renderer_storage(renderer),
            ..settings
        }),
        other => other,
    };
    let started = std::time::Instant::now();
    let expected = expected.render(scene, opaque)?;
    let expected_seconds = started.elapsed().as_secs_f64();
    let metrics = metrics::compare(&frame.image, &expected)?;
    Ok(Measured {
        frame,
        expected,
        metrics,
        expected_seconds,
    })
}

/// The measures every JSON report gives, as fields to add to its object. JSON has no
/// infinity: an infinite measure is the string "inf" or "-inf" (identical images have a PSNR
/// of "inf"; a frame with NaN or infinite pixels a max_error and rmse of "inf" and a PSNR of
/// "-inf"), and a NaN is null.
pub fn metrics_json(m: &Metrics) -> serde_json::Map<String, serde_json::Value> {
    let value = serde_json::json!({
        "max_error": number_json(m.max_error),
        "rmse": number_json(m.rmse),
        "psnr": number_json(m.psnr),
        "pixels_over": m.pixels_over,
        "share_over": m.share_over,
        "non_finite_pixels": m.non_finite,
    });
    match value {
        serde_json::Value::Object(fields) => fields,
        _ => serde_json::Map::new(),
    }
}

fn number_json(value: f32) -> serde_json::Value {
    match value {
        f32::INFINITY => serde_json::json!("inf"),
        f32::NEG_INFINITY => serde_json::json!("-inf"),
        _ => serde_json::json!(value),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame with NaN pixels once reported `"psnr": "inf", "rmse": 0.0`, a perfect score.
    #[test]
    fn json_of_a_frame_with_nan_pixels_reads_worst_not_perfect() {
        let reference = Image::filled(2, 2, glam::Vec4::ONE);
        let nan = Image::filled(2, 2, glam::Vec4::new(f32::NAN, 0.0, 0.0, 1.0));
        let fields = metrics_json(&metrics::compare(&nan, &reference).expect("same size"));
        assert_eq!(fields["psnr"], "-inf");
        assert_eq!(fields["rmse"], "inf");
        assert_eq!(fields["max_error"], "inf");
        assert_eq!(fields["non_finite_pixels"], 4);
        let same = metrics_json(&metrics::compare(&reference, &reference).expect("same size"));
        assert_eq!(same["psnr"], "inf");
        assert_eq!(same["rmse"], 0.0);
    }
}
