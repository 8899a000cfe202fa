/*
 * Plays an engine using host-device mode (the example engine, examples-c/engine.c): its own
 * Vulkan instance, device, images and command buffer. It asks translucid what to enable,
 * creates its device accordingly, draws (uploads) its opaque layer, lets translucid record
 * the transparent pass into the same command buffer, submits, waits, reads its colour image
 * back and compares it with a standalone context's frame of the same scene over the same
 * opaque layer: every method, every pixel within 2/255.
 * Then the errors: missing requirements, NULL handles, a second frame recorded before the
 * first completed, completing a frame that never ran, wrong layouts and formats, calls the
 * mode does not offer.
 *
 * With TRANSLUCID_VALIDATION=1 the engine's instance runs the Khronos validation layer, and
 * any error it reports fails the test. TRANSLUCID_SYNC_VALIDATION=1 adds synchronization
 * validation (the test harness turns it on, except under the sanitizers: the layer's own
 * allocations then count as leaks).
 */
#include "checks.h"

#define W 64
#define H 48

static translucid_context *g_host = NULL, *g_standalone = NULL;

static VkCommandPool g_pool;
static VkCommandBuffer g_cmd;
static VkFence g_fence;

/* The engine's frame: colour and depth images, and one host-visible buffer for uploads
 * (colour bytes, then depth floats) and readback. */
static VkImage g_colour, g_depth;
static VkDeviceMemory g_colour_memory, g_depth_memory, g_buffer_memory;
static VkBuffer g_buffer;
static void *g_mapped;
#define COLOUR_BYTES (W * H * 4)
#define DEPTH_BYTES (W * H * 4)
/* Where the depth image is read back to, after the upload's colour and depth. */
#define DEPTH_READBACK (COLOUR_BYTES + DEPTH_BYTES)

static void create_frame_resources(void) {
    VkCommandPoolCreateInfo pool;
    VkCommandBufferAllocateInfo alloc;
    VkFenceCreateInfo fence;
    VkImageUsageFlags transfer = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;

    memset(&pool, 0, sizeof pool);
    pool.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = g_family;
    VK_CHECK(vkCreateCommandPool(g_device, &pool, NULL, &g_pool));
    memset(&alloc, 0, sizeof alloc);
    alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    alloc.commandPool = g_pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VK_CHECK(vkAllocateCommandBuffers(g_device, &alloc, &g_cmd));
    memset(&fence, 0, sizeof fence);
    fence.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    VK_CHECK(vkCreateFence(g_device, &fence, NULL, &g_fence));

    g_colour = create_image(VK_FORMAT_R8G8B8A8_SRGB,
                            transfer | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT, W, H);
    g_colour_memory = bind_image(g_colour);
    /* Sampled: exact and wavelet read it where it is. */
    g_depth = create_image(VK_FORMAT_D32_SFLOAT,
                           transfer | VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                               VK_IMAGE_USAGE_SAMPLED_BIT,
                           W, H);
    g_depth_memory = bind_image(g_depth);

    g_buffer = create_host_buffer(COLOUR_BYTES + 2 * DEPTH_BYTES, &g_buffer_memory, &g_mapped);
}

static void begin(void) { begin_commands(g_cmd); }

/* The engine's "opaque pass": its colour and depth, copied from the upload buffer, left in
 * the attachment layouts an opaque pass would leave them in. */
static void record_opaque_layer(void) {
    VkBufferImageCopy colour = region(VK_IMAGE_ASPECT_COLOR_BIT, 0, W, H);
    VkBufferImageCopy depth = region(VK_IMAGE_ASPECT_DEPTH_BIT, COLOUR_BYTES, W, H);
    VkPipelineStageFlags transfer = VK_PIPELINE_STAGE_TRANSFER_BIT;
    barrier(g_cmd, g_colour, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
            VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
            VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT, transfer,
            VK_ACCESS_TRANSFER_WRITE_BIT);
    barrier(g_cmd, g_depth, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
            VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
            VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT, transfer,
            VK_ACCESS_TRANSFER_WRITE_BIT);
    vkCmdCopyBufferToImage(g_cmd, g_buffer, g_colour, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                           &colour);
    vkCmdCopyBufferToImage(g_cmd, g_buffer, g_depth, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                           &depth);
    barrier(g_cmd, g_colour, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
            VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, transfer, VK_ACCESS_TRANSFER_WRITE_BIT,
            VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
            VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
    barrier(g_cmd, g_depth, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
            VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL, transfer,
            VK_ACCESS_TRANSFER_WRITE_BIT,
            VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT,
            VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
}

/* After translucid: the colour image (left in TRANSFER_SRC_OPTIMAL as asked) and the depth
 * image into the buffer, for the host to read. The depth image's transition starts from the
 * final layout the frame asked for, so validation checks translucid left it there. */
static void record_readback(void) {
    VkBufferImageCopy colour = region(VK_IMAGE_ASPECT_COLOR_BIT, 0, W, H);
    VkBufferImageCopy depth = region(VK_IMAGE_ASPECT_DEPTH_BIT, DEPTH_READBACK, W, H);
    VkMemoryBarrier host;
    barrier(g_cmd, g_depth, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL,
            VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
            VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT,
            VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    vkCmdCopyImageToBuffer(g_cmd, g_colour, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, g_buffer, 1,
                           &colour);
    vkCmdCopyImageToBuffer(g_cmd, g_depth, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, g_buffer, 1,
                           &depth);
    memset(&host, 0, sizeof host);
    host.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
    host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(g_cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                         &host, 0, NULL, 0, NULL);
}

static void submit_and_wait(void) {
    submit_commands(g_cmd, g_fence);
    wait_fence(g_fence);
}

/* ---- the scene, the same in both contexts ---- */

static uint8_t g_opaque_colour[COLOUR_BYTES];
static float g_opaque_depth[W * H];

/* A gradient; depth in three bands: in front of every quad, cutting through them, far. */
static void make_opaque_layer(void) {
    static const float bands[3] = {0.3f, 0.75f, 1.0f};
    fill_opaque_layer(g_opaque_colour, g_opaque_depth, W, H, bands);
}

typedef struct scene {
    translucid_mesh meshes[3];
    translucid_material materials[3];
    translucid_draw draws[3];
} scene;

/* Three quads: two facing the camera at different depths, and one tilted through both. */
static void make_scene(translucid_context *ctx, scene *s) {
    size_t i;
    for (i = 0; i < 3; i++) make_quad(ctx, i, 0, &s->meshes[i], &s->materials[i], &s->draws[i]);
}

static translucid_frame_info frame_info(uint32_t method, const scene *s) {
    translucid_frame_info info;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
    info.method = method;
    info.width = W;
    info.height = H;
    info.camera.view[0] = info.camera.view[5] = info.camera.view[10] = info.camera.view[15] = 1;
    info.camera.fov_y = 0.9f;
    info.camera.z_near = 1.0f;
    info.camera.z_far = 10.0f;
    info.draws = s->draws;
    info.draw_count = 3;
    return info;
}

static translucid_host_frame_targets frame_targets(void) {
    translucid_host_frame_targets t;
    memset(&t, 0, sizeof t);
    t.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_FRAME_TARGETS;
    t.command_buffer = g_cmd;
    t.colour.image = g_colour;
    t.colour.format = VK_FORMAT_R8G8B8A8_SRGB;
    t.colour.width = t.depth.width = W;
    t.colour.height = t.depth.height = H;
    t.colour.layout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    t.colour.final_layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    t.depth.image = g_depth;
    t.depth.format = VK_FORMAT_D32_SFLOAT;
    t.depth.layout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    t.depth.final_layout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
    return t;
}

/* One whole engine frame: opaque layer, translucid, readback; submitted and waited for.
 * Returns what translucid_frame_complete said. */
static translucid_result engine_frame(const translucid_frame_info *info,
                                      translucid_frame *frame) {
    translucid_host_frame_targets targets = frame_targets();
    translucid_result completed;
    memcpy(g_mapped, g_opaque_colour, COLOUR_BYTES);
    memcpy((uint8_t *)g_mapped + COLOUR_BYTES, g_opaque_depth, DEPTH_BYTES);
    memset((uint8_t *)g_mapped + DEPTH_READBACK, 0xFF, DEPTH_BYTES);
    begin();
    record_opaque_layer();
    CHECK(g_host, translucid_frame_record(g_host, info, &targets, frame));
    record_readback();
    submit_and_wait();
    completed = translucid_frame_complete(g_host, *frame);
    TRUE_OR_FAIL(completed == TRANSLUCID_RESULT_SUCCESS ||
                 completed == TRANSLUCID_RESULT_FRAME_DEGRADED);
    /* translucid only reads the engine's depth. */
    TRUE_OR_FAIL(memcmp((uint8_t *)g_mapped + DEPTH_READBACK, g_opaque_depth, DEPTH_BYTES) == 0);
    return completed;
}

/* `wavelet` names the wavelet storage (NULL for the other methods): the bins composite onto
 * the engine's images where they are, the coefficient images copy in and out. */
static void compare_with_standalone(uint32_t method, const translucid_wavelet_settings *wavelet,
                                    const scene *host_scene, const scene *standalone_scene) {
    translucid_frame_info info = frame_info(method, standalone_scene);
    int in_place = method == TRANSLUCID_METHOD_EXACT ||
                   (method == TRANSLUCID_METHOD_WAVELET && wavelet != NULL &&
                    wavelet->storage == TRANSLUCID_WAVELET_STORAGE_BINS);
    translucid_frame frame;
    translucid_frame_statistics stats;
    static uint8_t expected[COLOUR_BYTES];
    const uint8_t *got = g_mapped;
    int worst = 0, attempts = 0;
    size_t i;
    translucid_result completed;

    info.next = wavelet;
    render_standalone(g_standalone, info, g_opaque_colour, g_opaque_depth, expected,
                      sizeof expected);

    info = frame_info(method, host_scene);
    info.next = wavelet;
    /* An overflow says "record it again"; the grown buffers then suffice. */
    do {
        completed = engine_frame(&info, &frame);
        attempts++;
        memset(&stats, 0, sizeof stats);
        stats.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS;
        CHECK(g_host, translucid_frame_get_statistics(g_host, frame, &stats));
        TRUE_OR_FAIL(stats.overflowed == (completed == TRANSLUCID_RESULT_FRAME_DEGRADED));
        CHECK(g_host, translucid_frame_destroy(g_host, frame));
    } while (completed == TRANSLUCID_RESULT_FRAME_DEGRADED && attempts < 3);
    TRUE_OR_FAIL(completed == TRANSLUCID_RESULT_SUCCESS);
    /* The quads cover most of the frame: exact's first guess of bin entries (eight per
     * triangle) is too small, and the frame is rasterized in bands within its one recording
     * (wavelet's bins are exact's; its images have no lists): right the first time. */
    TRUE_OR_FAIL(attempts == 1);

    for (i = 0; i < COLOUR_BYTES; i++) {
        int d = abs((int)got[i] - (int)expected[i]);
        if (i % 4 == 3) continue; /* alpha: the engine's, not compared */
        if (d > worst) worst = d;
        if (d > 2 && g_failed < 40) {
            printf("FAIL method %u pixel (%u, %u) channel %u: host %u, standalone %u\n", method,
                   (unsigned)(i / 4 % W), (unsigned)(i / 4 / W), (unsigned)(i % 4), got[i],
                   expected[i]);
        }
        if (d > 2) g_failed++;
    }
    g_passed++;
    printf("method %u%s: host-device vs standalone, worst difference %d/255\n", method,
           wavelet == NULL ? ""
           : wavelet->storage == TRANSLUCID_WAVELET_STORAGE_BINS ? " (bins)"
                                                                  : " (images)",
           worst);

    TRUE_OR_FAIL(stats.method == method && stats.width == W && stats.height == H);
    if (method == TRANSLUCID_METHOD_BLEND) {
        /* blend draws straight into the engine's images: no copy in or out. */
        TRUE_OR_FAIL(stats.stage_count == 1);
        TRUE_OR_FAIL(strcmp(stats.stages[0].name, "blend") == 0);
        TRUE_OR_FAIL(stats.dispatches == 0);
    } else if (in_place) {
        /* They sample the engine's depth and blend onto its colour where they are. */
        TRUE_OR_FAIL(stats.stage_count >= 2);
        TRUE_OR_FAIL(strcmp(stats.stages[0].name, "opaque") != 0);
        TRUE_OR_FAIL(strcmp(stats.stages[stats.stage_count - 1].name, "composite") == 0);
        /* A chain of compute dispatches, counted (the first frame records every band). */
        TRUE_OR_FAIL(stats.dispatches > 0);
    } else {
        TRUE_OR_FAIL(stats.stage_count >= 3);
        TRUE_OR_FAIL(strcmp(stats.stages[0].name, "opaque") == 0);
        TRUE_OR_FAIL(strcmp(stats.stages[stats.stage_count - 1].name, "output") == 0);
    }
    TRUE_OR_FAIL(stats.gpu_milliseconds >= stats.method_milliseconds);
    TRUE_OR_FAIL(stats.peak_gpu_bytes > 0);
    TRUE_OR_FAIL(stats.overflow_rerenders == 0);
}

static translucid_context_create_info context_info(const void *next) {
    translucid_context_create_info info;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_CONTEXT_CREATE_INFO;
    info.header_version = TRANSLUCID_HEADER_VERSION;
    info.mode = TRANSLUCID_CONTEXT_MODE_HOST_DEVICE;
    info.next = next;
    return info;
}

/* What the engine's device description must get right. */
static void context_errors(void) {
    translucid_host_device_create_info hd = host_device_info();
    translucid_context_create_info info = context_info(&hd);
    VkPhysicalDeviceFeatures fewer = g_features;
    translucid_context *ctx = (translucid_context *)&hd; /* a sentinel, never written */
    translucid_context *const sentinel = ctx;

    fewer.shaderInt64 = VK_FALSE;
    hd.enabled_features = &fewer;
    EXPECT(NULL, translucid_context_create(&info, &ctx),
           TRANSLUCID_RESULT_ERROR_DEVICE_REQUIREMENTS);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(NULL), "shaderInt64") != NULL);
    hd = host_device_info();
    hd.api_version = VK_API_VERSION_1_0;
    EXPECT(NULL, translucid_context_create(&info, &ctx),
           TRANSLUCID_RESULT_ERROR_DEVICE_REQUIREMENTS);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(NULL), "apiVersion") != NULL);
    hd = host_device_info();
    hd.queue_family_index = 99;
    EXPECT(NULL, translucid_context_create(&info, &ctx),
           TRANSLUCID_RESULT_ERROR_DEVICE_REQUIREMENTS);
    hd = host_device_info();
    hd.device = VK_NULL_HANDLE;
    EXPECT(NULL, translucid_context_create(&info, &ctx), TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    hd = host_device_info();
    hd.instance = VK_NULL_HANDLE;
    EXPECT(NULL, translucid_context_create(&info, &ctx), TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    hd = host_device_info();
    hd.get_instance_proc_addr = NULL;
    EXPECT(NULL, translucid_context_create(&info, &ctx), TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    hd = host_device_info();
    hd.enabled_features = NULL;
    EXPECT(NULL, translucid_context_create(&info, &ctx), TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    hd = host_device_info();
    hd.s_type = 0;
    EXPECT(NULL, translucid_context_create(&info, &ctx),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    if (g_subgroup_size_control) {
        /* Subgroup size control said enabled, without the extension on a Vulkan 1.2 device;
         * then a structure of another type chained in its place. */
        translucid_base_in_structure other;
        hd = host_device_info();
        TRUE_OR_FAIL(hd.next != NULL);
        hd.enabled_extension_count = 0;
        EXPECT(NULL, translucid_context_create(&info, &ctx),
               TRANSLUCID_RESULT_ERROR_DEVICE_REQUIREMENTS);
        TRUE_OR_FAIL(strstr(translucid_context_get_last_error(NULL),
                            "VK_EXT_subgroup_size_control") != NULL);
        memset(&other, 0, sizeof other);
        other.s_type = TRANSLUCID_STRUCTURE_TYPE_SAMPLER_INFO;
        hd = host_device_info();
        hd.next = &other;
        EXPECT(NULL, translucid_context_create(&info, &ctx),
               TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    }
    hd = host_device_info();
    info.device = "lavapipe";
    EXPECT(NULL, translucid_context_create(&info, &ctx), TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    TRUE_OR_FAIL(ctx == sentinel);
}

/* A method whose features the engine left off is refused by name, before anything is
 * recorded; the other methods do not need them. */
static void method_without_its_features(void) {
    translucid_host_device_create_info hd = host_device_info();
    translucid_context_create_info info = context_info(&hd);
    VkPhysicalDeviceFeatures fewer = g_features;
    translucid_host_frame_targets targets = frame_targets();
    translucid_context *ctx;
    translucid_frame_info frame;
    translucid_frame handle;
    scene s;

    fewer.geometryShader = VK_FALSE;
    fewer.independentBlend = VK_FALSE;
    hd.enabled_features = &fewer;
    CHECK(NULL, translucid_context_create(&info, &ctx));
    make_scene(ctx, &s);
    frame = frame_info(TRANSLUCID_METHOD_LINKED_LIST, &s);
    begin();
    EXPECT(ctx, translucid_frame_record(ctx, &frame, &targets, &handle),
           TRANSLUCID_RESULT_ERROR_DEVICE_REQUIREMENTS);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "geometryShader") != NULL);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "fragmentStoresAndAtomics") ==
                 NULL);
    frame.method = TRANSLUCID_METHOD_DEPTH_PEELING;
    EXPECT(ctx, translucid_frame_record(ctx, &frame, &targets, &handle),
           TRANSLUCID_RESULT_ERROR_DEVICE_REQUIREMENTS);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "independentBlend") != NULL);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "geometryShader") != NULL);
    VK_CHECK(vkEndCommandBuffer(g_cmd));
    translucid_context_destroy(ctx);
}

/* The features of `extra` ORed into `features`: what an engine does with the requirements of
 * each method it uses. */
static void or_features(VkPhysicalDeviceFeatures *features, const VkPhysicalDeviceFeatures *extra) {
    VkBool32 *to = (VkBool32 *)features;
    const VkBool32 *from = (const VkBool32 *)extra;
    size_t i;
    for (i = 0; i < sizeof *features / sizeof(VkBool32); i++) to[i] |= from[i];
}

/* Frame misuse on a working host-device context. */
static void frame_errors(const scene *s) {
    translucid_frame_info info = frame_info(TRANSLUCID_METHOD_BLEND, s);
    translucid_host_frame_targets targets = frame_targets();
    translucid_frame frame, second;
    translucid_frame_statistics stats;
    translucid_opaque_layer layer;
    uint8_t pixel[4];

    /* Checked before anything is recorded. */
    begin();
    EXPECT(g_host, translucid_frame_record(g_host, &info, NULL, &frame),
           TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    targets.s_type = 0;
    EXPECT(g_host, translucid_frame_record(g_host, &info, &targets, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    targets = frame_targets();
    targets.command_buffer = VK_NULL_HANDLE;
    EXPECT(g_host, translucid_frame_record(g_host, &info, &targets, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    targets = frame_targets();
    targets.depth.image = VK_NULL_HANDLE;
    EXPECT(g_host, translucid_frame_record(g_host, &info, &targets, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    targets = frame_targets();
    targets.colour.layout = VK_IMAGE_LAYOUT_UNDEFINED;
    EXPECT(g_host, translucid_frame_record(g_host, &info, &targets, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(g_host), "layout") != NULL);
    targets = frame_targets();
    targets.depth.final_layout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    EXPECT(g_host, translucid_frame_record(g_host, &info, &targets, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    targets = frame_targets();
    targets.depth.format = VK_FORMAT_S8_UINT;
    EXPECT(g_host, translucid_frame_record(g_host, &info, &targets, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(g_host), "D32_SFLOAT") != NULL);
    /* A format with stencil in a layout of its depth alone: its stencil's layout is unknown. */
    targets.depth.format = VK_FORMAT_D24_UNORM_S8_UINT;
    targets.depth.layout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    EXPECT(g_host, translucid_frame_record(g_host, &info, &targets, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(g_host), "stencil") != NULL);
    targets = frame_targets();
    targets.colour.format = VK_FORMAT_R8G8B8A8_UINT;
    EXPECT(g_host, translucid_frame_record(g_host, &info, &targets, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    /* An image of another size than the frame's (as the engine says it), or no size given. */
    targets = frame_targets();
    targets.depth.width = W / 2;
    EXPECT(g_host, translucid_frame_record(g_host, &info, &targets, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(g_host), "translucid_host_frame_targets.depth") != NULL);
    targets = frame_targets();
    targets.colour.height = 0;
    EXPECT(g_host, translucid_frame_record(g_host, &info, &targets, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
    targets = frame_targets();
    memset(&layer, 0, sizeof layer);
    info.opaque_layer = &layer;
    EXPECT(g_host, translucid_frame_record(g_host, &info, &targets, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    info.opaque_layer = NULL;
    {
        translucid_draw opaque = s->draws[0];
        opaque.layer = TRANSLUCID_LAYER_OPAQUE;
        info.draws = &opaque;
        info.draw_count = 1;
        EXPECT(g_host, translucid_frame_record(g_host, &info, &targets, &frame),
               TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
        /* Says where opaque geometry goes on the engine's device, not the standalone advice
         * to leave opaque_layer NULL, which it is. */
        TRUE_OR_FAIL(strstr(translucid_context_get_last_error(g_host), "host-device mode") != NULL);
        TRUE_OR_FAIL(strstr(translucid_context_get_last_error(g_host), "opaque_layer NULL") ==
                     NULL);
        info = frame_info(TRANSLUCID_METHOD_BLEND, s);
    }
    EXPECT(g_host, translucid_frame_render(g_host, &info, &frame),
           TRANSLUCID_RESULT_ERROR_NOT_SUPPORTED);
    EXPECT(g_standalone, translucid_frame_record(g_standalone, &info, &targets, &frame),
           TRANSLUCID_RESULT_ERROR_NOT_SUPPORTED);

    /* One frame in flight: a second recording and the first's statistics are refused,
     * completing it before it ran says NOT_READY and changes nothing, and destroying it is
     * refused (the GPU might be running it); abandoning it ends it. */
    record_opaque_layer();
    CHECK(g_host, translucid_frame_record(g_host, &info, &targets, &frame));
    EXPECT(g_host, translucid_frame_record(g_host, &info, &targets, &second),
           TRANSLUCID_RESULT_ERROR_FRAME_IN_FLIGHT);
    memset(&stats, 0, sizeof stats);
    stats.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS;
    EXPECT(g_host, translucid_frame_get_statistics(g_host, frame, &stats),
           TRANSLUCID_RESULT_ERROR_FRAME_IN_FLIGHT);
    EXPECT(g_host, translucid_frame_complete(g_host, frame), TRANSLUCID_RESULT_NOT_READY);
    EXPECT(g_host, translucid_frame_complete(g_host, frame), TRANSLUCID_RESULT_NOT_READY);
    EXPECT(g_host, translucid_frame_record(g_host, &info, &targets, &second),
           TRANSLUCID_RESULT_ERROR_FRAME_IN_FLIGHT);
    EXPECT(g_host, translucid_frame_destroy(g_host, frame), TRANSLUCID_RESULT_ERROR_FRAME_IN_FLIGHT);
    EXPECT(g_host, translucid_frame_read(g_host, frame, TRANSLUCID_PIXEL_FORMAT_RGBA8_SRGB, pixel,
                                         sizeof pixel),
           TRANSLUCID_RESULT_ERROR_NOT_SUPPORTED);
    /* The engine drops this command buffer (it is reset before its next use) and abandons the
     * frame: what it referenced is freed, so it must never be submitted. */
    VK_CHECK(vkEndCommandBuffer(g_cmd));
    CHECK(g_host, translucid_frame_abandon(g_host, frame));
    EXPECT(g_host, translucid_frame_complete(g_host, frame), TRANSLUCID_RESULT_ERROR_STALE_HANDLE);
    EXPECT(g_host, translucid_frame_abandon(g_host, frame), TRANSLUCID_RESULT_ERROR_STALE_HANDLE);

    /* After that the context records again, and a completed frame cannot complete twice. */
    TRUE_OR_FAIL(engine_frame(&info, &frame) == TRANSLUCID_RESULT_SUCCESS);
    EXPECT(g_host, translucid_frame_complete(g_host, frame), TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    EXPECT(g_host, translucid_frame_abandon(g_host, frame), TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    EXPECT(g_host, translucid_frame_read(g_host, frame, TRANSLUCID_PIXEL_FORMAT_RGBA8_SRGB, pixel,
                                         sizeof pixel),
           TRANSLUCID_RESULT_ERROR_NOT_SUPPORTED);
    CHECK(g_host, translucid_frame_destroy(g_host, frame));
}

int main(void) {
    translucid_host_requirements req;
    translucid_host_subgroup_requirements subgroups;
    translucid_host_device_create_info hd;
    translucid_context_create_info info;
    scene host_scene, standalone_scene;
    uint32_t methods[8];
    size_t count = 0, m;

    /* 1. What to enable, before the engine creates anything. */
    EXPECT(NULL, translucid_host_get_requirements(NULL), TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    memset(&req, 0, sizeof req);
    EXPECT(NULL, translucid_host_get_requirements(&req),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    req.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_REQUIREMENTS;
    CHECK(NULL, translucid_host_get_requirements(&req));
    TRUE_OR_FAIL(req.api_version >= VK_API_VERSION_1_2);
    TRUE_OR_FAIL(req.queue_flags & VK_QUEUE_GRAPHICS_BIT);
    TRUE_OR_FAIL(req.features.geometryShader == VK_FALSE);

    /* The subgroups exact and wavelet need, in a structure chained to the requirements; a
     * chained structure of another type is refused, and nothing is written. */
    memset(&subgroups, 0, sizeof subgroups);
    subgroups.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
    req.next = &subgroups;
    req.api_version = 0;
    EXPECT(NULL, translucid_host_get_requirements(&req),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    TRUE_OR_FAIL(req.api_version == 0 && subgroups.min_size == 0);
    subgroups.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_SUBGROUP_REQUIREMENTS;
    CHECK(NULL, translucid_host_get_requirements(&req));
    TRUE_OR_FAIL(req.next == &subgroups && subgroups.next == NULL);
    TRUE_OR_FAIL(req.api_version >= VK_API_VERSION_1_2);
    TRUE_OR_FAIL(subgroups.stages == VK_SHADER_STAGE_COMPUTE_BIT);
    TRUE_OR_FAIL(subgroups.operations ==
                 (VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_VOTE_BIT |
                  VK_SUBGROUP_FEATURE_ARITHMETIC_BIT | VK_SUBGROUP_FEATURE_BALLOT_BIT));
    TRUE_OR_FAIL(subgroups.min_size == 8);

    /* A method's own list: every method's features, and its own; an engine using several ORs
     * their features together. */
    {
        translucid_host_requirements per_method = req;
        EXPECT(NULL, translucid_host_get_method_requirements(TRANSLUCID_METHOD_BLEND, NULL),
               TRANSLUCID_RESULT_ERROR_NULL_POINTER);
        EXPECT(NULL, translucid_host_get_method_requirements(1000, &per_method),
               TRANSLUCID_RESULT_ERROR_INVALID_ENUM);
        CHECK(NULL, translucid_host_get_method_requirements(TRANSLUCID_METHOD_EXACT, &per_method));
        TRUE_OR_FAIL(memcmp(&per_method.features, &req.features, sizeof req.features) == 0);
        CHECK(NULL,
              translucid_host_get_method_requirements(TRANSLUCID_METHOD_LINKED_LIST, &per_method));
        TRUE_OR_FAIL(per_method.features.geometryShader == VK_TRUE);
        TRUE_OR_FAIL(per_method.features.fragmentStoresAndAtomics == VK_TRUE);
        TRUE_OR_FAIL(per_method.features.shaderInt64 == VK_TRUE);
        TRUE_OR_FAIL(per_method.api_version == req.api_version);
        CHECK(NULL,
              translucid_host_get_method_requirements(TRANSLUCID_METHOD_DEPTH_PEELING, &per_method));
        TRUE_OR_FAIL(per_method.features.independentBlend == VK_TRUE);
        TRUE_OR_FAIL(per_method.features.geometryShader == VK_TRUE);
        TRUE_OR_FAIL(per_method.features.fragmentStoresAndAtomics == VK_FALSE);
        CHECK(NULL, translucid_method_get_available(methods, 8, &count));
        for (m = 0; m < count; m++) {
            CHECK(NULL, translucid_host_get_method_requirements(methods[m], &per_method));
            or_features(&req.features, &per_method.features);
        }
    }

    /* 2. The engine's instance and device. */
    create_engine(&req);
    create_frame_resources();
    {
        /* Lavapipe has subgroup size control: the engine enables it and says so, so these
         * checks run translucid's held subgroups on an engine's device. */
        VkPhysicalDeviceProperties properties;
        vkGetPhysicalDeviceProperties(g_physical, &properties);
        TRUE_OR_FAIL(g_subgroup_size_control || strstr(properties.deviceName, "llvmpipe") == NULL);
    }

    /* 3. The context on the engine's device, and a standalone one to compare with. */
    context_errors();
    method_without_its_features();
    hd = host_device_info();
    info = context_info(&hd);
    CHECK(NULL, translucid_context_create(&info, &g_host));
    info = context_info(NULL);
    info.mode = TRANSLUCID_CONTEXT_MODE_STANDALONE;
    CHECK(NULL, translucid_context_create(&info, &g_standalone));
    printf("host-device context on %s\n", translucid_context_get_device_name(g_host));

    make_opaque_layer();
    make_scene(g_host, &host_scene);
    make_scene(g_standalone, &standalone_scene);
    CHECK(g_host, translucid_method_get_available(methods, 8, &count));
    for (m = 0; m < count; m++) {
        if (methods[m] == TRANSLUCID_METHOD_WAVELET) {
            /* Each storage, named: without settings the context's profile picks one. */
            translucid_wavelet_settings wavelet;
            memset(&wavelet, 0, sizeof wavelet);
            wavelet.s_type = TRANSLUCID_STRUCTURE_TYPE_WAVELET_SETTINGS;
            wavelet.storage = TRANSLUCID_WAVELET_STORAGE_BINS;
            compare_with_standalone(methods[m], &wavelet, &host_scene, &standalone_scene);
            wavelet.storage = TRANSLUCID_WAVELET_STORAGE_IMAGES;
            compare_with_standalone(methods[m], &wavelet, &host_scene, &standalone_scene);
        } else {
            compare_with_standalone(methods[m], NULL, &host_scene, &standalone_scene);
        }
    }
    frame_errors(&host_scene);

    /* The GPU is idle (every submission was waited for): the context goes before the device. */
    translucid_context_destroy(g_host);
    translucid_context_destroy(g_standalone);
    vkDestroyBuffer(g_device, g_buffer, NULL);
    vkFreeMemory(g_device, g_buffer_memory, NULL);
    vkDestroyImage(g_device, g_colour, NULL);
    vkFreeMemory(g_device, g_colour_memory, NULL);
    vkDestroyImage(g_device, g_depth, NULL);
    vkFreeMemory(g_device, g_depth_memory, NULL);
    vkDestroyFence(g_device, g_fence, NULL);
    vkDestroyCommandPool(g_device, g_pool, NULL);
    destroy_engine();

    printf("host: %d checks passed, %d failed, %d validation messages, %u methods\n", g_passed,
           g_failed, g_validation_messages, (unsigned)count);
    return g_failed == 0 && g_validation_messages == 0 ? 0 : 1;
}
