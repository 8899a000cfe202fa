//! The Vulkan types the host-device API uses, under vulkan.h's names. cbindgen does not emit
//! them (`cbindgen.toml` excludes them): the header includes `<vulkan/vulkan.h>`, whose
//! definitions have the same size and layout as ash's (handles are pointers or 64-bit
//! integers, enums and flags 32-bit integers, the features struct 55 `VkBool32`s).

#![allow(non_camel_case_types)]

use translucid::gpu::vk;

pub type VkInstance = vk::Instance;
pub type VkPhysicalDevice = vk::PhysicalDevice;
pub type VkDevice = vk::Device;
pub type VkCommandBuffer = vk::CommandBuffer;
pub type VkImage = vk::Image;
pub type VkFormat = vk::Format;
pub type VkImageLayout = vk::ImageLayout;
pub type VkQueueFlags = vk::QueueFlags;
pub type VkShaderStageFlags = vk::ShaderStageFlags;
pub type VkSubgroupFeatureFlags = vk::SubgroupFeatureFlags;
pub type VkBool32 = vk::Bool32;
pub type VkPhysicalDeviceFeatures = vk::PhysicalDeviceFeatures;
pub type VkAllocationCallbacks = vk::AllocationCallbacks<'static>;
/// Nullable, as every Vulkan function pointer type is in C.
pub type PFN_vkGetInstanceProcAddr = Option<vk::PFN_vkGetInstanceProcAddr>;
