//! Compute pipelines kept by their specialization: a frame that needs a variant built before
//! builds nothing.

#![deny(unsafe_code)]

use super::{ComputePipeline, DescriptorLayout, Gpu};
use crate::Result;
use std::collections::HashMap;
use std::sync::Arc;

/// The pipelines of one shader family over one set of descriptor layouts and one push
/// constant size, each built on first use for its (shader, constants) and kept for the
/// owner's life. Every call must pass the same layouts and push size: they are not part of
/// the key.
pub struct ComputePipelineCache {
    push_bytes: u32,
    built: HashMap<Key, Arc<ComputePipeline>>,
}

/// A shader by its SPIR-V (length and a hash of the words: the same shader may be reached
/// through different addresses), and its constants in `constant_id` order.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct Key {
    spirv: (usize, u64),
    constants: Vec<u32>,
}

fn spirv_hash(spirv: &[u8]) -> u64 {
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

    /// The pipeline of `spirv` with `constants` (constant_id i = constants[i]), built now if
    /// this cache has not built it before.
    pub fn get(
        &mut self,
        gpu: &Gpu,
        layouts: &[&DescriptorLayout],
        spirv: &'static [u8],
        constants: &[u32],
    ) -> Result<Arc<ComputePipeline>> {
        let key = Key {
            spirv: (spirv.len(), spirv_hash(spirv)),
            constants: constants.to_vec(),
        };
        if let Some(p) = self.built.get(&key) {
            return Ok(p.clone());
        }
        let p = Arc::new(ComputePipeline::specialized(
            gpu,
            spirv,
            layouts,
            self.push_bytes,
            constants,
        )?);
        self.built.insert(key, p.clone());
        Ok(p)
    }
}
