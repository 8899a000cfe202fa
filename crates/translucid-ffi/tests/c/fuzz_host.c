/* The engine's side of the C API fuzzer's host-device mode: see fuzz_host.h. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <pthread.h>
#include <string.h>

#include "checks.h"
#include "fuzz_host.h"

static translucid_host_device_create_info g_device_info;
static translucid_host_views_create_info g_views_info;
/* Queue submissions are externally synchronized: the threads take turns. */
static pthread_mutex_t g_queue_lock = PTHREAD_MUTEX_INITIALIZER;

/* Per thread: its command buffer, fence and readback buffer. */
typedef struct {
    VkCommandPool pool;
    VkCommandBuffer cmd;
    VkFence fence;
    VkBuffer readback;
    VkDeviceMemory readback_memory;
    void *mapped;
} thread_objects;
static _Thread_local thread_objects g_thread;

/* Frames are at most 40 x 40 (fuzz_calls' MAX_SIDE); images up to two pixels larger. */
#define MOST_SIDE 42
#define READBACK_BYTES (MOST_SIDE * MOST_SIDE * 16)

void fuzz_host_start(void) {
    translucid_host_requirements req;
    memset(&req, 0, sizeof req);
    req.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_REQUIREMENTS;
    CHECK(NULL, translucid_host_get_requirements(&req));
    uint32_t methods[8];
    size_t count = 0;
    CHECK(NULL, translucid_method_get_available(methods, 8, &count));
    for (size_t m = 0; m < count; m++) {
        translucid_host_requirements per_method = req;
        CHECK(NULL, translucid_host_get_method_requirements(methods[m], &per_method));
        VkBool32 *all = (VkBool32 *)&req.features;
        const VkBool32 *own = (const VkBool32 *)&per_method.features;
        for (size_t f = 0; f < sizeof req.features / sizeof(VkBool32); f++) {
            all[f] |= own[f];
        }
    }
    create_engine(&req);
    g_device_info = host_device_info();
    /* Frames of two views side by side: see fuzz_host_frame. */
    g_views_info.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_VIEWS_CREATE_INFO;
    g_views_info.next = g_device_info.next;
    g_views_info.views_per_frame = 2;
    g_device_info.next = &g_views_info;
}

int fuzz_host_stop(void) {
    destroy_engine();
    return g_validation_messages;
}

const void *fuzz_host_device_info(void) { return &g_device_info; }

void fuzz_host_thread_end(void) {
    if (g_thread.cmd == VK_NULL_HANDLE) {
        return;
    }
    vkDestroyBuffer(g_device, g_thread.readback, NULL);
    vkFreeMemory(g_device, g_thread.readback_memory, NULL);
    vkDestroyFence(g_device, g_thread.fence, NULL);
    vkDestroyCommandPool(g_device, g_thread.pool, NULL);
    memset(&g_thread, 0, sizeof g_thread);
}

static void thread_start(void) {
    if (g_thread.cmd != VK_NULL_HANDLE) {
        return;
    }
    VkCommandPoolCreateInfo pool;
    memset(&pool, 0, sizeof pool);
    pool.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = g_family;
    VK_CHECK(vkCreateCommandPool(g_device, &pool, NULL, &g_thread.pool));
    VkCommandBufferAllocateInfo alloc;
    memset(&alloc, 0, sizeof alloc);
    alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    alloc.commandPool = g_thread.pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VK_CHECK(vkAllocateCommandBuffers(g_device, &alloc, &g_thread.cmd));
    VkFenceCreateInfo fence;
    memset(&fence, 0, sizeof fence);
    fence.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    VK_CHECK(vkCreateFence(g_device, &fence, NULL, &g_thread.fence));
    g_thread.readback =
        create_host_buffer(READBACK_BYTES, &g_thread.readback_memory, &g_thread.mapped);
}

typedef struct {
    VkFormat format;
    int bytes;    /* per texel */
    int is_float; /* read back and checked finite: RGBA16F, RGBA32F */
} colour_format;

static const colour_format COLOUR_FORMATS[] = {
    {VK_FORMAT_R8G8B8A8_UNORM, 4, 0},      {VK_FORMAT_R8G8B8A8_SRGB, 4, 0},
    {VK_FORMAT_B8G8R8A8_UNORM, 4, 0},      {VK_FORMAT_B8G8R8A8_SRGB, 4, 0},
    {VK_FORMAT_A2B10G10R10_UNORM_PACK32, 4, 0},
    {VK_FORMAT_R16G16B16A16_SFLOAT, 8, 1}, {VK_FORMAT_R32G32B32A32_SFLOAT, 16, 1},
};
static const VkImageLayout COLOUR_LAYOUTS[] = {
    VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
    VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
};
static const VkFormat DEPTH_FORMATS[] = {
    VK_FORMAT_D32_SFLOAT, VK_FORMAT_D16_UNORM, VK_FORMAT_X8_D24_UNORM_PACK32,
    VK_FORMAT_D24_UNORM_S8_UINT, VK_FORMAT_D32_SFLOAT_S8_UINT,
};
/* Layouts of both aspects, which every depth format may be in. */
static const VkImageLayout DEPTH_LAYOUTS[] = {
    VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
    VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
    VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
};

#define COUNT(a) ((uint32_t)(sizeof(a) / sizeof((a)[0])))

static int has_stencil(VkFormat f) {
    return f == VK_FORMAT_D24_UNORM_S8_UINT || f == VK_FORMAT_D32_SFLOAT_S8_UINT;
}

/* A format the device can use as translucid needs it, drawn until one is found. */
static const colour_format *pick_colour(uint32_t (*below)(uint32_t)) {
    for (;;) {
        const colour_format *c = &COLOUR_FORMATS[below(COUNT(COLOUR_FORMATS))];
        VkFormatProperties p;
        vkGetPhysicalDeviceFormatProperties(g_physical, c->format, &p);
        VkFormatFeatureFlags need = VK_FORMAT_FEATURE_BLIT_SRC_BIT | VK_FORMAT_FEATURE_BLIT_DST_BIT |
                                    VK_FORMAT_FEATURE_TRANSFER_SRC_BIT |
                                    VK_FORMAT_FEATURE_TRANSFER_DST_BIT;
        if ((p.optimalTilingFeatures & need) == need) {
            return c;
        }
    }
}

static VkFormat pick_depth(uint32_t (*below)(uint32_t)) {
    for (;;) {
        VkFormat f = DEPTH_FORMATS[below(COUNT(DEPTH_FORMATS))];
        VkFormatProperties p;
        vkGetPhysicalDeviceFormatProperties(g_physical, f, &p);
        VkFormatFeatureFlags need = VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT |
                                    VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT |
                                    VK_FORMAT_FEATURE_TRANSFER_SRC_BIT |
                                    VK_FORMAT_FEATURE_TRANSFER_DST_BIT;
        if ((p.optimalTilingFeatures & need) == need) {
            return f;
        }
    }
}

static void transition(VkImage image, VkImageAspectFlags aspect, VkImageLayout from,
                       VkImageLayout to) {
    barrier(g_thread.cmd, image, aspect, from, to, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
            VK_ACCESS_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
            VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT);
}

static void submit_and_wait(void) {
    pthread_mutex_lock(&g_queue_lock);
    submit_commands(g_thread.cmd, g_thread.fence);
    pthread_mutex_unlock(&g_queue_lock);
    wait_fence(g_thread.fence);
}

translucid_result fuzz_host_frame(translucid_context *ctx, const translucid_frame_info *info,
                                  translucid_frame *out, uint32_t (*below)(uint32_t),
                                  fuzz_host_outcome *outcome) {
    thread_start();
    outcome->completed = -1;
    outcome->finite = 1;
    /* A third of the frames are two views side by side, each with the frame's camera (a
     * bad one is refused as it would be alone), into images twice as wide. */
    int two_views = below(3) == 0;
    /* Sizes past the largest frame the fuzzer makes are left to the frame's checks. */
    uint32_t width = info->width >= 1 && info->width <= 40
                         ? info->width * (two_views ? 2 : 1) + below(3)
                         : 8;
    uint32_t height = info->height >= 1 && info->height <= 40 ? info->height + below(3) : 8;
    const colour_format *colour = pick_colour(below);
    VkFormat depth_format = pick_depth(below);
    VkImageAspectFlags depth_aspects =
        VK_IMAGE_ASPECT_DEPTH_BIT | (has_stencil(depth_format) ? VK_IMAGE_ASPECT_STENCIL_BIT : 0);
    VkImage colour_image = create_image(
        colour->format,
        VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
            VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
        width, height);
    VkDeviceMemory colour_memory = bind_image(colour_image);
    VkImage depth_image = create_image(depth_format,
                                       VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                           VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                                           VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                                           VK_IMAGE_USAGE_SAMPLED_BIT,
                                       width, height);
    VkDeviceMemory depth_memory = bind_image(depth_image);

    translucid_host_frame_targets targets;
    memset(&targets, 0, sizeof targets);
    targets.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_FRAME_TARGETS;
    targets.command_buffer = g_thread.cmd;
    targets.colour.image = colour_image;
    targets.colour.format = colour->format;
    targets.colour.width = targets.depth.width = width;
    targets.colour.height = targets.depth.height = height;
    targets.colour.layout = COLOUR_LAYOUTS[below(COUNT(COLOUR_LAYOUTS))];
    targets.colour.final_layout = COLOUR_LAYOUTS[below(COUNT(COLOUR_LAYOUTS))];
    targets.depth.image = depth_image;
    targets.depth.format = depth_format;
    targets.depth.layout = DEPTH_LAYOUTS[below(COUNT(DEPTH_LAYOUTS))];
    targets.depth.final_layout = DEPTH_LAYOUTS[below(COUNT(DEPTH_LAYOUTS))];

    /* The engine's opaque layer: a grey clear, and depth far from the eye (0 under the
     * reversed-Z projections the fuzzer gives). */
    begin_commands(g_thread.cmd);
    transition(colour_image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    transition(depth_image, depth_aspects, VK_IMAGE_LAYOUT_UNDEFINED,
               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkClearColorValue grey = {{0.4f, 0.4f, 0.4f, 1.0f}};
    VkImageSubresourceRange colour_range = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(g_thread.cmd, colour_image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &grey,
                         1, &colour_range);
    int reversed = info->camera.projection[11] != 0.0f && info->camera.projection[14] > 0.0f;
    VkClearDepthStencilValue far = {reversed ? 0.0f : 1.0f, 0};
    VkImageSubresourceRange depth_range = {depth_aspects, 0, 1, 0, 1};
    vkCmdClearDepthStencilImage(g_thread.cmd, depth_image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                &far, 1, &depth_range);
    transition(colour_image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
               targets.colour.layout);
    transition(depth_image, depth_aspects, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
               targets.depth.layout);

    translucid_frame_view views[2];
    translucid_host_frame_views chain;
    if (two_views) {
        memset(views, 0, sizeof views);
        views[0].camera = views[1].camera = info->camera;
        views[1].x = info->width;
        memset(&chain, 0, sizeof chain);
        chain.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_FRAME_VIEWS;
        chain.view_count = 2;
        chain.views = views;
        targets.next = &chain;
    }
    translucid_result got = translucid_frame_record(ctx, info, &targets, out);
    int recorded = got == TRANSLUCID_RESULT_SUCCESS && out != NULL;
    VkImageLayout colour_now = recorded ? targets.colour.final_layout : targets.colour.layout;
    transition(colour_image, VK_IMAGE_ASPECT_COLOR_BIT, colour_now,
               VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    VkBufferImageCopy copy = region(VK_IMAGE_ASPECT_COLOR_BIT, 0, width, height);
    vkCmdCopyImageToBuffer(g_thread.cmd, colour_image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                           g_thread.readback, 1, &copy);
    submit_and_wait();
    if (recorded) {
        outcome->completed = translucid_frame_complete(ctx, *out);
        if (colour->is_float) {
            for (uint32_t i = 0; i < width * height * 4; i++) {
                int finite;
                if (colour->bytes == 16) {
                    float v;
                    memcpy(&v, (const uint8_t *)g_thread.mapped + 4 * i, 4);
                    finite = isfinite(v);
                } else {
                    uint16_t h;
                    memcpy(&h, (const uint8_t *)g_thread.mapped + 2 * i, 2);
                    finite = (h & 0x7C00u) != 0x7C00u; /* exponent all ones: Inf or NaN */
                }
                outcome->finite &= finite;
            }
        }
    }
    vkDestroyImage(g_device, colour_image, NULL);
    vkFreeMemory(g_device, colour_memory, NULL);
    vkDestroyImage(g_device, depth_image, NULL);
    vkFreeMemory(g_device, depth_memory, NULL);
    return got;
}
