/*
 * A small Vulkan engine for the host-device tests: an instance (with the Khronos validation
 * layer when TRANSLUCID_VALIDATION=1, and synchronization validation when
 * TRANSLUCID_SYNC_VALIDATION=1), a device made with exactly what translucid asks for, images,
 * and the test's checks. Any validation error counts as a failure.
 */
#ifndef TRANSLUCID_TEST_ENGINE_H
#define TRANSLUCID_TEST_ENGINE_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <vulkan/vulkan.h>

#include "translucid.h"

#ifdef __cplusplus
extern "C" {
#endif

extern int g_failed, g_passed, g_validation_messages;
extern VkInstance g_instance;
extern VkPhysicalDevice g_physical;
extern VkDevice g_device;
extern VkQueue g_queue;
extern uint32_t g_family;
extern VkPhysicalDeviceFeatures g_features;

/* Prints the failure and exits. */
void fail(const char *what, int line);

#define VK_CHECK(call)                                                                          \
    do {                                                                                        \
        if ((call) != VK_SUCCESS) fail(#call, __LINE__);                                        \
    } while (0)

/* Counts a call's result against the one wanted (a wrong success exits). */
void check(translucid_context *ctx, translucid_result got, translucid_result want,
           const char *call, int line);
#define EXPECT(ctx, call, want) check((ctx), (call), (want), #call, __LINE__)
#define CHECK(ctx, call) EXPECT(ctx, call, TRANSLUCID_RESULT_SUCCESS)

#define TRUE_OR_FAIL(cond)                                                                      \
    do {                                                                                        \
        if (cond) {                                                                             \
            g_passed++;                                                                         \
        } else {                                                                                \
            printf("FAIL line %d: %s\n", __LINE__, #cond);                                      \
            g_failed++;                                                                         \
        }                                                                                       \
    } while (0)

int env_is_1(const char *name);

/* The instance, and the first device and queue family that meet the requirements, made with
 * exactly the features translucid asks for. */
void create_instance(uint32_t api_version);
void create_device(const translucid_host_requirements *req);
/* Destroys the device, the validation messenger and the instance. */
void destroy_engine(void);

uint32_t memory_type(uint32_t bits, VkMemoryPropertyFlags wanted);
VkDeviceMemory bind_image(VkImage image);
VkImage create_image(VkFormat format, VkImageUsageFlags usage, uint32_t width, uint32_t height);
/* A host-visible, coherent transfer buffer of `size` bytes, mapped at `*mapped`. */
VkBuffer create_host_buffer(VkDeviceSize size, VkDeviceMemory *memory, void **mapped);

void barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from,
             VkImageLayout to, VkPipelineStageFlags src_stage, VkAccessFlags src,
             VkPipelineStageFlags dst_stage, VkAccessFlags dst);
/* A copy region of a whole width x height image's aspect, at `offset` in a buffer. */
VkBufferImageCopy region(VkImageAspectFlags aspect, VkDeviceSize offset, uint32_t width,
                         uint32_t height);

/* The engine's device, as the context create-info's `next` takes it. */
translucid_host_device_create_info host_device_info(void);

/* Command buffers: reset and begun for one submission; submitted with a fence; waited for. */
void begin_commands(VkCommandBuffer cmd);
void submit_commands(VkCommandBuffer cmd, VkFence fence);
void wait_fence(VkFence fence);

/* The tests' transparent quads (view space, camera at the origin looking down -Z): two facing
 * the camera at different depths, one tilted through both, and a narrow upright one. */
#define TEST_QUADS 4
extern const float g_test_quads[TEST_QUADS][12];

/* Quad `i` as a mesh and a material (its own colour, `material_flags`), and a transparent
 * draw of them with an identity transform. */
void make_quad(translucid_context *ctx, size_t i, uint32_t material_flags,
               translucid_mesh *mesh, translucid_material *material, translucid_draw *draw);

/* `ctx`'s standalone frame of `info` over an opaque layer of sRGB `colour` and `depth`, read
 * back as RGBA8 into `out` (`size` bytes). */
void render_standalone(translucid_context *ctx, translucid_frame_info info, const uint8_t *colour,
                       const float *depth, uint8_t *out, size_t size);

/* An opaque layer of width x height: an sRGB gradient, depth in three bands across, from
 * `bands[0]` on the left to `bands[2]` on the right. */
void fill_opaque_layer(uint8_t *colour, float *depth, size_t width, size_t height,
                       const float bands[3]);

#ifdef __cplusplus
}
#endif

#endif
