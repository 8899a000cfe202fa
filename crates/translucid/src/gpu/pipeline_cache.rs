//! Compute pipelines kept by their specialization: a frame that needs a variant built before
//! builds nothing, and neither does a renderer made while another on the same device holds
//! the variant (a new size or new assets in the C API, for instance).

#![deny(unsafe_code)]

use super::{BindingKind, ComputePipeline, DescriptorLayout, Gpu};
use crate::interface::specialization::Specialization;
use crate::Result;
use ash::vk;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, Weak};

/// The pipelines of one shader family over one set of descriptor layouts and one push
/// constant size, each built on first use for its (shader, constants) and kept for the
/// owner's life. Every call must pass the same layouts and push size: they are not part of
/// the key here (they are in the device's [`SharedPipelines`]).
pub struct ComputePipelineCache {
    push_bytes: u32,
    built: HashMap<Key, Arc<ComputePipeline>>,
}

/// A shader by its SPIR-V (length and a hash of the words: the same shader may be reached
/// through different addresses), and its constants.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct Key {
    spirv: (usize, u64),
    constants: Specialization,
}

/// A pipeline as the device knows it: the shader and constants, and the definitions of the
/// descriptor layouts and push constants it was made with, so that a renderer whose own
/// (identically defined) layouts differ in handle only binds its sets to it.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct SharedKey {
    shader: Key,
    layouts: Vec<(Vec<BindingKind>, u32)>,
    push_bytes: u32,
}

/// The pipelines alive on a device, by what they were made from. Held weakly: a pipeline
/// lives as long as a renderer holds it (holding it strongly here would keep the device
/// alive through the pipeline's own reference to it).
pub(crate) struct SharedPipelines<K, P>(Mutex<HashMap<K, Weak<P>>>);

impl<K, P> Default for SharedPipelines<K, P> {
    fn default() -> Self {
        Self(Mutex::new(HashMap::new()))
    }
}

impl<K: Eq + std::hash::Hash, P> SharedPipelines<K, P> {
    pub(crate) fn get(&self, key: &K) -> Option<Arc<P>> {
        let map = self.0.lock().unwrap_or_else(|e| e.into_inner());
        map.get(key).and_then(Weak::upgrade)
    }

    /// Every pipeline alive now.
    pub(crate) fn live(&self) -> Vec<Arc<P>> {
        let map = self.0.lock().unwrap_or_else(|e| e.into_inner());
        map.values().filter_map(Weak::upgrade).collect()
    }

    pub(crate) fn insert(&self, key: K, pipeline: &Arc<P>) {
        let mut map = self.0.lock().unwrap_or_else(|e| e.into_inner());
        map.retain(|_, p| p.strong_count() > 0);
        map.insert(key, Arc::downgrade(pipeline));
    }
}

/// The compute pipelines of a device.
pub(crate) type SharedComputePipelines = SharedPipelines<SharedKey, ComputePipeline>;

pub(crate) fn spirv_hash(spirv: &[u8]) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    spirv.hash(&mut h);
    h.finish()
}

impl ComputePipelineCache {
    pub fn new(push_bytes: u32) -> Self {
        Self {
            push_bytes,
            built: HashMap::new(),
        }
    }

    /// The pipeline of `spirv` with `constants`: this cache's,
    /// else one another renderer on the device holds, else built now.
    pub fn get(
        &mut self,
        gpu: &Gpu,
        layouts: &[&DescriptorLayout],
        spirv: &'static [u8],
        constants: &Specialization,
    ) -> Result<Arc<ComputePipeline>> {
        let key = Key {
            spirv: (spirv.len(), spirv_hash(spirv)),
            constants: constants.clone(),
        };
        if let Some(p) = self.built.get(&key) {
            return Ok(p.clone());
        }
        let shared_key = SharedKey {
            shader: key.clone(),
            layouts: layout_definitions(layouts),
            push_bytes: self.push_bytes,
        };
        let p = match gpu.compute_pipelines.get(&shared_key) {
            Some(p) => p,
            None => {
                let p = Arc::new(ComputePipeline::specialized(
                    gpu,
                    spirv,
                    layouts,
                    self.push_bytes,
                    constants,
                )?);
                gpu.compute_pipelines.insert(shared_key, &p);
                p
            }
        };
        self.built.insert(key, p.clone());
        Ok(p)
    }
}

/// The definitions of descriptor set layouts, as pipeline keys take them.
pub(crate) fn layout_definitions(layouts: &[&DescriptorLayout]) -> Vec<(Vec<BindingKind>, u32)> {
    layouts
        .iter()
        .map(|l| {
            let (kinds, stages): (&[BindingKind], vk::ShaderStageFlags) = l.definition();
            (kinds.to_vec(), stages.as_raw())
        })
        .collect()
}
