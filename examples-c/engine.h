/*
 * A small Vulkan engine, as translucid's host-device mode expects one: an instance (with the
 * Khronos validation layer when TRANSLUCID_VALIDATION=1, synchronization validation too when
 * TRANSLUCID_SYNC_VALIDATION=1, and a messenger that prints and counts the errors it
 * reports), a device made with exactly what translucid asks for, images, buffers, barriers and
 * command submission. frame_loop.c runs on it, and so do the C API's host-device tests
 * (crates/translucid-ffi/tests/c/), which add their checks in checks.h.
 *
 * A failed Vulkan call prints where and exits: an example and tests have nothing to recover.
 */
#ifndef TRANSLUCID_EXAMPLE_ENGINE_H
#define TRANSLUCID_EXAMPLE_ENGINE_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <vulkan/vulkan.h>

#include "translucid.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Errors the validation layer reported (each printed as "VALIDATION: ..."). */
extern int g_validation_messages;
extern VkInstance g_instance;
extern VkPhysicalDevice g_physical;
extern VkDevice g_device;
extern VkQueue g_queue;
extern uint32_t g_family;
/* The features the device was made with: translucid's requirements. */
extern VkPhysicalDeviceFeatures g_features;
/* Subgroup size control (VK_EXT_subgroup_size_control) is enabled: the device has it. */
extern VkBool32 g_subgroup_size_control;

/* Prints the failure (`what` at `file`:`line`) and exits. */
void engine_fail(const char *what, const char *file, int line);

#define VK_CHECK(call)                                                                          \
    do {                                                                                        \
        if ((call) != VK_SUCCESS) engine_fail(#call, __FILE__, __LINE__);                       \
    } while (0)

/* Whether the environment variable `name` is "1". */
int env_is_1(const char *name);

/* The instance, for Vulkan `api_version`. */
void create_instance(uint32_t api_version);
/* The first device that meets the requirements (its Vulkan version, every feature asked for,
 * the subgroups of a translucid_host_subgroup_requirements chained to `req`, a queue family
 * with the queue flags and timestamps), made with exactly the features and extensions
 * translucid asks for, and subgroup size control where the device has it; and its queue. */
void create_device(const translucid_host_requirements *req);
/* Destroys the device, the validation messenger and the instance. */
void destroy_engine(void);

/* A memory type among `bits` with the `wanted` properties. */
uint32_t memory_type(uint32_t bits, VkMemoryPropertyFlags wanted);
/* Device-local memory allocated for `image` and bound to it. */
VkDeviceMemory bind_image(VkImage image);
/* A 2D image of one level and one sample, optimal tiling, its memory not yet bound. */
VkImage create_image(VkFormat format, VkImageUsageFlags usage, uint32_t width, uint32_t height);
/* The same with `layers` array layers (an XR swapchain's, one a view). */
VkImage create_image_layers(VkFormat format, VkImageUsageFlags usage, uint32_t width,
                            uint32_t height, uint32_t layers);
/* A host-visible, coherent transfer buffer of `size` bytes, mapped at `*mapped`. */
VkBuffer create_host_buffer(VkDeviceSize size, VkDeviceMemory *memory, void **mapped);

/* A layout transition of the image's `aspect` in its first array layer, between the stages and
 * accesses given. */
void barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from,
             VkImageLayout to, VkPipelineStageFlags src_stage, VkAccessFlags src,
             VkPipelineStageFlags dst_stage, VkAccessFlags dst);
/* Every array layer of `image` (its `aspect`) from layout `from` to `to`, after and before
 * anything. */
void every_layer(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect,
                 VkImageLayout from, VkImageLayout to);
/* A copy region of a whole width x height image's aspect, at `offset` in a buffer. */
VkBufferImageCopy region(VkImageAspectFlags aspect, VkDeviceSize offset, uint32_t width,
                         uint32_t height);

/* The engine's device, as the context create-info's `next` takes it (with a
 * translucid_host_subgroup_size_control where g_subgroup_size_control). */
translucid_host_device_create_info host_device_info(void);

/* Command buffers: reset and begun for one submission; ended and submitted with a fence;
 * the fence waited for and reset. */
void begin_commands(VkCommandBuffer cmd);
void submit_commands(VkCommandBuffer cmd, VkFence fence);
void wait_fence(VkFence fence);

#ifdef __cplusplus
}
#endif

#endif
