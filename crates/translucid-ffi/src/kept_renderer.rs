//! One renderer kept across a context's frames. A frame that moves the camera, the light or
//! the draws, or changes the background, takes the kept renderer as it is
//! (`Renderer::set_frame`: nothing rebuilt, no shader compiled); a frame that draws other
//! meshes or materials, or asks for another method, size or setting, gets a new one.

use crate::frame::{translucid_frame_info, FrameInput};
use crate::result::{Failure, FfiResult};
use translucid::gpu::Gpu;
use translucid::renderer::Renderer;

/// A renderer and the assets key of the frames it draws.
pub struct KeptRenderer {
    key: Vec<u64>,
    renderer: Renderer,
}

impl KeptRenderer {
    pub fn renderer_mut(&mut self) -> &mut Renderer {
        &mut self.renderer
    }
}

/// The words that decide whether a renderer can draw a frame: method, size, settings, and
/// the mesh, material and layer of each draw in order (which fixes the scene's assets and
/// their indices). Cameras, lights, transforms and the background are the frame's own.
fn assets_key(info: &translucid_frame_info) -> FfiResult<Vec<u64>> {
    let mut key = vec![
        u64::from(info.method),
        u64::from(info.width),
        u64::from(info.height),
        u64::from(info.wavelet_coefficients),
        u64::from(info.wavelet_noise.to_bits()),
        u64::from(info.wavelet_storage),
        u64::from(info.exact_threshold.to_bits()),
    ];
    let count = usize::try_from(info.draw_count).map_err(|_| Failure::size("too many draws"))?;
    for d in crate::cast::try_slice(info.draws, count, "draws")? {
        key.extend([d.mesh.id, d.material.id, u64::from(d.layer)]);
    }
    Ok(key)
}

/// The renderer for the frame `info` describes (built as `input`): the kept one, set to this
/// frame, when it draws the same assets with the same settings, else a new one that starts
/// from the buffer sizes the last one learned. After an error nothing is kept.
pub(crate) fn renderer_for<'k>(
    kept: &'k mut Option<KeptRenderer>,
    gpu: &Gpu,
    input: &FrameInput,
    info: &translucid_frame_info,
) -> FfiResult<&'k mut Renderer> {
    let key = assets_key(info)?;
    let renderer = match kept.take() {
        Some(k) if k.key == key => {
            let mut renderer = k.renderer;
            renderer.set_frame(&input.scene.frame_input())?;
            renderer
        }
        previous => {
            // Free the last renderer before making the next.
            let options = match previous {
                Some(k) if k.renderer.method_name() == input.method.name() => {
                    k.renderer.learned_options(&input.options)
                }
                _ => input.options.clone(),
            };
            Renderer::with_options(
                gpu,
                &input.scene,
                input.method.kind(),
                info.width,
                info.height,
                &options,
            )?
        }
    };
    Ok(&mut kept.insert(KeptRenderer { key, renderer }).renderer)
}
