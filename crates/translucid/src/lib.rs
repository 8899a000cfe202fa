//! translucid: exact order-independent transparency as a drop-in pass.
//!
//! The crate is organised one room per concern:
//! - [`scene`]: meshes (quads), materials, textures, draws, cameras, glTF import, generated scenes.
//! - [`shading`]: the one shading function every method and the CPU reference share.
//! - [`raster`]: the rasterization rules (fixed-point snapping, top-left fill) shared by the
//!   CPU reference and the compute rasterizer.
//! - [`reference`]: the CPU exact renderer that proves every GPU method right.
//! - [`metrics`]: image error measures.
//! - [`gpu`]: Vulkan through `ash`, the only place that talks to the driver.
//! - [`methods`]: one module per transparency method behind one small trait.
//! - [`renderer`]: ties a device, an uploaded scene, the opaque layer and a method into a frame.

pub mod assets;
pub mod context;
pub mod error;
pub mod frame;
pub mod gpu;
pub mod image;
pub mod interface;
pub mod methods;
pub mod metrics;
pub mod raster;
pub mod reference;
pub mod renderer;
pub mod scene;
pub mod shader_types;
pub mod shading;

pub use error::{Error, Result};
pub use image::{Image, OpaqueLayer};
