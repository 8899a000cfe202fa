/*
 * An engine's frame loop in host-device mode (the example engine, examples-c/engine.c), held
 * against a standalone context that renders the same frames over the same opaque layer: every
 * pixel within 2/255.
 *
 * 1. 2 and 3 frames in flight on one context: each frame moves the camera, moves one mesh's
 *    vertices (translucid_mesh_update) and one draw; the engine keeps a command buffer,
 *    fence, images and readback per frame in flight and completes a frame when its fence
 *    signalled (the last ones newest first: completing a frame completes the older ones).
 * 2. Two views (cameras) in one command buffer, each over its own images.
 * 3. The engine's own projection: reversed-Z with an infinite far plane, and a jitter.
 * 4. A mesh destroyed while a frame that draws it is in flight.
 * 5. Misuse: too many frames in flight or views, abandoning a frame between others, bad
 *    updates, preparing for images no frame could record into, views that cannot be.
 * 6. Every depth format an engine may hand over, with forward and reversed-Z depth, each
 *    prepared for (translucid_host_image_formats): its frame builds no pipeline. For exact,
 *    which samples the engine's depth, and linked_list, which imports it.
 * 7. Every method: frames abandoned unsubmitted (carrying a streamed mesh and moved vertices)
 *    cost the next frame nothing: no pipeline built, its image right.
 * 8. Every method in a declared loop (translucid_context_prepare, with the engine's image
 *    formats): the first frame, assets of every kind that changes a shader variant, streamed
 *    in one per frame, then a stack that makes the frames deep, build no pipeline. Then
 *    again with nothing declared but what the first frame draws: each streamed kind is past
 *    the declaration, drawn with the superset variant, and builds nothing either; and
 *    preparing another method for a frame that draws more leaves the first's frames as they
 *    were, building nothing.
 * 9. A resolution drop then translucid_context_trim: memory given back, and the next frame
 *    builds no pipeline and completes right.
 * 10. Stereo with 3 frames in flight: each frame's two views (cameras) recorded into one
 *    command buffer over their own images, 6 frames in flight, each view as the standalone
 *    context renders it alone, and no pipeline built past the first frame.
 * 11. Every method, 3 frames in flight and sized as it sizes itself, through a scene that
 *    grows deep mid-loop (section 8's stack): every frame completes (none degraded) and is
 *    as the standalone context renders it, though the frames recorded before the first deep
 *    one completed could learn nothing from it.
 * 12. Every method within a memory budget: frames as the standalone context renders them,
 *    the context never holding more than the budget; a mesh too large for what is left of it
 *    is refused with TRANSLUCID_RESULT_ERROR_OUT_OF_MEMORY, a message naming the budget, and
 *    nothing changed: the next frame is as before.
 * 13. Every method in stereo into layered images, as an XR swapchain hands them: one colour
 *    and one depth image of two layers, each view a frame into its own layer, both in one
 *    command buffer; each layer as the standalone context renders its view alone.
 * 14. Every method, a level streamed in while the loop plays: what it may draw prepared in
 *    the background (translucid_context_prepare_in_background) while frames go on, building
 *    nothing; once taken in, its assets of every variant-changing kind build nothing either.
 * 15. Every method in a split screen: two views side by side in one colour and one depth
 *    image, each half as the standalone context renders its view, the pixels between them
 *    untouched; the views as two frames (translucid_host_image_region), then as one frame
 *    of two views (translucid_host_frame_views), prepared for, building nothing.
 * 16. Every method in stereo, 3 frames of 2 views in flight (translucid_host_frame_views
 *    into layered images), prepared for: no frame builds a pipeline, each layer of each
 *    frame is as the standalone context renders its view, and the views' statistics
 *    (translucid_frame_view_statistics) add up to the frame's.
 * And first, in the standalone context: an updated mesh draws as one created so.
 */
/* nanosleep, to wait for work in the background without taking a core from it. */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdlib.h>
#include <time.h>

#include "checks.h"

#define W 48
#define H 36
#define MOST_IN_FLIGHT 3
/* Stereo: each frame in flight records two views, each into its own slot's images. */
#define VIEWS 2
#define SLOTS (MOST_IN_FLIGHT * VIEWS)
#define FRAMES 9
#define COLOUR_BYTES (W * H * 4)
#define DEPTH_BYTES (W * H * 4)

static translucid_context *g_standalone;

/* One frame in flight's resources. */
typedef struct slot {
    VkCommandBuffer cmd;
    VkFence fence;
    VkImage colour, depth;
    VkDeviceMemory colour_memory, depth_memory, buffer_memory;
    /* Upload (colour bytes, then depth floats), then the colour readback. */
    VkBuffer buffer;
    uint8_t *mapped;
    translucid_frame frame;
    int busy;
    uint8_t expected[COLOUR_BYTES];
} slot;

static VkCommandPool g_pool;
static slot g_slots[SLOTS];

static void create_slot(slot *s) {
    VkCommandBufferAllocateInfo alloc;
    VkFenceCreateInfo fence;
    VkImageUsageFlags transfer = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    void *mapped;

    memset(&alloc, 0, sizeof alloc);
    alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    alloc.commandPool = g_pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VK_CHECK(vkAllocateCommandBuffers(g_device, &alloc, &s->cmd));
    memset(&fence, 0, sizeof fence);
    fence.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    VK_CHECK(vkCreateFence(g_device, &fence, NULL, &s->fence));
    s->colour = create_image(VK_FORMAT_R8G8B8A8_SRGB,
                             transfer | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT, W, H);
    s->colour_memory = bind_image(s->colour);
    /* Sampled too: reversed-Z depth is read by a full-screen pass, not copied. */
    s->depth = create_image(VK_FORMAT_D32_SFLOAT,
                            transfer | VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                                VK_IMAGE_USAGE_SAMPLED_BIT,
                            W, H);
    s->depth_memory = bind_image(s->depth);
    s->buffer = create_host_buffer(2 * COLOUR_BYTES + DEPTH_BYTES, &s->buffer_memory, &mapped);
    s->mapped = mapped;
    s->busy = 0;
}

static void destroy_slot(slot *s) {
    vkDestroyBuffer(g_device, s->buffer, NULL);
    vkFreeMemory(g_device, s->buffer_memory, NULL);
    vkDestroyImage(g_device, s->colour, NULL);
    vkFreeMemory(g_device, s->colour_memory, NULL);
    vkDestroyImage(g_device, s->depth, NULL);
    vkFreeMemory(g_device, s->depth_memory, NULL);
    vkDestroyFence(g_device, s->fence, NULL);
}

/* ---- the opaque layer and the scene, alike in both contexts ---- */

static uint8_t g_opaque_colour[COLOUR_BYTES];
/* The engine's depth; translucid's convention (what a standalone layer takes) is the same
 * for forward depth and 1 - d for reversed-Z. */
static float g_engine_depth[W * H], g_layer_depth[W * H];

/* The opaque layer, its depth in three bands across: `bands` near to far. */
static void make_opaque_layer(const float bands[3], int reversed) {
    size_t i;
    fill_opaque_layer(g_opaque_colour, g_engine_depth, W, H, bands);
    for (i = 0; i < W * H; i++) {
        g_layer_depth[i] = reversed ? 1.0f - g_engine_depth[i] : g_engine_depth[i];
    }
}

#define QUADS 3
/* Quads 0-1 face the camera, quad 2 (the "particles") is moved every frame, quad 3 is the
 * one destroyed in flight. */
typedef struct scene {
    translucid_mesh meshes[QUADS + 1];
    translucid_material materials[QUADS + 1];
    translucid_draw draws[QUADS + 1];
} scene;

static void make_scene(translucid_context *ctx, scene *s) {
    size_t i;
    for (i = 0; i < QUADS + 1; i++) {
        make_quad(ctx, i, TRANSLUCID_MATERIAL_LIT, &s->meshes[i], &s->materials[i], &s->draws[i]);
    }
}

/* The scene's meshes and materials, destroyed (its frames done with them). */
static void destroy_scene(translucid_context *ctx, scene *s) {
    size_t i;
    for (i = 0; i < QUADS + 1; i++) {
        CHECK(ctx, translucid_mesh_destroy(ctx, s->meshes[i]));
        CHECK(ctx, translucid_material_destroy(ctx, s->materials[i]));
    }
}

/* Frame `k`'s motion, in both contexts: quad 2's vertices sway, quad 1 slides. */
static void move_scene(translucid_context *host_ctx, scene *host, scene *standalone, int k) {
    float positions[12];
    size_t v;
    memcpy(positions, g_test_quads[2], sizeof positions);
    for (v = 0; v < 4; v++) {
        positions[v * 3 + 1] += 0.08f * (float)k * (v < 2 ? 1.0f : -0.5f);
    }
    CHECK(host_ctx, translucid_mesh_update(host_ctx, host->meshes[2], 0, 4, positions));
    CHECK(g_standalone,
          translucid_mesh_update(g_standalone, standalone->meshes[2], 0, 4, positions));
    host->draws[1].transform[12] = standalone->draws[1].transform[12] = 0.05f * (float)k;
}

/* A camera at `angle` radians around the scene's centre (0, 0, -2.6), looking at it. */
static translucid_camera orbit_camera(float angle) {
    translucid_camera c;
    float s = sinf(angle), co = cosf(angle), d = 2.6f;
    memset(&c, 0, sizeof c);
    /* View = rotate(-angle about y) * translate(-eye), eye = centre + d (sin, 0, cos). */
    c.view[0] = co;
    c.view[2] = s;
    c.view[5] = 1.0f;
    c.view[8] = -s;
    c.view[10] = co;
    c.view[15] = 1.0f;
    {
        float ex = d * s, ez = -2.6f + d * co;
        c.view[12] = -(co * ex - s * ez);
        c.view[14] = -(s * ex + co * ez);
    }
    c.fov_y = 0.9f;
    c.z_near = 1.0f;
    c.z_far = 10.0f;
    return c;
}

static translucid_frame_info frame_info(const scene *s, uint32_t draw_count,
                                        translucid_camera camera) {
    translucid_frame_info info;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
    info.method = TRANSLUCID_METHOD_EXACT;
    info.width = W;
    info.height = H;
    info.camera = camera;
    info.draws = s->draws;
    info.draw_count = draw_count;
    return info;
}

/* The standalone context's frame of `info` (drawn from `s`) over the opaque layer. */
static void render_expected(translucid_frame_info info, const scene *s, uint8_t *out) {
    info.draws = s->draws;
    render_standalone(g_standalone, info, g_opaque_colour, g_layer_depth, out, COLOUR_BYTES);
}


/* The engine's opaque pass into the slot's colour and `depth` (of `aspects`), uploaded from
 * the slot's buffer: colour bytes, then the depth texels the caller wrote after them. */
static void record_opaque_into(VkCommandBuffer cmd, slot *s, VkImage depth_image,
                               VkImageAspectFlags aspects) {
    VkBufferImageCopy colour = region(VK_IMAGE_ASPECT_COLOR_BIT, 0, W, H);
    VkBufferImageCopy depth = region(VK_IMAGE_ASPECT_DEPTH_BIT, COLOUR_BYTES, W, H);
    VkPipelineStageFlags all = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
    VkAccessFlags any = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    VkPipelineStageFlags transfer = VK_PIPELINE_STAGE_TRANSFER_BIT;
    memcpy(s->mapped, g_opaque_colour, COLOUR_BYTES);
    barrier(cmd, s->colour, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
            VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, all, any, transfer,
            VK_ACCESS_TRANSFER_WRITE_BIT);
    barrier(cmd, depth_image, aspects, VK_IMAGE_LAYOUT_UNDEFINED,
            VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, all, any, transfer,
            VK_ACCESS_TRANSFER_WRITE_BIT);
    vkCmdCopyBufferToImage(cmd, s->buffer, s->colour, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                           &colour);
    vkCmdCopyBufferToImage(cmd, s->buffer, depth_image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                           &depth);
    barrier(cmd, s->colour, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
            VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, transfer, VK_ACCESS_TRANSFER_WRITE_BIT,
            all, any);
    barrier(cmd, depth_image, aspects, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
            VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL, transfer,
            VK_ACCESS_TRANSFER_WRITE_BIT, all, any);
}

/* The engine's opaque pass into the slot's own images (D32 depth). */
static void record_opaque(VkCommandBuffer cmd, slot *s) {
    memcpy(s->mapped + COLOUR_BYTES, g_engine_depth, DEPTH_BYTES);
    record_opaque_into(cmd, s, s->depth, VK_IMAGE_ASPECT_DEPTH_BIT);
}

/* The copies recorded before, made visible to the host once the commands have run. */
static void copies_to_host(VkCommandBuffer cmd) {
    VkMemoryBarrier host;
    memset(&host, 0, sizeof host);
    host.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
    host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                         &host, 0, NULL, 0, NULL);
}

/* After translucid: the slot's colour (left in TRANSFER_SRC_OPTIMAL) into its buffer. */
static void record_readback(VkCommandBuffer cmd, slot *s) {
    VkBufferImageCopy colour = region(VK_IMAGE_ASPECT_COLOR_BIT, COLOUR_BYTES + DEPTH_BYTES, W, H);
    vkCmdCopyImageToBuffer(cmd, s->colour, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, s->buffer, 1,
                           &colour);
    copies_to_host(cmd);
}

static translucid_host_frame_targets targets_of(VkCommandBuffer cmd, const slot *s) {
    translucid_host_frame_targets t;
    memset(&t, 0, sizeof t);
    t.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_FRAME_TARGETS;
    t.command_buffer = cmd;
    t.colour.image = s->colour;
    t.colour.format = VK_FORMAT_R8G8B8A8_SRGB;
    t.colour.width = t.depth.width = W;
    t.colour.height = t.depth.height = H;
    t.colour.layout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    t.colour.final_layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    t.depth.image = s->depth;
    t.depth.format = VK_FORMAT_D32_SFLOAT;
    t.depth.layout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    t.depth.final_layout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    return t;
}

/* Fills `prepare` (with `formats` chained) for frames like `info` into images like `t`'s
 * that may draw `content`. */
static void fill_prepare(translucid_prepare_info *prepare, translucid_host_image_formats *formats,
                         const translucid_frame_info *info,
                         const translucid_host_frame_targets *t, uint32_t content) {
    memset(formats, 0, sizeof *formats);
    formats->s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_IMAGE_FORMATS;
    formats->colour_format = t->colour.format;
    formats->colour_layout = t->colour.layout;
    formats->colour_final_layout = t->colour.final_layout;
    formats->depth_format = t->depth.format;
    formats->depth_layout = t->depth.layout;
    formats->depth_final_layout = t->depth.final_layout;
    memset(prepare, 0, sizeof *prepare);
    prepare->s_type = TRANSLUCID_STRUCTURE_TYPE_PREPARE_INFO;
    prepare->next = formats;
    prepare->frame = info;
    prepare->content = content;
}

/* Declares `content` and builds what frames like `info` into images like `t`'s need;
 * returns the pipelines it built. */
static uint64_t prepare_declaring(translucid_context *ctx, const translucid_frame_info *info,
                                  const translucid_host_frame_targets *t, uint32_t content) {
    translucid_host_image_formats formats;
    translucid_prepare_info prepare;
    uint64_t built = 0;
    fill_prepare(&prepare, &formats, info, t, content);
    CHECK(ctx, translucid_context_prepare(ctx, &prepare, &built));
    return built;
}

/* prepare_declaring everything. */
static uint64_t prepare_for(translucid_context *ctx, const translucid_frame_info *info,
                            const translucid_host_frame_targets *t) {
    return prepare_declaring(ctx, info, t, TRANSLUCID_CONTENT_ALL);
}

/* Records the slot's whole frame (opaque, translucid, readback) into `cmd`. */
static void record_frame(translucid_context *ctx, VkCommandBuffer cmd, slot *s,
                         const translucid_frame_info *info) {
    translucid_host_frame_targets t = targets_of(cmd, s);
    record_opaque(cmd, s);
    CHECK(ctx, translucid_frame_record(ctx, info, &t, &s->frame));
    record_readback(cmd, s);
    s->busy = 1;
}



/* Records the slot's whole frame in its own command buffer, submits it, waits for it and
 * completes it. */
static void run_frame(translucid_context *ctx, slot *s, const translucid_frame_info *info) {
    begin_commands(s->cmd);
    record_frame(ctx, s->cmd, s, info);
    submit_commands(s->cmd, s->fence);
    wait_fence(s->fence);
    CHECK(ctx, translucid_frame_complete(ctx, s->frame));
}

static int worst_difference(const uint8_t *a, const uint8_t *b);

/* The slot's readback against what the standalone context rendered; its frame destroyed. */
static void compare(translucid_context *ctx, slot *s, const char *what) {
    translucid_frame_statistics stats;
    int worst = worst_difference(s->mapped + COLOUR_BYTES + DEPTH_BYTES, s->expected);
    memset(&stats, 0, sizeof stats);
    stats.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS;
    CHECK(ctx, translucid_frame_get_statistics(ctx, s->frame, &stats));
    TRUE_OR_FAIL(stats.overflowed == 0 && stats.fragments > 0);
    if (worst > 2) printf("FAIL %s: %d/255 off the standalone frame\n", what, worst);
    TRUE_OR_FAIL(worst <= 2);
    CHECK(ctx, translucid_frame_destroy(ctx, s->frame));
    s->busy = 0;
}

/* Worst channel difference of two RGBA8 frames, alpha aside. */
static int worst_difference(const uint8_t *a, const uint8_t *b) {
    int worst = 0;
    size_t i;
    for (i = 0; i < COLOUR_BYTES; i++) {
        int d = abs((int)a[i] - (int)b[i]);
        if (i % 4 != 3 && d > worst) worst = d;
    }
    return worst;
}

/* 0. An updated mesh draws as a mesh created with those positions does (the standalone
 * context, which the other parts hold the engine's frames against). */
static void updates_move_the_mesh(void) {
    static uint8_t before[COLOUR_BYTES], updated[COLOUR_BYTES], created[COLOUR_BYTES];
    static const uint32_t triangles[] = {0, 1, 2, 0, 2, 3};
    scene s;
    translucid_frame_info info;
    translucid_mesh_create_info mesh;
    translucid_mesh moved;
    float positions[12];
    size_t v;
    make_scene(g_standalone, &s);
    info = frame_info(&s, QUADS, orbit_camera(0.1f));
    render_expected(info, &s, before);
    memcpy(positions, g_test_quads[2], sizeof positions);
    for (v = 0; v < 4; v++) positions[v * 3 + 1] += 0.4f;
    CHECK(g_standalone, translucid_mesh_update(g_standalone, s.meshes[2], 0, 4, positions));
    render_expected(info, &s, updated);
    memset(&mesh, 0, sizeof mesh);
    mesh.s_type = TRANSLUCID_STRUCTURE_TYPE_MESH_CREATE_INFO;
    mesh.primitive = TRANSLUCID_PRIMITIVE_TRIANGLES;
    mesh.vertex_count = 4;
    mesh.positions = positions;
    mesh.index_count = 6;
    mesh.indices = triangles;
    CHECK(g_standalone, translucid_mesh_create(g_standalone, &mesh, &moved));
    s.draws[2].mesh = moved;
    render_expected(info, &s, created);
    TRUE_OR_FAIL(worst_difference(before, updated) > 8);
    TRUE_OR_FAIL(worst_difference(updated, created) <= 2);
    for (v = 0; v < QUADS + 1; v++) {
        CHECK(g_standalone, translucid_mesh_destroy(g_standalone, s.meshes[v]));
        CHECK(g_standalone, translucid_material_destroy(g_standalone, s.materials[v]));
    }
    CHECK(g_standalone, translucid_mesh_destroy(g_standalone, moved));
}

/* A host-device context for `frames_in_flight` frames of up to `views` views each. */
static translucid_context *host_context_views(uint32_t frames_in_flight, uint32_t views) {
    translucid_host_device_create_info hd = host_device_info();
    translucid_host_views_create_info view_info;
    translucid_context_create_info info;
    translucid_context *ctx = NULL;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_CONTEXT_CREATE_INFO;
    info.header_version = TRANSLUCID_HEADER_VERSION;
    info.mode = TRANSLUCID_CONTEXT_MODE_HOST_DEVICE;
    info.next = &hd;
    info.frames_in_flight = frames_in_flight;
    memset(&view_info, 0, sizeof view_info);
    view_info.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_VIEWS_CREATE_INFO;
    view_info.next = hd.next;
    view_info.views_per_frame = views;
    hd.next = &view_info;
    CHECK(NULL, translucid_context_create(&info, &ctx));
    return ctx;
}

static translucid_context *host_context(uint32_t frames_in_flight) {
    return host_context_views(frames_in_flight, 1);
}

/* What the call that recorded `frame` built, as its statistics say: pipelines, and whether
 * it allocated GPU memory. */
static void built_by_frame(translucid_context *ctx, translucid_frame frame, uint64_t *pipelines,
                           int *allocated) {
    translucid_frame_statistics stats;
    memset(&stats, 0, sizeof stats);
    stats.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS;
    CHECK(ctx, translucid_frame_get_statistics(ctx, frame, &stats));
    *pipelines = stats.pipelines_created;
    *allocated = stats.bytes_allocated > 0;
}

/* Checks that `frame`'s statistics, with each view's share chained, has `views` shares that
 * add up to the frame's figures, each view with GPU time of its own. */
static void views_add_up(translucid_context *ctx, translucid_frame frame, uint32_t views,
                         const char *what) {
    translucid_frame_statistics stats;
    translucid_frame_view_statistics shares;
    double gpu = 0.0, method_ms = 0.0;
    uint64_t fragments = 0, dispatches = 0, tail = 0, unpeeled = 0;
    uint32_t v, overflowed = 0;
    memset(&stats, 0, sizeof stats);
    memset(&shares, 0, sizeof shares);
    stats.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS;
    stats.next = &shares;
    /* Another structure there is refused, and nothing written. */
    shares.s_type = TRANSLUCID_STRUCTURE_TYPE_MEMORY_STATISTICS;
    TRUE_OR_FAIL(translucid_frame_get_statistics(ctx, frame, &stats) ==
                 TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    TRUE_OR_FAIL(shares.view_count == 0 && stats.gpu_milliseconds == 0.0);
    shares.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_VIEW_STATISTICS;
    CHECK(ctx, translucid_frame_get_statistics(ctx, frame, &stats));
    if (shares.view_count != views) {
        printf("FAIL %s: %u view shares, not %u\n", what, shares.view_count, views);
    }
    TRUE_OR_FAIL(shares.view_count == views && stats.next == &shares);
    for (v = 0; v < shares.view_count && v < TRANSLUCID_MAX_VIEWS; v++) {
        const translucid_view_statistics *share = &shares.views[v];
        TRUE_OR_FAIL(share->gpu_milliseconds > 0.0);
        gpu += share->gpu_milliseconds;
        method_ms += share->method_milliseconds;
        fragments += share->fragments;
        dispatches += share->dispatches;
        tail += share->tail_fragments;
        unpeeled += share->unpeeled_pixels;
        overflowed |= share->overflowed;
    }
    if (fabs(gpu - stats.gpu_milliseconds) > 1e-6 * stats.gpu_milliseconds) {
        printf("FAIL %s: the views' GPU time %.6f ms is not the frame's %.6f\n", what, gpu,
               stats.gpu_milliseconds);
    }
    TRUE_OR_FAIL(fabs(gpu - stats.gpu_milliseconds) <= 1e-6 * stats.gpu_milliseconds);
    TRUE_OR_FAIL(fabs(method_ms - stats.method_milliseconds) <=
                 1e-6 * stats.method_milliseconds);
    TRUE_OR_FAIL(fragments == stats.fragments && dispatches == stats.dispatches);
    TRUE_OR_FAIL(tail == stats.tail_fragments && unpeeled == stats.unpeeled_pixels);
    TRUE_OR_FAIL(overflowed == stats.overflowed);
}

/* The same of a slot's frame. */
static void built_by(translucid_context *ctx, const slot *s, uint64_t *pipelines, int *allocated) {
    built_by_frame(ctx, s->frame, pipelines, allocated);
}

/* 1. FRAMES moving frames with `in_flight` of them in flight: a frame is completed when the
 * engine comes back to its slot, after waiting for its fence; the last ones are completed
 * newest first, which completes the older ones too. Halfway through, a mesh is streamed in
 * (created, and drawn from then on): its frame uploads it and builds no pipeline; past the
 * first two frames, the others build nothing. */
static void frame_loop(uint32_t in_flight) {
    const int streamed_at = FRAMES / 2;
    translucid_context *ctx = host_context(in_flight);
    scene host, standalone;
    int k;
    uint32_t n;
    char what[64];
    make_scene(ctx, &host);
    make_scene(g_standalone, &standalone);
    for (k = 0; k < FRAMES; k++) {
        slot *s = &g_slots[k % in_flight];
        translucid_frame_info info;
        if (s->busy) {
            int done = k - (int)in_flight, allocated;
            /* The renderer allocates for its first frame and for its first move, the next. */
            int warm = done >= 2 && done != streamed_at;
            uint64_t pipelines;
            wait_fence(s->fence);
            CHECK(ctx, translucid_frame_complete(ctx, s->frame));
            built_by(ctx, s, &pipelines, &allocated);
            if (done == streamed_at) {
                TRUE_OR_FAIL(pipelines == 0);
            } else if (warm) {
                if (pipelines != 0 || allocated) {
                    printf("FAIL %u in flight, frame %d built %llu pipelines, allocated %d\n",
                           in_flight, done, (unsigned long long)pipelines, allocated);
                }
                TRUE_OR_FAIL(pipelines == 0 && !allocated);
            }
            snprintf(what, sizeof what, "%u in flight, frame %d", in_flight, done);
            views_add_up(ctx, s->frame, 1, what);
            compare(ctx, s, what);
        }
        if (k == streamed_at) {
            /* Quad 0 again, raised: nothing the renderer's shaders are specialized for
             * changes (a mesh reaching the near plane, say, would need a variant). */
            make_quad(ctx, 0, TRANSLUCID_MATERIAL_LIT, &host.meshes[3], &host.materials[3],
                      &host.draws[3]);
            make_quad(g_standalone, 0, TRANSLUCID_MATERIAL_LIT, &standalone.meshes[3],
                      &standalone.materials[3], &standalone.draws[3]);
            host.draws[3].transform[13] = standalone.draws[3].transform[13] = 0.3f;
        }
        move_scene(ctx, &host, &standalone, k);
        info = frame_info(&host, k < streamed_at ? QUADS : QUADS + 1,
                          orbit_camera(0.15f * (float)k));
        /* No quad reaches the near plane, whose path the first frame may not have built. */
        info.camera.z_near = 0.5f;
        render_expected(info, &standalone, s->expected);
        begin_commands(s->cmd);
        record_frame(ctx, s->cmd, s, &info);
        submit_commands(s->cmd, s->fence);
    }
    /* Every slot is in flight: wait for them all, complete the newest (the older ones
     * complete with it: they ran first, on the same queue), then check each. */
    for (n = 0; n < in_flight; n++) wait_fence(g_slots[n].fence);
    CHECK(ctx, translucid_frame_complete(ctx, g_slots[(FRAMES - 1) % in_flight].frame));
    for (n = 0; n < in_flight; n++) {
        slot *s = &g_slots[(FRAMES + n) % in_flight];
        EXPECT(ctx, translucid_frame_complete(ctx, s->frame),
               TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
        snprintf(what, sizeof what, "%u in flight, last frames, slot %u", in_flight, n);
        compare(ctx, s, what);
    }
    printf("%u frames in flight: %d moving frames as the standalone context renders them\n",
           in_flight, FRAMES);
    translucid_context_destroy(ctx);
}

/* 2. Two views of one frame, recorded into one command buffer over their own images. */
static void two_views(void) {
    translucid_context *ctx = host_context(2);
    scene host, standalone;
    translucid_frame_info left, right;
    make_scene(ctx, &host);
    make_scene(g_standalone, &standalone);
    left = frame_info(&host, QUADS + 1, orbit_camera(-0.3f));
    right = frame_info(&host, QUADS + 1, orbit_camera(0.3f));
    render_expected(left, &standalone, g_slots[0].expected);
    render_expected(right, &standalone, g_slots[1].expected);
    begin_commands(g_slots[0].cmd);
    record_frame(ctx, g_slots[0].cmd, &g_slots[0], &left);
    record_frame(ctx, g_slots[0].cmd, &g_slots[1], &right);
    submit_commands(g_slots[0].cmd, g_slots[0].fence);
    wait_fence(g_slots[0].fence);
    CHECK(ctx, translucid_frame_complete(ctx, g_slots[0].frame));
    CHECK(ctx, translucid_frame_complete(ctx, g_slots[1].frame));
    compare(ctx, &g_slots[0], "left view");
    compare(ctx, &g_slots[1], "right view");
    printf("two views in one command buffer as the standalone context renders them\n");
    translucid_context_destroy(ctx);
}

/* 3. The engine's projection: reversed-Z, infinite far plane, and a jitter. Its depth image
 * holds that projection's depth (near 1, far 0); the standalone layer takes 1 - d. */
static void engine_projection(void) {
    static const float reversed_bands[3] = {0.7f, 0.35f, 0.0f};
    translucid_context *ctx = host_context(1);
    scene host, standalone;
    translucid_frame_info info;
    translucid_camera camera = orbit_camera(0.2f);
    float f = 1.0f / tanf(0.45f), aspect = (float)W / (float)H, near = 1.0f;
    make_opaque_layer(reversed_bands, 1);
    memset(camera.projection, 0, sizeof camera.projection);
    /* Vulkan clip space, Y down: depth = near / distance. */
    camera.projection[0] = f / aspect;
    camera.projection[5] = -f;
    camera.projection[11] = -1.0f;
    camera.projection[14] = near;
    camera.jitter[0] = 0.3f;
    camera.jitter[1] = -0.4f;
    make_scene(ctx, &host);
    make_scene(g_standalone, &standalone);
    info = frame_info(&host, QUADS + 1, camera);
    render_expected(info, &standalone, g_slots[0].expected);
    begin_commands(g_slots[0].cmd);
    record_frame(ctx, g_slots[0].cmd, &g_slots[0], &info);
    submit_commands(g_slots[0].cmd, g_slots[0].fence);
    wait_fence(g_slots[0].fence);
    CHECK(ctx, translucid_frame_complete(ctx, g_slots[0].frame));
    compare(ctx, &g_slots[0], "reversed-Z, infinite far, jittered");
    printf("reversed-Z, infinite far plane and jitter as the standalone context renders them\n");
    translucid_context_destroy(ctx);
}

/* 4. A mesh destroyed while the frame drawing it is in flight: the frame keeps it. */
static void destroy_in_flight(void) {
    static const float forward_bands[3] = {0.3f, 0.75f, 1.0f};
    translucid_context *ctx = host_context(2);
    scene host, standalone;
    translucid_frame_info info;
    make_opaque_layer(forward_bands, 0);
    make_scene(ctx, &host);
    make_scene(g_standalone, &standalone);
    info = frame_info(&host, QUADS + 1, orbit_camera(0.0f));
    render_expected(info, &standalone, g_slots[0].expected);
    begin_commands(g_slots[0].cmd);
    record_frame(ctx, g_slots[0].cmd, &g_slots[0], &info);
    CHECK(ctx, translucid_mesh_destroy(ctx, host.meshes[QUADS]));
    submit_commands(g_slots[0].cmd, g_slots[0].fence);
    /* The next frame, without it, while the first is in flight. */
    info.draw_count = QUADS;
    render_expected(info, &standalone, g_slots[1].expected);
    begin_commands(g_slots[1].cmd);
    record_frame(ctx, g_slots[1].cmd, &g_slots[1], &info);
    submit_commands(g_slots[1].cmd, g_slots[1].fence);
    wait_fence(g_slots[0].fence);
    wait_fence(g_slots[1].fence);
    CHECK(ctx, translucid_frame_complete(ctx, g_slots[0].frame));
    CHECK(ctx, translucid_frame_complete(ctx, g_slots[1].frame));
    compare(ctx, &g_slots[0], "frame drawing a mesh destroyed in flight");
    compare(ctx, &g_slots[1], "frame after the destruction");
    info.draw_count = QUADS + 1;
    begin_commands(g_slots[0].cmd);
    {
        translucid_host_frame_targets t = targets_of(g_slots[0].cmd, &g_slots[0]);
        EXPECT(ctx, translucid_frame_record(ctx, &info, &t, &g_slots[0].frame),
               TRANSLUCID_RESULT_ERROR_STALE_HANDLE);
        TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "draws[3]") != NULL);
    }
    VK_CHECK(vkEndCommandBuffer(g_slots[0].cmd));
    printf("a mesh destroyed in flight stays with the frame that draws it\n");
    translucid_context_destroy(ctx);
}

/* One engine depth format: writes the engine's depth as its texels at `out` and the depth
 * they hold (what translucid reads) into g_layer_depth, turned around when reversed. */
static void encode_depth(VkFormat format, int reversed, uint8_t *out) {
    size_t i;
    for (i = 0; i < W * H; i++) {
        float d = g_engine_depth[i], held = d;
        if (format == VK_FORMAT_D16_UNORM) {
            uint16_t k = (uint16_t)((double)d * 65535.0 + 0.5);
            memcpy(out + i * 2, &k, 2);
            held = (float)k / 65535.0f;
        } else if (format == VK_FORMAT_X8_D24_UNORM_PACK32 ||
                   format == VK_FORMAT_D24_UNORM_S8_UINT) {
            uint32_t k = (uint32_t)((double)d * 16777215.0 + 0.5);
            memcpy(out + i * 4, &k, 4);
            held = (float)((double)k / 16777215.0);
        } else {
            memcpy(out + i * 4, &d, 4);
        }
        g_layer_depth[i] = reversed ? 1.0f - held : held;
    }
}

/* 6. Every depth format an engine may hand over, forward and reversed-Z: the opaque bands
 * hide part of the quads, read from each format (the stencil of D24S8 and D32S8 ignored). */
static void depth_formats(translucid_method method) {
    static const VkFormat formats[5] = {VK_FORMAT_D16_UNORM, VK_FORMAT_X8_D24_UNORM_PACK32,
                                        VK_FORMAT_D24_UNORM_S8_UINT, VK_FORMAT_D32_SFLOAT,
                                        VK_FORMAT_D32_SFLOAT_S8_UINT};
    static const float forward_bands[3] = {0.3f, 0.75f, 1.0f};
    static const float reversed_bands[3] = {0.7f, 0.35f, 0.0f};
    translucid_context *ctx = host_context(1);
    scene host, standalone;
    slot *s = &g_slots[0];
    int f, reversed;
    make_scene(ctx, &host);
    make_scene(g_standalone, &standalone);
    for (reversed = 0; reversed < 2; reversed++) {
        translucid_camera camera = orbit_camera(0.1f);
        translucid_frame_info info;
        if (reversed) {
            float focal = 1.0f / tanf(0.45f);
            camera.projection[0] = focal * (float)H / (float)W;
            camera.projection[5] = -focal;
            camera.projection[11] = -1.0f;
            camera.projection[14] = 1.0f;
        }
        make_opaque_layer(reversed ? reversed_bands : forward_bands, reversed);
        info = frame_info(&host, QUADS + 1, camera);
        info.method = method;
        for (f = 0; f < 5; f++) {
            VkFormat format = formats[f];
            int stencil = format == VK_FORMAT_D24_UNORM_S8_UINT ||
                          format == VK_FORMAT_D32_SFLOAT_S8_UINT;
            VkImageAspectFlags aspects =
                VK_IMAGE_ASPECT_DEPTH_BIT | (stencil ? VK_IMAGE_ASPECT_STENCIL_BIT : 0);
            VkImage depth = create_image(
                format,
                VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                    VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                W, H);
            VkDeviceMemory memory = bind_image(depth);
            translucid_host_frame_targets t = targets_of(s->cmd, s);
            char what[96];
            uint64_t pipelines;
            int allocated;
            encode_depth(format, reversed, s->mapped + COLOUR_BYTES);
            render_expected(info, &standalone, s->expected);
            t.depth.image = depth;
            t.depth.format = format;
            snprintf(what, sizeof what, "method %d, depth format %d%s", (int)method,
                     (int)format, reversed ? ", reversed-Z" : "");
            /* Prepared for these images, the frame into them builds nothing. */
            prepare_for(ctx, &info, &t);
            begin_commands(s->cmd);
            record_opaque_into(s->cmd, s, depth, aspects);
            CHECK(ctx, translucid_frame_record(ctx, &info, &t, &s->frame));
            record_readback(s->cmd, s);
            submit_commands(s->cmd, s->fence);
            wait_fence(s->fence);
            CHECK(ctx, translucid_frame_complete(ctx, s->frame));
            built_by(ctx, s, &pipelines, &allocated);
            if (pipelines != 0) {
                printf("FAIL %s: prepared, the frame built %llu pipelines\n", what,
                       (unsigned long long)pipelines);
            }
            TRUE_OR_FAIL(pipelines == 0);
            compare(ctx, s, what);
            vkDestroyImage(g_device, depth, NULL);
            vkFreeMemory(g_device, memory, NULL);
        }
    }
    printf("method %d: every depth format, forward and reversed-Z, as the standalone context "
           "renders it, prepared for\n",
           (int)method);
    translucid_context_destroy(ctx);
}

/* 5. Misuse in the frame loop. */
static void misuse(void) {
    translucid_host_device_create_info hd = host_device_info();
    translucid_context_create_info create;
    translucid_context *ctx = NULL;
    scene host;
    translucid_frame_info info;
    translucid_frame_statistics stats;
    translucid_frame extra;
    float positions[12];
    uint32_t n;

    memset(&create, 0, sizeof create);
    create.s_type = TRANSLUCID_STRUCTURE_TYPE_CONTEXT_CREATE_INFO;
    create.header_version = TRANSLUCID_HEADER_VERSION;
    create.mode = TRANSLUCID_CONTEXT_MODE_HOST_DEVICE;
    create.next = &hd;
    create.frames_in_flight = TRANSLUCID_MAX_FRAMES_IN_FLIGHT + 1;
    EXPECT(NULL, translucid_context_create(&create, &ctx), TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(NULL), "frames_in_flight") != NULL);
    /* Views past TRANSLUCID_MAX_VIEWS, or past the slots with the frames in flight; the
     * views' structure chained twice. */
    {
        translucid_host_views_create_info views, again;
        memset(&views, 0, sizeof views);
        views.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_VIEWS_CREATE_INFO;
        views.next = hd.next;
        hd.next = &views;
        create.frames_in_flight = 1;
        views.views_per_frame = TRANSLUCID_MAX_VIEWS + 1;
        EXPECT(NULL, translucid_context_create(&create, &ctx),
               TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
        TRUE_OR_FAIL(strstr(translucid_context_get_last_error(NULL), "views_per_frame") != NULL);
        create.frames_in_flight = TRANSLUCID_MAX_FRAMES_IN_FLIGHT / 2 + 1;
        views.views_per_frame = 2;
        EXPECT(NULL, translucid_context_create(&create, &ctx),
               TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
        TRUE_OR_FAIL(strstr(translucid_context_get_last_error(NULL), "views_per_frame") != NULL);
        create.frames_in_flight = 1;
        again = views;
        views.next = &again;
        EXPECT(NULL, translucid_context_create(&create, &ctx),
               TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
        TRUE_OR_FAIL(strstr(translucid_context_get_last_error(NULL), "chained twice") != NULL);
        hd = host_device_info();
    }
    create.mode = TRANSLUCID_CONTEXT_MODE_STANDALONE;
    create.next = NULL;
    create.frames_in_flight = 2;
    EXPECT(NULL, translucid_context_create(&create, &ctx), TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);

    ctx = host_context(MOST_IN_FLIGHT);
    make_scene(ctx, &host);
    info = frame_info(&host, QUADS, orbit_camera(0.0f));
    {
        /* Preparing for images no frame could record into, or with a stranger chained. */
        translucid_host_image_formats formats;
        translucid_frame_statistics wrong;
        translucid_prepare_info prepare;
        translucid_host_frame_targets t = targets_of(g_slots[0].cmd, &g_slots[0]);
        fill_prepare(&prepare, &formats, &info, &t, 0);
        formats.depth_format = VK_FORMAT_R32_SFLOAT;
        EXPECT(ctx, translucid_context_prepare(ctx, &prepare, NULL),
               TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
        TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "depth format") != NULL);
        formats.depth_format = VK_FORMAT_D32_SFLOAT;
        formats.colour_layout = VK_IMAGE_LAYOUT_UNDEFINED;
        EXPECT(ctx, translucid_context_prepare(ctx, &prepare, NULL),
               TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
        memset(&wrong, 0, sizeof wrong);
        wrong.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS;
        prepare.next = &wrong;
        EXPECT(ctx, translucid_context_prepare(ctx, &prepare, NULL),
               TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
        /* A standalone context records into no engine image. */
        formats.colour_layout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        prepare.next = &formats;
        info.draws = NULL;
        info.draw_count = 0;
        EXPECT(g_standalone, translucid_context_prepare(g_standalone, &prepare, NULL),
               TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
        info = frame_info(&host, QUADS, orbit_camera(0.0f));
    }
    /* Updates: a range past the mesh, a NaN, a destroyed mesh. */
    memcpy(positions, g_test_quads[0], sizeof positions);
    EXPECT(ctx, translucid_mesh_update(ctx, host.meshes[0], 2, 4, positions),
           TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
    EXPECT(ctx, translucid_mesh_update(ctx, host.meshes[0], 0, 0, positions),
           TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
    positions[4] = (float)NAN;
    EXPECT(ctx, translucid_mesh_update(ctx, host.meshes[0], 0, 4, positions),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    EXPECT(ctx, translucid_mesh_update(ctx, host.meshes[0], 0, 4, NULL),
           TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    CHECK(ctx, translucid_mesh_destroy(ctx, host.meshes[QUADS]));
    EXPECT(ctx, translucid_mesh_update(ctx, host.meshes[QUADS], 0, 4, g_test_quads[QUADS]),
           TRANSLUCID_RESULT_ERROR_STALE_HANDLE);

    /* Frame indices come back in the statistics, and may not go backwards (views of one
     * frame share theirs; 0 is none). */
    info.frame_index = 7;
    begin_commands(g_slots[0].cmd);
    record_frame(ctx, g_slots[0].cmd, &g_slots[0], &info);
    record_frame(ctx, g_slots[0].cmd, &g_slots[1], &info);
    info.frame_index = 6;
    {
        translucid_host_frame_targets t = targets_of(g_slots[0].cmd, &g_slots[2]);
        EXPECT(ctx, translucid_frame_record(ctx, &info, &t, &extra),
               TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
        TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "frame_index 6 after 7") !=
                     NULL);
    }
    submit_commands(g_slots[0].cmd, g_slots[0].fence);
    wait_fence(g_slots[0].fence);
    CHECK(ctx, translucid_frame_complete(ctx, g_slots[1].frame));
    for (n = 0; n < 2; n++) {
        memset(&stats, 0, sizeof stats);
        stats.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS;
        CHECK(ctx, translucid_frame_get_statistics(ctx, g_slots[n].frame, &stats));
        TRUE_OR_FAIL(stats.frame_index == 7);
        CHECK(ctx, translucid_frame_destroy(ctx, g_slots[n].frame));
        g_slots[n].busy = 0;
    }
    info.frame_index = 0;

    /* A view over the largest frame the device renders, its images as large: refused for
     * its size, in the header's terms. */
    {
        translucid_frame_info big = info;
        translucid_host_frame_targets t = targets_of(g_slots[0].cmd, &g_slots[0]);
        VkPhysicalDeviceProperties props;
        const char *message;
        vkGetPhysicalDeviceProperties(g_physical, &props);
        big.width = t.colour.width = t.depth.width = props.limits.maxImageDimension2D + 1;
        EXPECT(ctx, translucid_frame_record(ctx, &big, &t, &extra),
               TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
        message = translucid_context_get_last_error(ctx);
        TRUE_OR_FAIL(strstr(message, "translucid_frame_info.width") != NULL &&
                     strstr(message, "maxImageDimension2D") != NULL);
    }

    /* A region the images do not hold, and chained structures repeated: refused before
     * anything is recorded. */
    {
        translucid_host_frame_targets t = targets_of(g_slots[0].cmd, &g_slots[0]);
        translucid_host_image_region place, again;
        memset(&place, 0, sizeof place);
        place.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_IMAGE_REGION;
        place.x = 1;
        t.next = &place;
        EXPECT(ctx, translucid_frame_record(ctx, &info, &t, &extra),
               TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
        TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "from (1, 0)") != NULL);
        again = place;
        place.x = 0;
        place.next = &again;
        EXPECT(ctx, translucid_frame_record(ctx, &info, &t, &extra),
               TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
        TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "chained twice") != NULL);
        VK_CHECK(vkResetCommandBuffer(g_slots[0].cmd, 0));
    }

    /* Frames of several views that cannot be: refused before anything is recorded. */
    {
        translucid_host_frame_targets t = targets_of(g_slots[0].cmd, &g_slots[0]);
        translucid_host_image_region place;
        translucid_frame_view list[2];
        translucid_host_frame_views views;
        const char *message;
        memset(list, 0, sizeof list);
        list[0].camera = list[1].camera = info.camera;
        memset(&views, 0, sizeof views);
        views.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_FRAME_VIEWS;
        views.views = list;
        t.next = &views;
        /* No view. */
        EXPECT(ctx, translucid_frame_record(ctx, &info, &t, &extra),
               TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
        TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "view_count is 0") != NULL);
        /* More views than the context was made for (1), said before anything else of them. */
        views.view_count = 2;
        EXPECT(ctx, translucid_frame_record(ctx, &info, &t, &extra),
               TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
        TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "views_per_frame") != NULL);
        /* Two views in one place, on a context of two views a frame. */
        {
            translucid_context *two = host_context_views(1, 2);
            EXPECT(two, translucid_frame_record(two, &info, &t, &extra),
                   TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
            message = translucid_context_get_last_error(two);
            TRUE_OR_FAIL(strstr(message, "views[1] overlaps views[0]") != NULL);
            translucid_context_destroy(two);
        }
        /* A layer past the count given. */
        list[1].colour_layer = list[1].depth_layer = 1;
        EXPECT(ctx, translucid_frame_record(ctx, &info, &t, &extra),
               TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
        TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "views[1]: colour_layer") !=
                     NULL);
        views.colour_layer_count = views.depth_layer_count = 2;
        /* A view without a camera. */
        memset(&list[1].camera, 0, sizeof list[1].camera);
        EXPECT(ctx, translucid_frame_record(ctx, &info, &t, &extra),
               TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
        TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "views[1]: translucid_camera") !=
                     NULL);
        /* Views with a region besides. */
        memset(&place, 0, sizeof place);
        place.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_IMAGE_REGION;
        place.next = &views;
        t.next = &place;
        EXPECT(ctx, translucid_frame_record(ctx, &info, &t, &extra),
               TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
        TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "alone") != NULL);
        VK_CHECK(vkResetCommandBuffer(g_slots[0].cmd, 0));
    }

    /* As many frames in flight as the context takes; one more is refused. The first is
     * submitted, the others are not: abandoning the second ends it and the third, and the
     * first completes as usual. */
    for (n = 0; n < MOST_IN_FLIGHT; n++) {
        begin_commands(g_slots[n].cmd);
        record_frame(ctx, g_slots[n].cmd, &g_slots[n], &info);
    }
    {
        translucid_host_frame_targets t = targets_of(g_slots[0].cmd, &g_slots[0]);
        EXPECT(ctx, translucid_frame_record(ctx, &info, &t, &extra),
               TRANSLUCID_RESULT_ERROR_FRAME_IN_FLIGHT);
        TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "frames_in_flight") != NULL);
    }
    submit_commands(g_slots[0].cmd, g_slots[0].fence);
    CHECK(ctx, translucid_frame_abandon(ctx, g_slots[1].frame));
    EXPECT(ctx, translucid_frame_destroy(ctx, g_slots[1].frame), TRANSLUCID_RESULT_ERROR_STALE_HANDLE);
    memset(&stats, 0, sizeof stats);
    stats.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS;
    EXPECT(ctx, translucid_frame_get_statistics(ctx, g_slots[2].frame, &stats),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    EXPECT(ctx, translucid_frame_complete(ctx, g_slots[2].frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    CHECK(ctx, translucid_frame_destroy(ctx, g_slots[2].frame));
    /* Their command buffers are dropped, never submitted. */
    VK_CHECK(vkEndCommandBuffer(g_slots[1].cmd));
    VK_CHECK(vkEndCommandBuffer(g_slots[2].cmd));
    g_slots[1].busy = g_slots[2].busy = 0;
    wait_fence(g_slots[0].fence);
    CHECK(ctx, translucid_frame_complete(ctx, g_slots[0].frame));
    CHECK(ctx, translucid_frame_destroy(ctx, g_slots[0].frame));
    g_slots[0].busy = 0;
    /* And the loop goes on. */
    begin_commands(g_slots[1].cmd);
    record_frame(ctx, g_slots[1].cmd, &g_slots[1], &info);
    submit_commands(g_slots[1].cmd, g_slots[1].fence);
    wait_fence(g_slots[1].fence);
    CHECK(ctx, translucid_frame_complete(ctx, g_slots[1].frame));
    CHECK(ctx, translucid_frame_destroy(ctx, g_slots[1].frame));
    g_slots[1].busy = 0;
    translucid_context_destroy(ctx);
}

/* 7. Each method, warmed by two frames; then two frames recorded and never submitted, the
 * first carrying a streamed-in mesh's upload and moved vertices, are abandoned (as for an
 * out-of-date swapchain). The next frame builds no pipeline (its renderer was kept, with its
 * pipelines and buffers; its completion may grow buffers for the streamed mesh, as it would
 * have without the abandon), and it draws the streamed, moved mesh as the standalone context
 * does. */
static void abandon_keeps_what_is_built(translucid_method method) {
    translucid_context *ctx = host_context(MOST_IN_FLIGHT);
    scene host, standalone;
    translucid_frame_info info;
    translucid_frame_statistics stats;
    uint64_t pipelines;
    int k, allocated, worst;
    make_scene(ctx, &host);
    make_scene(g_standalone, &standalone);
    for (k = 0; k < 5; k++) {
        slot *s = &g_slots[k % MOST_IN_FLIGHT];
        if (k == 2) {
            make_quad(ctx, 0, TRANSLUCID_MATERIAL_LIT, &host.meshes[3], &host.materials[3],
                      &host.draws[3]);
            make_quad(g_standalone, 0, TRANSLUCID_MATERIAL_LIT, &standalone.meshes[3],
                      &standalone.materials[3], &standalone.draws[3]);
            host.draws[3].transform[13] = standalone.draws[3].transform[13] = 0.3f;
        }
        if (k <= 2) move_scene(ctx, &host, &standalone, k);
        info = frame_info(&host, k < 2 ? QUADS : QUADS + 1, orbit_camera(0.1f * (float)k));
        info.method = method;
        info.camera.z_near = 0.5f;
        begin_commands(s->cmd);
        record_frame(ctx, s->cmd, s, &info);
        if (k == 3) {
            /* Frames 2 and 3 are dropped unsubmitted. */
            CHECK(ctx, translucid_frame_abandon(ctx, g_slots[2].frame));
            CHECK(ctx, translucid_frame_destroy(ctx, g_slots[0].frame));
            VK_CHECK(vkEndCommandBuffer(g_slots[2].cmd));
            VK_CHECK(vkEndCommandBuffer(g_slots[0].cmd));
            g_slots[2].busy = g_slots[0].busy = 0;
            continue;
        }
        if (k == 2) continue;
        submit_commands(s->cmd, s->fence);
        wait_fence(s->fence);
        CHECK(ctx, translucid_frame_complete(ctx, s->frame));
        if (k < 2) {
            CHECK(ctx, translucid_frame_destroy(ctx, s->frame));
            s->busy = 0;
        }
    }
    /* Frame 4, in slot 1. */
    built_by(ctx, &g_slots[1], &pipelines, &allocated);
    render_expected(info, &standalone, g_slots[1].expected);
    worst = worst_difference(g_slots[1].mapped + COLOUR_BYTES + DEPTH_BYTES, g_slots[1].expected);
    memset(&stats, 0, sizeof stats);
    stats.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS;
    CHECK(ctx, translucid_frame_get_statistics(ctx, g_slots[1].frame, &stats));
    if (pipelines != 0 || worst > 2 || stats.overflowed) {
        printf("FAIL method %d after abandoned frames: %llu pipelines built, "
               "%d/255 off the standalone frame, overflowed %u\n",
               (int)method, (unsigned long long)pipelines, worst, (unsigned)stats.overflowed);
    }
    TRUE_OR_FAIL(pipelines == 0 && worst <= 2 && !stats.overflowed);
    CHECK(ctx, translucid_frame_destroy(ctx, g_slots[1].frame));
    g_slots[1].busy = 0;
    printf("method %d: abandoned frames cost the next one nothing\n", (int)method);
    translucid_context_destroy(ctx);
    CHECK(g_standalone, translucid_mesh_destroy(g_standalone, standalone.meshes[3]));
}

/* Section 8's assets, each bringing content the frames before did not draw. */
enum streamed {
    CORNER_COLOURS,
    FIRST_TEXTURE,
    FIRST_LIT,
    FIRST_TRANSMISSIVE,
    NEAR_PLANE,
    DEEP_STACK,
    STREAMED_KINDS
};
static const char *const k_streamed_names[STREAMED_KINDS] = {
    "vertex colours per corner",     "a first texture",
    "a first lit material",          "a first transmissive material",
    "a first near-plane crossing",   "a stack making the frame deep"};
/* The deep stack: quads one behind another over the middle quarter of the frame, nearer than
 * the opaque layer: about 11 fragments a pixel over the frame, and 40 where it is. */
#define STACK 40

/* Creates streamed asset `kind` in `ctx`: a mesh, its material (and texture), and a draw. */
static void stream_in(translucid_context *ctx, enum streamed kind, translucid_mesh *mesh,
                      translucid_material *material, translucid_draw *draw) {
    static const uint32_t triangles[] = {0, 1, 2, 0, 2, 3};
    static const float corner_colours[16] = {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1, 1, 1, 1, 1};
    static const float uvs[8] = {0, 0, 1, 0, 1, 1, 0, 1};
    static const uint8_t texels[16] = {255, 40, 40, 255, 40, 255, 40, 160,
                                       40, 40, 255, 255, 250, 250, 40, 200};
    /* From behind the eye (at the origin, near plane 1) to well in front of it. */
    static const float crossing[12] = {-0.6f, -0.4f, 0.5f, 0.6f, -0.4f, 0.5f,
                                       0.6f,  -0.1f, -4.0f, -0.6f, -0.1f, -4.0f};
    static float stack[STACK * 12];
    static uint32_t stack_triangles[STACK * 6];
    translucid_mesh_create_info mesh_info;
    translucid_material_create_info material_info;
    memset(&mesh_info, 0, sizeof mesh_info);
    mesh_info.s_type = TRANSLUCID_STRUCTURE_TYPE_MESH_CREATE_INFO;
    mesh_info.primitive = TRANSLUCID_PRIMITIVE_TRIANGLES;
    mesh_info.vertex_count = 4;
    mesh_info.positions = kind == NEAR_PLANE ? crossing : g_test_quads[(size_t)kind % TEST_QUADS];
    mesh_info.index_count = 6;
    mesh_info.indices = triangles;
    memset(&material_info, 0, sizeof material_info);
    material_info.s_type = TRANSLUCID_STRUCTURE_TYPE_MATERIAL_CREATE_INFO;
    material_info.base_colour[0] = 0.9f;
    material_info.base_colour[1] = 0.7f;
    material_info.base_colour[2] = 0.3f;
    material_info.base_colour[3] = 0.5f;
    switch (kind) {
    case CORNER_COLOURS:
        mesh_info.colours = corner_colours;
        break;
    case FIRST_TEXTURE: {
        translucid_texture_create_info texture;
        memset(&texture, 0, sizeof texture);
        texture.s_type = TRANSLUCID_STRUCTURE_TYPE_TEXTURE_CREATE_INFO;
        texture.width = texture.height = 2;
        texture.texels = texels;
        CHECK(ctx, translucid_texture_create(ctx, &texture, &material_info.texture));
        mesh_info.uvs = uvs;
        break;
    }
    case FIRST_LIT:
        material_info.flags = TRANSLUCID_MATERIAL_LIT;
        break;
    case FIRST_TRANSMISSIVE:
        material_info.transmission = 0.6f;
        material_info.transmission_tint[0] = 0.2f;
        material_info.transmission_tint[1] = 0.8f;
        material_info.transmission_tint[2] = 0.9f;
        break;
    case DEEP_STACK: {
        uint32_t q, v;
        for (q = 0; q < STACK; q++) {
            /* z from -1.1 to -1.3: in front of the opaque layer's nearest band (1.37). */
            float z = -1.1f - 0.2f * (float)q / STACK;
            static const float corners[4][2] = {
                {-0.4f, -0.3f}, {0.4f, -0.3f}, {0.4f, 0.3f}, {-0.4f, 0.3f}};
            for (v = 0; v < 4; v++) {
                stack[q * 12 + v * 3] = corners[v][0];
                stack[q * 12 + v * 3 + 1] = corners[v][1];
                stack[q * 12 + v * 3 + 2] = z;
            }
            for (v = 0; v < 6; v++) stack_triangles[q * 6 + v] = q * 4 + triangles[v];
        }
        mesh_info.positions = stack;
        mesh_info.vertex_count = STACK * 4;
        mesh_info.indices = stack_triangles;
        mesh_info.index_count = STACK * 6;
        material_info.base_colour[3] = 0.1f;
        break;
    }
    default:
        break;
    }
    CHECK(ctx, translucid_mesh_create(ctx, &mesh_info, mesh));
    CHECK(ctx, translucid_material_create(ctx, &material_info, material));
    memset(draw, 0, sizeof *draw);
    draw->mesh = *mesh;
    draw->material = *material;
    draw->layer = TRANSLUCID_LAYER_TRANSPARENT;
    draw->transform[0] = draw->transform[5] = draw->transform[10] = draw->transform[15] = 1.0f;
    /* Apart from the quads already drawn. */
    if (kind != NEAR_PLANE && kind != DEEP_STACK) {
        draw->transform[12] = 0.25f * (float)kind - 0.5f;
        draw->transform[13] = 0.2f;
    }
}

/* A frame of `count` draws by `method` from section 8's camera. The section's draws make at
 * most 47 layers: depth_peeling peels them all in its fixed passes, and linked_list's fixed
 * pool holds them, so that no frame is sized by the one before (as section 8 streams in more
 * layers, those frames would be, and complete degraded). */
static translucid_frame_info frame_of(translucid_draw *draws, uint32_t count,
                                      translucid_method method) {
    static translucid_depth_peeling_settings peeling;
    static translucid_linked_list_settings lists;
    translucid_frame_info info;
    memset(&peeling, 0, sizeof peeling);
    peeling.s_type = TRANSLUCID_STRUCTURE_TYPE_DEPTH_PEELING_SETTINGS;
    peeling.passes = 24;
    memset(&lists, 0, sizeof lists);
    lists.s_type = TRANSLUCID_STRUCTURE_TYPE_LINKED_LIST_SETTINGS;
    lists.node_budget = W * H * 48;
    memset(&info, 0, sizeof info);
    if (method == TRANSLUCID_METHOD_DEPTH_PEELING) info.next = &peeling;
    if (method == TRANSLUCID_METHOD_LINKED_LIST) info.next = &lists;
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
    info.method = method;
    info.width = W;
    info.height = H;
    info.camera = orbit_camera(0.0f);
    info.draws = draws;
    info.draw_count = count;
    return info;
}

/* The slot's readback against the standalone frame, for any method; its frame destroyed.
 * Within 2/255, but for blend, which on the engine's device blends straight into the
 * engine's 8-bit sRGB image, rounding after each layer, where the standalone frame blends in
 * floats: measured 6/255 where section 8's deep stack puts over 40 layers. */
static void compare_any(translucid_context *ctx, slot *s, const char *what,
                        translucid_method method) {
    translucid_frame_statistics stats;
    int bound = method == TRANSLUCID_METHOD_BLEND ? 8 : 2;
    int worst = worst_difference(s->mapped + COLOUR_BYTES + DEPTH_BYTES, s->expected);
    memset(&stats, 0, sizeof stats);
    stats.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS;
    CHECK(ctx, translucid_frame_get_statistics(ctx, s->frame, &stats));
    if (worst > bound || stats.overflowed) {
        printf("FAIL %s: %d/255 off the standalone frame, overflowed %u\n", what, worst,
               (unsigned)stats.overflowed);
    }
    TRUE_OR_FAIL(worst <= bound && !stats.overflowed);
    CHECK(ctx, translucid_frame_destroy(ctx, s->frame));
    s->busy = 0;
}

/* Section 8's draws in the host context ([0]) and the standalone one ([1]): two plain quads
 * (unlit, untextured, one colour each, in front of the near plane), then the streamed assets. */
typedef struct streamed_scene {
    translucid_draw draws[2][2 + STREAMED_KINDS];
    translucid_mesh meshes[2][2 + STREAMED_KINDS];
    translucid_material materials[2][2 + STREAMED_KINDS];
} streamed_scene;

static void make_plain_quads(translucid_context *ctx, streamed_scene *sc) {
    size_t k;
    for (k = 0; k < 2; k++) {
        make_quad(ctx, k, 0, &sc->meshes[0][k], &sc->materials[0][k], &sc->draws[0][k]);
        make_quad(g_standalone, k, 0, &sc->meshes[1][k], &sc->materials[1][k],
                  &sc->draws[1][k]);
    }
}

/* The slot's completed frame built no pipeline and is as the standalone context rendered it
 * (its frame destroyed); `what` names it. */
static void built_nothing_and_right(translucid_context *ctx, slot *s, const char *what,
                                    translucid_method method) {
    uint64_t pipelines;
    int allocated;
    built_by(ctx, s, &pipelines, &allocated);
    if (pipelines != 0) printf("FAIL %s: %llu pipelines built\n", what,
                               (unsigned long long)pipelines);
    TRUE_OR_FAIL(pipelines == 0);
    compare_any(ctx, s, what, method);
}

/* `ctx`'s frames of the plain quads, the first, then one per kind streamed in before it,
 * and one more (deep frames move to their variants after the first deep frame completes):
 * each builds no pipeline and is as the standalone context renders it. `loop` names them. */
static void stream_every_kind(translucid_context *ctx, translucid_method method,
                              streamed_scene *sc, const char *loop) {
    translucid_frame_info info;
    int k;
    char what[112];
    for (k = 0; k <= STREAMED_KINDS + 1; k++) {
        slot *s = &g_slots[k % MOST_IN_FLIGHT];
        int draws = 2 + (k > STREAMED_KINDS ? STREAMED_KINDS : k), i;
        if (k > 0 && k <= STREAMED_KINDS) {
            for (i = 0; i < 2; i++) {
                stream_in(i == 0 ? ctx : g_standalone, (enum streamed)(k - 1),
                          &sc->meshes[i][k + 1], &sc->materials[i][k + 1],
                          &sc->draws[i][k + 1]);
            }
        }
        info = frame_of(sc->draws[1], (uint32_t)draws, method);
        render_standalone(g_standalone, info, g_opaque_colour, g_layer_depth, s->expected,
                          COLOUR_BYTES);
        info.draws = sc->draws[0];
        run_frame(ctx, s, &info);
        snprintf(what, sizeof what, "method %d, %s, %s", (int)method, loop,
                 k == 0                 ? "first frame"
                 : k > STREAMED_KINDS ? "the frame after the deep one"
                                        : k_streamed_names[k - 1]);
        built_nothing_and_right(ctx, s, what, method);
    }
}

static void destroy_standalone_assets(streamed_scene *sc) {
    int k;
    for (k = 0; k < 2 + STREAMED_KINDS; k++) {
        CHECK(g_standalone, translucid_mesh_destroy(g_standalone, sc->meshes[1][k]));
        CHECK(g_standalone, translucid_material_destroy(g_standalone, sc->materials[1][k]));
    }
}

/* Section 8, after the streamed kinds past the declaration: the deep stack, most of the
 * assets' bytes, destroyed and made again, so that the next frame uploads the assets anew and
 * makes its renderer anew over deep pixels the loop did not declare. It starts where the one
 * it replaces drew (its depth too), building nothing. */
static void uploaded_anew_past_the_declaration(translucid_context *ctx, translucid_method method,
                                               streamed_scene *sc) {
    const int stack = 2 + DEEP_STACK, draws = 2 + STREAMED_KINDS;
    translucid_frame_info info;
    uint64_t pipelines;
    int allocated;
    char what[96];
    CHECK(ctx, translucid_mesh_destroy(ctx, sc->meshes[0][stack]));
    CHECK(ctx, translucid_material_destroy(ctx, sc->materials[0][stack]));
    stream_in(ctx, DEEP_STACK, &sc->meshes[0][stack], &sc->materials[0][stack],
              &sc->draws[0][stack]);
    info = frame_of(sc->draws[1], (uint32_t)draws, method);
    render_standalone(g_standalone, info, g_opaque_colour, g_layer_depth, g_slots[0].expected,
                      COLOUR_BYTES);
    info.draws = sc->draws[0];
    run_frame(ctx, &g_slots[0], &info);
    /* Uploaded anew: the frame allocated. */
    built_by(ctx, &g_slots[0], &pipelines, &allocated);
    TRUE_OR_FAIL(allocated);
    snprintf(what, sizeof what, "method %d, past the declaration, uploaded anew", (int)method);
    built_nothing_and_right(ctx, &g_slots[0], what, method);
}

/* Section 8, the loop declaring `content` (besides what its first frame draws). */
static void declared_loop(translucid_method method, uint32_t content) {
    translucid_context *ctx = host_context(MOST_IN_FLIGHT);
    translucid_host_frame_targets t = targets_of(g_slots[0].cmd, &g_slots[0]);
    static streamed_scene sc;
    translucid_frame_info info;
    uint64_t built;
    make_plain_quads(ctx, &sc);
    info = frame_of(sc.draws[0], 2, method);
    built = prepare_declaring(ctx, &info, &t, content);
    printf("method %d: prepare for content %#x built %llu pipelines\n", (int)method,
           (unsigned)content, (unsigned long long)built);
    stream_every_kind(ctx, method, &sc,
                      content == TRANSLUCID_CONTENT_ALL ? "declared loop"
                                                        : "past the declaration");
    if (content == 0) uploaded_anew_past_the_declaration(ctx, method, &sc);
    translucid_context_destroy(ctx);
    destroy_standalone_assets(&sc);
}

/* Section 8, last: exact prepared for the plain quads, then wavelet prepared for a frame that
 * also draws a textured quad. What wavelet's frame draws is declared for wavelet's frames
 * alone: exact's next frame, of the plain quads, builds nothing. */
static void preparing_another_method_keeps_the_first(void) {
    translucid_context *ctx = host_context(MOST_IN_FLIGHT);
    translucid_host_frame_targets t = targets_of(g_slots[0].cmd, &g_slots[0]);
    static streamed_scene sc;
    translucid_frame_info info;
    int k;
    make_plain_quads(ctx, &sc);
    for (k = 0; k < 2; k++) {
        stream_in(k == 0 ? ctx : g_standalone, FIRST_TEXTURE, &sc.meshes[k][2],
                  &sc.materials[k][2], &sc.draws[k][2]);
    }
    info = frame_of(sc.draws[0], 2, TRANSLUCID_METHOD_EXACT);
    prepare_declaring(ctx, &info, &t, 0);
    run_frame(ctx, &g_slots[0], &info);
    info = frame_of(sc.draws[0], 3, TRANSLUCID_METHOD_WAVELET);
    prepare_declaring(ctx, &info, &t, 0);
    info = frame_of(sc.draws[1], 2, TRANSLUCID_METHOD_EXACT);
    render_standalone(g_standalone, info, g_opaque_colour, g_layer_depth, g_slots[1].expected,
                      COLOUR_BYTES);
    info.draws = sc.draws[0];
    run_frame(ctx, &g_slots[1], &info);
    built_nothing_and_right(ctx, &g_slots[1], "exact after wavelet was prepared for more",
                            TRANSLUCID_METHOD_EXACT);
    CHECK(ctx, translucid_frame_destroy(ctx, g_slots[0].frame));
    translucid_context_destroy(ctx);
    for (k = 0; k < 3; k++) {
        CHECK(g_standalone, translucid_mesh_destroy(g_standalone, sc.meshes[1][k]));
        CHECK(g_standalone, translucid_material_destroy(g_standalone, sc.materials[1][k]));
    }
}

/* 14. A level streamed in while the loop plays: the loop's plain quads prepared for at
 * load time, then everything the next level may draw prepared in the background while frames
 * go on (each builds nothing and is right); once that is taken in, assets of every kind that
 * changes a shader variant, streamed in one per frame, build nothing either. A context
 * destroyed while such work runs waits for it. */
#define BACKGROUND_FRAMES 24
static void background_prepare(translucid_method method) {
    translucid_context *ctx = host_context(MOST_IN_FLIGHT);
    static streamed_scene sc;
    translucid_host_image_formats formats;
    translucid_prepare_info prepare;
    translucid_host_frame_targets t = targets_of(g_slots[0].cmd, &g_slots[0]);
    translucid_frame_info info;
    translucid_result status = TRANSLUCID_RESULT_NOT_READY;
    uint64_t built = 0, pipelines;
    int k, allocated, meanwhile = 0;
    make_plain_quads(ctx, &sc);
    info = frame_of(sc.draws[0], 2, method);
    fill_prepare(&prepare, &formats, &info, &t, 0);
    CHECK(ctx, translucid_context_prepare(ctx, &prepare, NULL));
    prepare.content = TRANSLUCID_CONTENT_ALL;
    CHECK(ctx, translucid_context_prepare_in_background(ctx, &prepare));
    /* The loop goes on, one frame per slot in turn, until the work is taken in (past
     * BACKGROUND_FRAMES frames, the test only waits). */
    for (k = 0; status == TRANSLUCID_RESULT_NOT_READY; k++) {
        slot *s = &g_slots[k % MOST_IN_FLIGHT];
        status = translucid_context_get_prepare_status(ctx, &built);
        if (status != TRANSLUCID_RESULT_NOT_READY) {
            CHECK(ctx, status);
            break;
        }
        if (k >= BACKGROUND_FRAMES) {
            const struct timespec pause = {0, 10 * 1000 * 1000};
            nanosleep(&pause, NULL);
            continue;
        }
        info = frame_of(sc.draws[1], 2, method);
        info.camera = orbit_camera(0.05f * (float)k);
        render_standalone(g_standalone, info, g_opaque_colour, g_layer_depth, s->expected,
                          COLOUR_BYTES);
        info.draws = sc.draws[0];
        run_frame(ctx, s, &info);
        built_by(ctx, s, &pipelines, &allocated);
        if (pipelines != 0) {
            printf("FAIL method %d, frame %d while preparing in the background: %llu "
                   "pipelines built\n",
                   (int)method, k, (unsigned long long)pipelines);
        }
        TRUE_OR_FAIL(pipelines == 0);
        compare_any(ctx, s, "a frame while preparing in the background", method);
        meanwhile++;
    }
    /* exact and wavelet have variants for content the loop did not draw; the other methods
     * had built everything for the loop. */
    if (method == TRANSLUCID_METHOD_EXACT || method == TRANSLUCID_METHOD_WAVELET) {
        if (built == 0) printf("FAIL method %d: the background work built nothing\n", (int)method);
        TRUE_OR_FAIL(built > 0);
    }
    printf("method %d: %llu pipelines built in the background while %d frames went on\n",
           (int)method, (unsigned long long)built, meanwhile);
    stream_every_kind(ctx, method, &sc, "prepared in the background");
    translucid_context_destroy(ctx);
    destroy_standalone_assets(&sc);
    /* Destroyed while the work runs: the destruction waits for it. */
    ctx = host_context(MOST_IN_FLIGHT);
    make_quad(ctx, 0, 0, &sc.meshes[0][0], &sc.materials[0][0], &sc.draws[0][0]);
    info = frame_of(sc.draws[0], 1, method);
    fill_prepare(&prepare, &formats, &info, &t, TRANSLUCID_CONTENT_ALL);
    CHECK(ctx, translucid_context_prepare_in_background(ctx, &prepare));
    translucid_context_destroy(ctx);
}

/* The context's GPU memory now, in bytes. */
static uint64_t memory_of(translucid_context *ctx) {
    translucid_memory_statistics memory;
    memset(&memory, 0, sizeof memory);
    memory.s_type = TRANSLUCID_STRUCTURE_TYPE_MEMORY_STATISTICS;
    CHECK(ctx, translucid_context_get_memory_statistics(ctx, &memory));
    TRUE_OR_FAIL(memory.total_bytes == memory.device_local_bytes + memory.per_frame_bytes +
                                           memory.staging_bytes + memory.readback_bytes);
    return memory.total_bytes;
}

/* 9. Frames at the images' size, then at half of it (a dynamic resolution: the renderer keeps
 * the buffers of the largest), then a trim: memory goes down, and the next half-size frame
 * builds no pipeline, is not degraded, and holds less memory than before the trim. */
static void trim_after_a_resolution_drop(translucid_method method) {
    translucid_context *ctx = host_context(1);
    scene host;
    translucid_frame_info info;
    uint64_t before, freed = 0, after, pipelines;
    int k, allocated;
    make_scene(ctx, &host);
    info = frame_info(&host, QUADS, orbit_camera(0.2f));
    info.method = method;
    for (k = 0; k < 3; k++) {
        slot *s = &g_slots[0];
        if (k == 1) {
            info.width = W / 2;
            info.height = H / 2;
        }
        if (k == 2) {
            before = memory_of(ctx);
            CHECK(ctx, translucid_context_trim(ctx, &freed));
            after = memory_of(ctx);
            if (freed == 0 || after + freed != before) {
                printf("FAIL method %d: trim freed %llu of %llu bytes, %llu left\n", (int)method,
                       (unsigned long long)freed, (unsigned long long)before,
                       (unsigned long long)after);
            }
            TRUE_OR_FAIL(freed > 0 && after + freed == before);
        }
        run_frame(ctx, s, &info);
        built_by(ctx, s, &pipelines, &allocated);
        if (k == 2) {
            after = memory_of(ctx);
            printf("method %d: %llu bytes at %dx%d, %llu trimmed, %llu at %dx%d after the "
                   "next frame, which built %llu pipelines\n",
                   (int)method, (unsigned long long)before, W, H, (unsigned long long)freed,
                   (unsigned long long)after, W / 2, H / 2, (unsigned long long)pipelines);
            TRUE_OR_FAIL(pipelines == 0 && after < before);
        }
        CHECK(ctx, translucid_frame_destroy(ctx, s->frame));
        s->busy = 0;
    }
    translucid_context_destroy(ctx);
}

/* 10. Stereo, 3 frames in flight: frame k records its left and right views into slots
 * 2 (k % 3) and 2 (k % 3) + 1, in the left slot's command buffer; when the engine comes back
 * to them, it waits, completes the right view (which completes the left, recorded first)
 * and checks both against the standalone context's single-view frames. */
static void stereo_in_flight(void) {
    translucid_context *ctx = host_context(MOST_IN_FLIGHT * VIEWS);
    scene host, standalone;
    int k, v, allocated;
    uint64_t pipelines;
    char what[64];
    make_scene(ctx, &host);
    make_scene(g_standalone, &standalone);
    for (k = 0; k < FRAMES + MOST_IN_FLIGHT; k++) {
        slot *views = &g_slots[(k % MOST_IN_FLIGHT) * VIEWS];
        if (views[0].busy) {
            int done = k - MOST_IN_FLIGHT;
            wait_fence(views[0].fence);
            CHECK(ctx, translucid_frame_complete(ctx, views[VIEWS - 1].frame));
            for (v = 0; v < VIEWS; v++) {
                built_by(ctx, &views[v], &pipelines, &allocated);
                if (done > 0 && pipelines != 0) {
                    printf("FAIL stereo frame %d, view %d: %llu pipelines built\n", done, v,
                           (unsigned long long)pipelines);
                }
                TRUE_OR_FAIL(done == 0 || pipelines == 0);
                snprintf(what, sizeof what, "stereo frame %d, view %d", done, v);
                compare(ctx, &views[v], what);
            }
        }
        if (k >= FRAMES) continue;
        move_scene(ctx, &host, &standalone, k);
        begin_commands(views[0].cmd);
        for (v = 0; v < VIEWS; v++) {
            /* Eyes 6 cm apart, turning with the frame. */
            translucid_frame_info info =
                frame_info(&host, QUADS, orbit_camera(0.1f * (float)k + (v ? 0.03f : -0.03f)));
            info.camera.z_near = 0.5f;
            info.frame_index = (uint64_t)k + 1;
            render_expected(info, &standalone, views[v].expected);
            record_frame(ctx, views[0].cmd, &views[v], &info);
        }
        submit_commands(views[0].cmd, views[0].fence);
    }
    printf("stereo: %d frames of %d views, %d frames in flight, as the standalone context "
           "renders each view\n",
           FRAMES, VIEWS, MOST_IN_FLIGHT);
    translucid_context_destroy(ctx);
}

/* 11. Section 8's two quads, then from frame DEEP_FROM on its deep stack too, 3 frames in
 * flight: each frame completed when the engine comes back to its slot. */
#define DEEP_FRAMES 8
#define DEEP_FROM 3
static void grows_deep_in_flight(translucid_method method) {
    translucid_context *ctx = host_context(MOST_IN_FLIGHT);
    translucid_draw draws[2][3];
    translucid_mesh meshes[2][3];
    translucid_material materials[2][3];
    int k, c;
    char what[96];
    for (c = 0; c < 2; c++) {
        translucid_context *owner = c == 0 ? ctx : g_standalone;
        for (k = 0; k < 2; k++) {
            make_quad(owner, (size_t)k, 0, &meshes[c][k], &materials[c][k], &draws[c][k]);
        }
        stream_in(owner, DEEP_STACK, &meshes[c][2], &materials[c][2], &draws[c][2]);
    }
    for (k = 0; k < DEEP_FRAMES + MOST_IN_FLIGHT; k++) {
        slot *s = &g_slots[k % MOST_IN_FLIGHT];
        translucid_frame_info info;
        if (s->busy) {
            int done = k - MOST_IN_FLIGHT;
            translucid_result result;
            wait_fence(s->fence);
            result = translucid_frame_complete(ctx, s->frame);
            TRUE_OR_FAIL(result == TRANSLUCID_RESULT_SUCCESS);
            snprintf(what, sizeof what, "method %d, %d frames in flight, frame %d%s",
                     (int)method, MOST_IN_FLIGHT, done, done >= DEEP_FROM ? " (deep)" : "");
            compare_any(ctx, s, what, method);
        }
        if (k >= DEEP_FRAMES) continue;
        /* Sized by the method itself: no fixed passes or pool. */
        info = frame_of(draws[1], k < DEEP_FROM ? 2 : 3, method);
        info.next = NULL;
        info.camera = orbit_camera(0.05f * (float)k);
        render_standalone(g_standalone, info, g_opaque_colour, g_layer_depth, s->expected,
                          COLOUR_BYTES);
        info.draws = draws[0];
        begin_commands(s->cmd);
        record_frame(ctx, s->cmd, s, &info);
        submit_commands(s->cmd, s->fence);
    }
    printf("method %d: %d frames growing deep, %d in flight, each checked\n", (int)method,
           DEEP_FRAMES, MOST_IN_FLIGHT);
    translucid_context_destroy(ctx);
    for (k = 0; k < 3; k++) {
        CHECK(g_standalone, translucid_mesh_destroy(g_standalone, meshes[1][k]));
        CHECK(g_standalone, translucid_material_destroy(g_standalone, materials[1][k]));
    }
}

/* 12's host allocator: each block it hands out has its start and size stored before it, and
 * the blocks live and handed out are counted (Vulkan may call from any thread). */
static long g_host_blocks_live = 0, g_host_blocks_made = 0;
static void *VKAPI_PTR counted_allocation(void *user, size_t size, size_t alignment,
                                           VkSystemAllocationScope scope) {
    size_t header = 2 * sizeof(size_t);
    unsigned char *base, *block;
    (void)user;
    (void)scope;
    if (alignment < header) alignment = header;
    base = malloc(size + alignment + header);
    if (base == NULL) return NULL;
    block = base + header + (alignment - (size_t)(base + header) % alignment) % alignment;
    ((size_t *)block)[-1] = size;
    ((unsigned char **)block)[-2] = base;
    __sync_fetch_and_add(&g_host_blocks_live, 1);
    __sync_fetch_and_add(&g_host_blocks_made, 1);
    return block;
}
static void VKAPI_PTR counted_free(void *user, void *memory) {
    (void)user;
    if (memory == NULL) return;
    free(((unsigned char **)memory)[-2]);
    __sync_fetch_and_sub(&g_host_blocks_live, 1);
}
static void *VKAPI_PTR counted_reallocation(void *user, void *original, size_t size,
                                             size_t alignment, VkSystemAllocationScope scope) {
    void *block;
    if (original == NULL) return counted_allocation(user, size, alignment, scope);
    if (size == 0) {
        counted_free(user, original);
        return NULL;
    }
    block = counted_allocation(user, size, alignment, scope);
    if (block == NULL) return NULL;
    memcpy(block, original, size < ((size_t *)original)[-1] ? size : ((size_t *)original)[-1]);
    counted_free(user, original);
    return block;
}

/* 12. A context of at most BUDGET bytes, on the engine's host allocator: a frame, a mesh of
 * BIG_QUADS quads refused (at its creation or at the frame that uploads it), and the frame
 * again; once the context is destroyed, every block it took from the allocator is back. */
#define BUDGET (16u << 20)
#define BIG_QUADS 100000
static void within_a_budget(translucid_method method) {
    translucid_host_device_create_info hd = host_device_info();
    translucid_memory_create_info memory;
    VkAllocationCallbacks callbacks;
    translucid_context_create_info create;
    translucid_context *ctx = NULL;
    scene host, standalone;
    translucid_frame_info info;
    translucid_mesh_create_info big;
    translucid_mesh big_mesh;
    translucid_result result;
    float *positions = calloc((size_t)BIG_QUADS * 12, sizeof(float));
    uint32_t *indices = calloc((size_t)BIG_QUADS * 6, sizeof(uint32_t));
    slot *s = &g_slots[0];
    uint32_t q, pass;
    const char *refused_by = "its creation";
    char what[64];
    memset(&callbacks, 0, sizeof callbacks);
    callbacks.pfnAllocation = counted_allocation;
    callbacks.pfnReallocation = counted_reallocation;
    callbacks.pfnFree = counted_free;
    g_host_blocks_made = 0;
    memset(&memory, 0, sizeof memory);
    memory.s_type = TRANSLUCID_STRUCTURE_TYPE_MEMORY_CREATE_INFO;
    memory.next = &hd;
    memory.budget_bytes = BUDGET;
    memory.allocation_callbacks = &callbacks;
    memset(&create, 0, sizeof create);
    create.s_type = TRANSLUCID_STRUCTURE_TYPE_CONTEXT_CREATE_INFO;
    create.header_version = TRANSLUCID_HEADER_VERSION;
    create.mode = TRANSLUCID_CONTEXT_MODE_HOST_DEVICE;
    create.next = &memory;
    CHECK(NULL, translucid_context_create(&create, &ctx));
    make_scene(ctx, &host);
    make_scene(g_standalone, &standalone);
    info = frame_info(&host, QUADS, orbit_camera(0.3f));
    info.method = method;

    /* Small quads, one behind the other in front of the camera. */
    TRUE_OR_FAIL(positions != NULL && indices != NULL);
    if (positions == NULL || indices == NULL) return;
    for (q = 0; q < BIG_QUADS; q++) {
        static const float corners[4][2] = {{0, 0}, {0.01f, 0}, {0.01f, 0.01f}, {0, 0.01f}};
        static const uint32_t triangles[6] = {0, 1, 2, 0, 2, 3};
        uint32_t v;
        for (v = 0; v < 4; v++) {
            positions[q * 12 + v * 3] = corners[v][0];
            positions[q * 12 + v * 3 + 1] = corners[v][1];
            positions[q * 12 + v * 3 + 2] = -1.5f;
        }
        for (v = 0; v < 6; v++) indices[q * 6 + v] = q * 4 + triangles[v];
    }
    memset(&big, 0, sizeof big);
    big.s_type = TRANSLUCID_STRUCTURE_TYPE_MESH_CREATE_INFO;
    big.primitive = TRANSLUCID_PRIMITIVE_TRIANGLES;
    big.vertex_count = BIG_QUADS * 4;
    big.positions = positions;
    big.index_count = BIG_QUADS * 6;
    big.indices = indices;

    for (pass = 0; pass < 2; pass++) {
        snprintf(what, sizeof what, "method %d within a budget, frame %u", (int)method, pass);
        render_expected(info, &standalone, s->expected);
        run_frame(ctx, s, &info);
        compare_any(ctx, s, what, method);
        TRUE_OR_FAIL(memory_of(ctx) <= BUDGET);
        if (pass == 1) break;
        /* The large mesh: refused when it is created, or by the frame that would upload it. */
        result = translucid_mesh_create(ctx, &big, &big_mesh);
        if (result == TRANSLUCID_RESULT_SUCCESS) {
            translucid_host_frame_targets t = targets_of(s->cmd, s);
            translucid_frame_info with_big = info;
            host.draws[QUADS].mesh = big_mesh;
            with_big.draw_count = QUADS + 1;
            begin_commands(s->cmd);
            record_opaque(s->cmd, s);
            result = translucid_frame_record(ctx, &with_big, &t, &s->frame);
            refused_by = "the frame that uploads it";
            CHECK(ctx, translucid_mesh_destroy(ctx, big_mesh));
        }
        if (result != TRANSLUCID_RESULT_ERROR_OUT_OF_MEMORY ||
            strstr(translucid_context_get_last_error(ctx), "budget") == NULL) {
            printf("FAIL method %d: a mesh past the budget gave %d: %s\n", (int)method,
                   (int)result, translucid_context_get_last_error(ctx));
        }
        TRUE_OR_FAIL(result == TRANSLUCID_RESULT_ERROR_OUT_OF_MEMORY &&
                     strstr(translucid_context_get_last_error(ctx), "budget") != NULL);
        TRUE_OR_FAIL(memory_of(ctx) <= BUDGET);
    }
    free(positions);
    free(indices);
    translucid_context_destroy(ctx);
    printf("method %d: frames within a %u-byte budget, a mesh past it refused by %s; %ld "
           "blocks from the engine's host allocator, %ld still out after the context\n",
           (int)method, BUDGET, refused_by, g_host_blocks_made, g_host_blocks_live);
    TRUE_OR_FAIL(g_host_blocks_made > 0 && g_host_blocks_live == 0);
    destroy_scene(g_standalone, &standalone);
}

/* One colour and one depth image that several views of a frame share, and a host buffer for
 * their opaque layers and readback (sections 13 and 15). */
typedef struct shared_images {
    VkImage colour, depth;
    VkDeviceMemory colour_memory, depth_memory, buffer_memory;
    VkBuffer buffer;
    uint8_t *mapped;
} shared_images;

static shared_images create_shared_images(VkImage colour, VkImage depth, VkDeviceSize bytes) {
    shared_images i;
    void *m;
    i.colour = colour;
    i.depth = depth;
    i.colour_memory = bind_image(colour);
    i.depth_memory = bind_image(depth);
    i.buffer = create_host_buffer(bytes, &i.buffer_memory, &m);
    i.mapped = m;
    return i;
}

/* A colour (sRGB) and a depth (D32) image of VIEWS layers, and `bytes` of host buffer. */
static shared_images create_layered_images(VkDeviceSize bytes) {
    VkImageUsageFlags transfer = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    return create_shared_images(
        create_image_layers(VK_FORMAT_R8G8B8A8_SRGB,
                            transfer | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT, W, H, VIEWS),
        create_image_layers(VK_FORMAT_D32_SFLOAT,
                            transfer | VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                                VK_IMAGE_USAGE_SAMPLED_BIT,
                            W, H, VIEWS),
        bytes);
}

static void destroy_shared_images(shared_images *i) {
    vkDestroyBuffer(g_device, i->buffer, NULL);
    vkFreeMemory(g_device, i->buffer_memory, NULL);
    vkDestroyImage(g_device, i->colour, NULL);
    vkFreeMemory(g_device, i->colour_memory, NULL);
    vkDestroyImage(g_device, i->depth, NULL);
    vkFreeMemory(g_device, i->depth_memory, NULL);
}

/* Moves every layer of both images between layouts: (colour from, colour to) and the same of
 * depth. */
static void shared_images_to(VkCommandBuffer cmd, const shared_images *i, VkImageLayout from,
                             VkImageLayout colour, VkImageLayout depth) {
    every_layer(cmd, i->colour, VK_IMAGE_ASPECT_COLOR_BIT, from, colour);
    every_layer(cmd, i->depth, VK_IMAGE_ASPECT_DEPTH_BIT, from, depth);
}

/* View `v` of the stereo frame sections 13 and 15 record, by `method`. */
static translucid_frame_info stereo_view(const scene *host, translucid_method method, uint32_t v) {
    translucid_frame_info info =
        frame_info(host, QUADS, orbit_camera(0.4f + (v ? 0.03f : -0.03f)));
    info.method = method;
    info.camera.z_near = 0.5f;
    return info;
}

/* 13. One frame of two views into the layers of one colour and one depth image. */
static void layered_stereo(translucid_method method) {
    translucid_context *ctx = host_context(VIEWS);
    scene host, standalone;
    /* The opaque colour and depth, then each layer's readback. */
    shared_images images =
        create_layered_images(COLOUR_BYTES + DEPTH_BYTES + VIEWS * COLOUR_BYTES);
    VkImage colour = images.colour, depth = images.depth;
    VkBuffer buffer = images.buffer;
    uint8_t *mapped = images.mapped;
    static uint8_t expected[VIEWS][COLOUR_BYTES];
    translucid_frame frames[VIEWS];
    VkCommandBuffer cmd = g_slots[0].cmd;
    uint32_t v;
    memcpy(mapped, g_opaque_colour, COLOUR_BYTES);
    memcpy(mapped + COLOUR_BYTES, g_engine_depth, DEPTH_BYTES);
    make_scene(ctx, &host);
    make_scene(g_standalone, &standalone);

    begin_commands(cmd);
    shared_images_to(cmd, &images, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                     VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    for (v = 0; v < VIEWS; v++) {
        VkBufferImageCopy c = region(VK_IMAGE_ASPECT_COLOR_BIT, 0, W, H);
        VkBufferImageCopy d = region(VK_IMAGE_ASPECT_DEPTH_BIT, COLOUR_BYTES, W, H);
        c.imageSubresource.baseArrayLayer = d.imageSubresource.baseArrayLayer = v;
        vkCmdCopyBufferToImage(cmd, buffer, colour, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &c);
        vkCmdCopyBufferToImage(cmd, buffer, depth, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &d);
    }
    shared_images_to(cmd, &images, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                     VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                     VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    for (v = 0; v < VIEWS; v++) {
        translucid_frame_info info = stereo_view(&host, method, v);
        translucid_host_frame_targets t = targets_of(cmd, &g_slots[0]);
        translucid_host_image_layers layers;
        render_expected(info, &standalone, expected[v]);
        memset(&layers, 0, sizeof layers);
        layers.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_IMAGE_LAYERS;
        layers.colour_layer = layers.depth_layer = v;
        layers.colour_layer_count = layers.depth_layer_count = VIEWS;
        t.next = &layers;
        t.colour.image = colour;
        t.depth.image = depth;
        CHECK(ctx, translucid_frame_record(ctx, &info, &t, &frames[v]));
    }
    for (v = 0; v < VIEWS; v++) {
        VkBufferImageCopy c =
            region(VK_IMAGE_ASPECT_COLOR_BIT, COLOUR_BYTES + DEPTH_BYTES + v * COLOUR_BYTES, W, H);
        c.imageSubresource.baseArrayLayer = v;
        vkCmdCopyImageToBuffer(cmd, colour, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer, 1, &c);
    }
    copies_to_host(cmd);
    submit_commands(cmd, g_slots[0].fence);
    wait_fence(g_slots[0].fence);
    CHECK(ctx, translucid_frame_complete(ctx, frames[VIEWS - 1]));
    for (v = 0; v < VIEWS; v++) {
        int bound = method == TRANSLUCID_METHOD_BLEND ? 8 : 2;
        int worst = worst_difference(mapped + COLOUR_BYTES + DEPTH_BYTES + v * COLOUR_BYTES,
                                     expected[v]);
        if (worst > bound) {
            printf("FAIL method %d, layer %u: %d/255 off the standalone view\n", (int)method, v,
                   worst);
        }
        TRUE_OR_FAIL(worst <= bound);
        CHECK(ctx, translucid_frame_destroy(ctx, frames[v]));
    }
    printf("method %d: stereo into the %d layers of one colour and one depth image, each as "
           "the standalone context renders its view\n",
           (int)method, VIEWS);
    translucid_context_destroy(ctx);
    destroy_shared_images(&images);
    destroy_scene(g_standalone, &standalone);
}

/* 15. Every method in a split screen: two views side by side in one colour and one D16 depth
 * image twice the frame's width, both in one command buffer; each half as the standalone
 * context renders its view alone, and the pixels between the halves' frames untouched. The
 * second view's opaque layer is the first's mirrored, so that a view that read the other's
 * place would be off. The methods that sample the engine's depth do so at the view's place,
 * the others import it from there (D16 cannot be copied). With `one_frame` 0, each view is
 * a frame into its half (translucid_host_image_region); with 1, the views are one frame
 * (translucid_host_frame_views, the frame info's camera left zero), prepared for, which
 * builds no pipeline. */
static void split_screen(translucid_method method, int one_frame) {
    translucid_context *ctx = host_context_views(one_frame ? 1 : VIEWS, one_frame ? VIEWS : 1);
    scene host, standalone;
    VkImageUsageFlags transfer = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    /* One column between the views, which neither frame may write. */
    const uint32_t width = VIEWS * W + 1;
    /* Per view, its opaque colour and depth (D16); then the whole colour image's readback. */
    const size_t layer_bytes = COLOUR_BYTES + DEPTH_BYTES, image_bytes = (size_t)width * H * 4;
    shared_images images = create_shared_images(
        create_image(VK_FORMAT_R8G8B8A8_SRGB, transfer | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT,
                     width, H),
        create_image(VK_FORMAT_D16_UNORM,
                     transfer | VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                         VK_IMAGE_USAGE_SAMPLED_BIT,
                     width, H),
        VIEWS * layer_bytes + image_bytes);
    VkImage colour = images.colour, depth = images.depth;
    VkBuffer buffer = images.buffer;
    uint8_t *mapped = images.mapped, *read = images.mapped + VIEWS * layer_bytes;
    /* Per view, the opaque layer as the standalone context takes it. */
    static uint8_t opaque[VIEWS][COLOUR_BYTES], expected[VIEWS][COLOUR_BYTES], view[COLOUR_BYTES];
    static float held[VIEWS][W * H], scratch[W * H];
    translucid_frame frames[VIEWS];
    VkCommandBuffer cmd = g_slots[0].cmd;
    VkClearColorValue marker;
    VkImageSubresourceRange whole;
    uint32_t v, x, y;
    translucid_frame_view view_list[VIEWS];
    translucid_host_frame_views views;
    uint64_t pipelines;
    int allocated;
    memset(view_list, 0, sizeof view_list);
    memset(&views, 0, sizeof views);
    views.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_FRAME_VIEWS;
    views.view_count = VIEWS;
    views.views = view_list;
    encode_depth(VK_FORMAT_D16_UNORM, 0, mapped + COLOUR_BYTES);
    for (y = 0; y < H; y++) {
        for (x = 0; x < W; x++) {
            size_t i = (size_t)y * W + x, mirrored = (size_t)y * W + (W - 1 - x);
            uint16_t k = (uint16_t)((double)g_layer_depth[mirrored] * 65535.0 + 0.5);
            memcpy(opaque[0] + i * 4, g_opaque_colour + i * 4, 4);
            memcpy(opaque[1] + i * 4, g_opaque_colour + mirrored * 4, 4);
            held[0][i] = g_layer_depth[i];
            held[1][i] = g_layer_depth[mirrored];
            memcpy(mapped + layer_bytes + COLOUR_BYTES + i * 2, &k, 2);
        }
    }
    for (v = 0; v < VIEWS; v++) memcpy(mapped + v * layer_bytes, opaque[v], COLOUR_BYTES);
    make_scene(ctx, &host);
    make_scene(g_standalone, &standalone);

    begin_commands(cmd);
    shared_images_to(cmd, &images, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                     VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    /* A marker colour everywhere, then each view's opaque layer in its half. */
    memset(&marker, 0, sizeof marker);
    marker.float32[1] = 1.0f;
    marker.float32[3] = 1.0f;
    memset(&whole, 0, sizeof whole);
    whole.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT;
    whole.levelCount = whole.layerCount = 1;
    vkCmdClearColorImage(cmd, colour, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &marker, 1, &whole);
    barrier(cmd, colour, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
            VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT,
            VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
            VK_ACCESS_TRANSFER_WRITE_BIT);
    for (v = 0; v < VIEWS; v++) {
        VkBufferImageCopy c = region(VK_IMAGE_ASPECT_COLOR_BIT, v * layer_bytes, W, H);
        VkBufferImageCopy d =
            region(VK_IMAGE_ASPECT_DEPTH_BIT, v * layer_bytes + COLOUR_BYTES, W, H);
        c.imageOffset.x = d.imageOffset.x = (int32_t)(v * (W + 1));
        vkCmdCopyBufferToImage(cmd, buffer, colour, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &c);
        vkCmdCopyBufferToImage(cmd, buffer, depth, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &d);
    }
    shared_images_to(cmd, &images, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                     VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                     VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    for (v = 0; v < VIEWS; v++) {
        translucid_frame_info info = stereo_view(&host, method, v);
        translucid_host_frame_targets t = targets_of(cmd, &g_slots[0]);
        translucid_host_image_region place;
        info.draws = standalone.draws;
        render_standalone(g_standalone, info, opaque[v], held[v], expected[v], COLOUR_BYTES);
        info.draws = host.draws;
        memset(&place, 0, sizeof place);
        place.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_IMAGE_REGION;
        place.x = v * (W + 1);
        t.next = &place;
        t.colour.image = colour;
        t.colour.width = t.depth.width = width;
        t.depth.image = depth;
        t.depth.format = VK_FORMAT_D16_UNORM;
        if (one_frame) {
            view_list[v].camera = info.camera;
            view_list[v].x = place.x;
            if (v + 1 < VIEWS) continue;
            t.next = &views;
            TRUE_OR_FAIL(prepare_for(ctx, &info, &t) > 0);
            /* The camera is the views'. */
            memset(&info.camera, 0, sizeof info.camera);
            CHECK(ctx, translucid_frame_record(ctx, &info, &t, &frames[0]));
            break;
        }
        /* The views share the image: the first leaves it as the second takes it. */
        if (v + 1 < VIEWS) t.colour.final_layout = t.colour.layout;
        CHECK(ctx, translucid_frame_record(ctx, &info, &t, &frames[v]));
    }
    {
        VkBufferImageCopy c = region(VK_IMAGE_ASPECT_COLOR_BIT, VIEWS * layer_bytes, width, H);
        vkCmdCopyImageToBuffer(cmd, colour, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer, 1, &c);
    }
    copies_to_host(cmd);
    submit_commands(cmd, g_slots[0].fence);
    wait_fence(g_slots[0].fence);
    CHECK(ctx, translucid_frame_complete(ctx, frames[one_frame ? 0 : VIEWS - 1]));
    if (one_frame) {
        built_by_frame(ctx, frames[0], &pipelines, &allocated);
        if (pipelines != 0) {
            printf("FAIL method %d: a prepared frame of %d views built %llu pipelines\n",
                   (int)method, VIEWS, (unsigned long long)pipelines);
        }
        TRUE_OR_FAIL(pipelines == 0);
    }
    for (v = 0; v < VIEWS; v++) {
        int bound = method == TRANSLUCID_METHOD_BLEND ? 8 : 2;
        int worst;
        for (y = 0; y < H; y++) {
            memcpy(view + (size_t)y * W * 4, read + ((size_t)y * width + v * (W + 1)) * 4,
                   (size_t)W * 4);
        }
        worst = worst_difference(view, expected[v]);
        if (worst > bound) {
            printf("FAIL method %d, split-screen view %u%s: %d/255 off the standalone view\n",
                   (int)method, v, one_frame ? " of one frame" : "", worst);
        }
        TRUE_OR_FAIL(worst <= bound);
        if (!one_frame || v == 0) CHECK(ctx, translucid_frame_destroy(ctx, frames[v]));
    }
    /* The column between the frames keeps the marker (sRGB green). */
    for (y = 0; y < H; y++) {
        const uint8_t *p = read + ((size_t)y * width + W) * 4;
        x = p[0] == 0 && p[1] == 255 && p[2] == 0;
        if (!x) printf("FAIL method %d: row %u between the views was written\n", (int)method, y);
        TRUE_OR_FAIL(x);
    }
    printf("method %d: a split screen of %d views%s in one colour and one D16 depth image, "
           "each as the standalone context renders it\n",
           (int)method, VIEWS, one_frame ? " in one frame" : "");
    translucid_context_destroy(ctx);
    destroy_shared_images(&images);
    destroy_scene(g_standalone, &standalone);
    /* The opaque layer as the other sections read it (D32). */
    encode_depth(VK_FORMAT_D32_SFLOAT, 0, (uint8_t *)scratch);
}

/* 16. Every method in stereo with 3 frames in flight, as an XR runtime hands out swapchain
 * images: per frame in flight, one colour and one depth image of two layers, and each frame
 * one translucid frame of two views (translucid_host_frame_views), one per layer, the eyes
 * turning with the frame. The context is made for 3 frames of 2 views; the loop is prepared
 * for, and no frame builds a pipeline. Each layer of each frame is as the standalone context
 * renders its view alone, under synchronization validation. */
#define STEREO_FRAMES 6
static void stereo_frames_in_flight(translucid_method method) {
    translucid_context *ctx = host_context_views(MOST_IN_FLIGHT, VIEWS);
    scene host, standalone;
    const size_t readback = COLOUR_BYTES + DEPTH_BYTES;
    shared_images images[MOST_IN_FLIGHT];
    static uint8_t expected[MOST_IN_FLIGHT][VIEWS][COLOUR_BYTES];
    translucid_frame frames[MOST_IN_FLIGHT];
    int busy[MOST_IN_FLIGHT] = {0};
    int k, i, allocated;
    uint32_t v;
    uint64_t pipelines;
    for (i = 0; i < MOST_IN_FLIGHT; i++) {
        images[i] = create_layered_images(readback + VIEWS * COLOUR_BYTES);
        memcpy(images[i].mapped, g_opaque_colour, COLOUR_BYTES);
        memcpy(images[i].mapped + COLOUR_BYTES, g_engine_depth, DEPTH_BYTES);
    }
    make_scene(ctx, &host);
    make_scene(g_standalone, &standalone);
    for (k = 0; k < STEREO_FRAMES + MOST_IN_FLIGHT; k++) {
        int at = k % MOST_IN_FLIGHT;
        shared_images *im = &images[at];
        VkCommandBuffer cmd = g_slots[at].cmd;
        translucid_frame_view view_list[VIEWS];
        translucid_host_frame_views views;
        translucid_frame_info info;
        translucid_host_frame_targets t;
        if (busy[at]) {
            int done = k - MOST_IN_FLIGHT;
            wait_fence(g_slots[at].fence);
            CHECK(ctx, translucid_frame_complete(ctx, frames[at]));
            built_by_frame(ctx, frames[at], &pipelines, &allocated);
            if (pipelines != 0) {
                printf("FAIL method %d, stereo frame %d: %llu pipelines built\n", (int)method,
                       done, (unsigned long long)pipelines);
            }
            TRUE_OR_FAIL(pipelines == 0);
            views_add_up(ctx, frames[at], VIEWS, "a stereo frame's view statistics");
            for (v = 0; v < VIEWS; v++) {
                int bound = method == TRANSLUCID_METHOD_BLEND ? 8 : 2;
                int worst = worst_difference(im->mapped + readback + v * COLOUR_BYTES,
                                             expected[at][v]);
                if (worst > bound) {
                    printf("FAIL method %d, stereo frame %d, view %u: %d/255 off the "
                           "standalone view\n",
                           (int)method, done, v, worst);
                }
                TRUE_OR_FAIL(worst <= bound);
            }
            CHECK(ctx, translucid_frame_destroy(ctx, frames[at]));
            busy[at] = 0;
        }
        if (k >= STEREO_FRAMES) continue;
        move_scene(ctx, &host, &standalone, k);
        memset(view_list, 0, sizeof view_list);
        for (v = 0; v < VIEWS; v++) {
            /* Eyes 6 cm apart, turning with the frame. */
            translucid_frame_info eye = frame_info(
                &host, QUADS, orbit_camera(0.1f * (float)k + (v ? 0.03f : -0.03f)));
            eye.method = method;
            eye.camera.z_near = 0.5f;
            render_expected(eye, &standalone, expected[at][v]);
            view_list[v].camera = eye.camera;
            view_list[v].colour_layer = view_list[v].depth_layer = v;
        }
        memset(&views, 0, sizeof views);
        views.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_FRAME_VIEWS;
        views.colour_layer_count = views.depth_layer_count = VIEWS;
        views.view_count = VIEWS;
        views.views = view_list;
        info = frame_info(&host, QUADS, view_list[0].camera);
        info.method = method;
        info.frame_index = (uint64_t)k + 1;
        t = targets_of(cmd, &g_slots[0]);
        t.colour.image = im->colour;
        t.depth.image = im->depth;
        t.next = &views;
        if (k == 0) prepare_for(ctx, &info, &t);
        begin_commands(cmd);
        shared_images_to(cmd, im, VK_IMAGE_LAYOUT_UNDEFINED,
                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        for (v = 0; v < VIEWS; v++) {
            VkBufferImageCopy c = region(VK_IMAGE_ASPECT_COLOR_BIT, 0, W, H);
            VkBufferImageCopy d = region(VK_IMAGE_ASPECT_DEPTH_BIT, COLOUR_BYTES, W, H);
            c.imageSubresource.baseArrayLayer = d.imageSubresource.baseArrayLayer = v;
            vkCmdCopyBufferToImage(cmd, im->buffer, im->colour,
                                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &c);
            vkCmdCopyBufferToImage(cmd, im->buffer, im->depth,
                                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &d);
        }
        shared_images_to(cmd, im, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                         VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                         VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
        /* The frame info's camera is not read: the views give theirs. */
        memset(&info.camera, 0, sizeof info.camera);
        CHECK(ctx, translucid_frame_record(ctx, &info, &t, &frames[at]));
        for (v = 0; v < VIEWS; v++) {
            VkBufferImageCopy c =
                region(VK_IMAGE_ASPECT_COLOR_BIT, readback + v * COLOUR_BYTES, W, H);
            c.imageSubresource.baseArrayLayer = v;
            vkCmdCopyImageToBuffer(cmd, im->colour, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                   im->buffer, 1, &c);
        }
        copies_to_host(cmd);
        submit_commands(cmd, g_slots[at].fence);
        busy[at] = 1;
    }
    printf("method %d: stereo, %d frames of %d views with %d in flight, each view as the "
           "standalone context renders it, no pipeline built\n",
           (int)method, STEREO_FRAMES, VIEWS, MOST_IN_FLIGHT);
    translucid_context_destroy(ctx);
    for (i = 0; i < MOST_IN_FLIGHT; i++) destroy_shared_images(&images[i]);
    destroy_scene(g_standalone, &standalone);
}

int main(void) {
    static const float forward_bands[3] = {0.3f, 0.75f, 1.0f};
    translucid_host_requirements req;
    translucid_context_create_info info;
    VkCommandPoolCreateInfo pool;
    uint32_t n;

    memset(&req, 0, sizeof req);
    req.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_REQUIREMENTS;
    CHECK(NULL, translucid_host_get_requirements(&req));
    {
        /* Every method's features, which section 7 draws with. */
        uint32_t methods[8];
        size_t count = 0, m, f;
        CHECK(NULL, translucid_method_get_available(methods, 8, &count));
        for (m = 0; m < count; m++) {
            translucid_host_requirements per_method = req;
            VkBool32 *all = (VkBool32 *)&req.features;
            const VkBool32 *own = (const VkBool32 *)&per_method.features;
            CHECK(NULL, translucid_host_get_method_requirements(methods[m], &per_method));
            for (f = 0; f < sizeof req.features / sizeof(VkBool32); f++) all[f] |= own[f];
        }
    }
    create_engine(&req);
    memset(&pool, 0, sizeof pool);
    pool.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = g_family;
    VK_CHECK(vkCreateCommandPool(g_device, &pool, NULL, &g_pool));
    for (n = 0; n < SLOTS; n++) create_slot(&g_slots[n]);

    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_CONTEXT_CREATE_INFO;
    info.header_version = TRANSLUCID_HEADER_VERSION;
    CHECK(NULL, translucid_context_create(&info, &g_standalone));

    make_opaque_layer(forward_bands, 0);
    updates_move_the_mesh();
    frame_loop(2);
    frame_loop(3);
    two_views();
    stereo_in_flight();
    engine_projection();
    destroy_in_flight();
    /* One method that samples the engine's depth where it is, one that imports it. */
    depth_formats(TRANSLUCID_METHOD_EXACT);
    depth_formats(TRANSLUCID_METHOD_LINKED_LIST);
    make_opaque_layer(forward_bands, 0);
    misuse();
    {
        static const translucid_method methods[] = {
            TRANSLUCID_METHOD_EXACT,       TRANSLUCID_METHOD_WAVELET,
            TRANSLUCID_METHOD_LINKED_LIST, TRANSLUCID_METHOD_DEPTH_PEELING,
            TRANSLUCID_METHOD_WBOIT,       TRANSLUCID_METHOD_BLEND};
        for (n = 0; n < sizeof methods / sizeof methods[0]; n++) {
            abandon_keeps_what_is_built(methods[n]);
        }
        for (n = 0; n < sizeof methods / sizeof methods[0]; n++) {
            declared_loop(methods[n], TRANSLUCID_CONTENT_ALL);
            declared_loop(methods[n], 0);
        }
        preparing_another_method_keeps_the_first();
        for (n = 0; n < sizeof methods / sizeof methods[0]; n++) {
            trim_after_a_resolution_drop(methods[n]);
        }
        for (n = 0; n < sizeof methods / sizeof methods[0]; n++) {
            grows_deep_in_flight(methods[n]);
        }
        for (n = 0; n < sizeof methods / sizeof methods[0]; n++) within_a_budget(methods[n]);
        for (n = 0; n < sizeof methods / sizeof methods[0]; n++) layered_stereo(methods[n]);
        for (n = 0; n < sizeof methods / sizeof methods[0]; n++) {
            background_prepare(methods[n]);
        }
        for (n = 0; n < sizeof methods / sizeof methods[0]; n++) {
            split_screen(methods[n], 0);
            split_screen(methods[n], 1);
        }
        for (n = 0; n < sizeof methods / sizeof methods[0]; n++) {
            stereo_frames_in_flight(methods[n]);
        }
    }

    translucid_context_destroy(g_standalone);
    for (n = 0; n < SLOTS; n++) destroy_slot(&g_slots[n]);
    vkDestroyCommandPool(g_device, g_pool, NULL);
    destroy_engine();
    printf("frames: %d checks passed, %d failed, %d validation messages\n", g_passed, g_failed,
           g_validation_messages);
    return g_failed == 0 && g_validation_messages == 0 ? 0 : 1;
}
