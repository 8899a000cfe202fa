/*
 * translucid in an engine's frame loop (host-device mode): the engine owns the Vulkan
 * instance, device, images and command buffers, keeps 3 frames in flight, draws each in
 * stereo (a left and a right view into the two layers of one colour and one depth image, as an
 * XR swapchain hands them: one translucid frame of two views, translucid_host_frame_views),
 * and each frame moves its camera, sways a cloud of particles
 * (translucid_mesh_update) and turns three glass panes; at load time it prepares what the
 * loop needs (translucid_context_prepare, with the formats of its images), so that no frame
 * builds a pipeline; an eighth through, the shaders of the next level's lit pane build in the
 * background (translucid_context_prepare_in_background) while the loop goes on, and from
 * halfway, once they are ready, that pane is streamed in (a mesh and a material created, and
 * drawn from then on); in the last quarter a dynamic resolution renders the frames at 70
 * to 90 % of the images' size (translucid draws their top-left corner). translucid records
 * the transparent pass into the engine's command buffer; the engine submits, and completes
 * each frame when it comes back to its slot.
 *
 *   frame_loop [OUTPUT_DIR] [FRAMES] [DRAWS]      (default: out 120 0)
 *
 * DRAWS adds that many small moving panes, one draw each (a draw-call-heavy frame).
 *
 * Before each frame, the engine draws the same transparent draws its own way, unsorted blending
 * straight into its images (translucid_frame_record_native_blend, the yardstick, with the same
 * views), then clears them again: each frame's GPU time over the yardstick's is what translucid costs next to the
 * engine's own blend.
 *
 * For exact and blend it prints each frame's CPU time in translucid_frame_record, its GPU
 * time and its ratio to the yardstick's (both views), what it built, the loop's wall time per
 * frame, and writes the last frame's left view (layer 0) as OUTPUT_DIR/frame_loop-<method>.png
 * (read back by the engine).
 *
 * The engine (its instance, device, images, buffers and submissions) is engine.c, which the
 * C API's host-device tests run on too. With TRANSLUCID_VALIDATION=1 its instance runs the
 * Khronos validation layer (TRANSLUCID_SYNC_VALIDATION=1: synchronization validation too),
 * and the program fails if the layer reports an error.
 */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "engine.h"

#define WIDTH 480
#define HEIGHT 270
#define IN_FLIGHT 3
/* Stereo: each frame draws a left and a right view, into the layers of its images. */
#define VIEWS 2
#define PARTICLES 96
#define PIXEL_BYTES (WIDTH * HEIGHT * 4)

static translucid_context *g_context = NULL;

static void check(translucid_result result, const char *call) {
    if (result < 0) {
        fprintf(stderr, "%s failed: %s (%d)\n  %s\n", call, translucid_result_string(result),
                (int)result, translucid_context_get_last_error(g_context));
        exit(1);
    }
}
#define CHECK(call) check((call), #call)

static double now_ms(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec / 1e6;
}

/* ---- the engine: device (engine.c), images, command buffers ---- */

static VkCommandPool g_pool;

/* One frame in flight: its command buffer, fence, images (a layer per view), the left view's
 * readback, and translucid's frames. */
typedef struct frame_slot {
    VkCommandBuffer cmd;
    VkFence fence;
    VkImage colour, depth;
    VkDeviceMemory colour_memory, depth_memory, readback_memory;
    VkBuffer readback;
    void *pixels;
    translucid_frame frame;
    /* The yardstick's frame, recorded before `frame` into the same command buffer. */
    translucid_frame native;
    int in_flight;
    double record_ms;
} frame_slot;

static frame_slot g_slots[IN_FLIGHT];

/* The engine's instance and device, made with what translucid asks for. */
static void create_engine(void) {
    translucid_host_requirements req;
    translucid_host_subgroup_requirements subgroups;
    memset(&subgroups, 0, sizeof subgroups);
    subgroups.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_SUBGROUP_REQUIREMENTS;
    memset(&req, 0, sizeof req);
    req.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_REQUIREMENTS;
    req.next = &subgroups;
    CHECK(translucid_host_get_requirements(&req));
    create_instance(req.api_version);
    create_device(&req);
}

static void create_slots(void) {
    VkCommandPoolCreateInfo pool;
    VkCommandBufferAllocateInfo alloc;
    VkFenceCreateInfo fence;
    VkImageUsageFlags transfer = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    int i;

    memset(&pool, 0, sizeof pool);
    pool.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = g_family;
    VK_CHECK(vkCreateCommandPool(g_device, &pool, NULL, &g_pool));
    for (i = 0; i < IN_FLIGHT; i++) {
        frame_slot *s = &g_slots[i];
        memset(&alloc, 0, sizeof alloc);
        alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
        alloc.commandPool = g_pool;
        alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        alloc.commandBufferCount = 1;
        VK_CHECK(vkAllocateCommandBuffers(g_device, &alloc, &s->cmd));
        memset(&fence, 0, sizeof fence);
        fence.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
        VK_CHECK(vkCreateFence(g_device, &fence, NULL, &s->fence));
        s->colour = create_image_layers(VK_FORMAT_R8G8B8A8_SRGB,
                                        transfer | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT, WIDTH,
                                        HEIGHT, VIEWS);
        s->colour_memory = bind_image(s->colour);
        /* Sampled: exact reads it where it is, as it blends onto the colour. */
        s->depth = create_image_layers(VK_FORMAT_D32_SFLOAT,
                                       transfer | VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                                           VK_IMAGE_USAGE_SAMPLED_BIT,
                                       WIDTH, HEIGHT, VIEWS);
        s->depth_memory = bind_image(s->depth);
        s->readback = create_host_buffer(PIXEL_BYTES, &s->readback_memory, &s->pixels);
        s->in_flight = 0;
    }
}

static void destroy_slots(void) {
    int i;
    for (i = 0; i < IN_FLIGHT; i++) {
        frame_slot *s = &g_slots[i];
        vkDestroyBuffer(g_device, s->readback, NULL);
        vkFreeMemory(g_device, s->readback_memory, NULL);
        vkDestroyImage(g_device, s->colour, NULL);
        vkFreeMemory(g_device, s->colour_memory, NULL);
        vkDestroyImage(g_device, s->depth, NULL);
        vkFreeMemory(g_device, s->depth_memory, NULL);
        vkDestroyFence(g_device, s->fence, NULL);
    }
    vkDestroyCommandPool(g_device, g_pool, NULL);
}

/* The engine's opaque pass over both views, here a clear: a dark sky, nothing in the way. */
static void record_opaque(VkCommandBuffer cmd, const frame_slot *s) {
    VkClearColorValue sky;
    VkClearDepthStencilValue far;
    VkImageSubresourceRange colour, depth;
    memset(&sky, 0, sizeof sky);
    sky.float32[0] = 0.02f;
    sky.float32[1] = 0.03f;
    sky.float32[2] = 0.06f;
    sky.float32[3] = 1.0f;
    far.depth = 1.0f;
    far.stencil = 0;
    memset(&colour, 0, sizeof colour);
    colour.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT;
    colour.levelCount = 1;
    colour.layerCount = VIEWS;
    depth = colour;
    depth.aspectMask = VK_IMAGE_ASPECT_DEPTH_BIT;
    every_layer(cmd, s->colour, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    every_layer(cmd, s->depth, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    vkCmdClearColorImage(cmd, s->colour, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &sky, 1, &colour);
    vkCmdClearDepthStencilImage(cmd, s->depth, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &far, 1,
                                &depth);
}

/* ---- a PNG of the read-back frame (stored deflate blocks: no compression library) ---- */

static uint32_t crc32_of(const uint8_t *data, size_t n, uint32_t crc) {
    size_t i;
    int k;
    crc = ~crc;
    for (i = 0; i < n; i++) {
        crc ^= data[i];
        for (k = 0; k < 8; k++) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

static void put_u32(uint8_t *p, uint32_t v) {
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
}

static void write_chunk(FILE *f, const char *type, const uint8_t *data, uint32_t n) {
    uint8_t word[4];
    uint32_t crc = crc32_of((const uint8_t *)type, 4, 0);
    crc = crc32_of(data, n, crc);
    put_u32(word, n);
    fwrite(word, 1, 4, f);
    fwrite(type, 1, 4, f);
    if (n > 0) fwrite(data, 1, n, f);
    put_u32(word, crc);
    fwrite(word, 1, 4, f);
}

static void write_png(const char *path, const uint8_t *rgba) {
    static const uint8_t signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    const size_t row = 1 + WIDTH * 4, raw = row * HEIGHT;
    const size_t blocks = (raw + 65534) / 65535;
    uint8_t header[13];
    uint8_t *zlib = malloc(2 + raw + 5 * blocks + 4), *out;
    uint8_t *scanlines = malloc(raw);
    uint32_t a = 1, b = 0;
    size_t y, i, done;
    FILE *f = fopen(path, "wb");
    if (zlib == NULL || scanlines == NULL || f == NULL) {
        fprintf(stderr, "cannot write %s\n", path);
        exit(1);
    }
    for (y = 0; y < HEIGHT; y++) {
        scanlines[y * row] = 0; /* filter: none */
        memcpy(scanlines + y * row + 1, rgba + y * WIDTH * 4, WIDTH * 4);
    }
    out = zlib;
    *out++ = 0x78;
    *out++ = 0x01;
    for (done = 0; done < raw;) {
        size_t n = raw - done < 65535 ? raw - done : 65535;
        *out++ = done + n == raw ? 1 : 0;
        *out++ = (uint8_t)n;
        *out++ = (uint8_t)(n >> 8);
        *out++ = (uint8_t)~n;
        *out++ = (uint8_t)(~n >> 8);
        memcpy(out, scanlines + done, n);
        out += n;
        done += n;
    }
    for (i = 0; i < raw; i++) {
        a = (a + scanlines[i]) % 65521;
        b = (b + a) % 65521;
    }
    put_u32(out, (b << 16) | a);
    out += 4;
    put_u32(header, WIDTH);
    put_u32(header + 4, HEIGHT);
    header[8] = 8;  /* bits per channel */
    header[9] = 6;  /* RGBA */
    header[10] = 0; /* deflate */
    header[11] = 0; /* adaptive filters */
    header[12] = 0; /* not interlaced */
    fwrite(signature, 1, 8, f);
    write_chunk(f, "IHDR", header, 13);
    write_chunk(f, "IDAT", zlib, (uint32_t)(out - zlib));
    write_chunk(f, "IEND", NULL, 0);
    fclose(f);
    free(zlib);
    free(scanlines);
}

/* ---- the scene: assets created once, moved every frame ---- */

typedef struct scene {
    translucid_mesh pane, particles, streamed;
    translucid_material glass[3], smoke, amber;
    float particle_positions[PARTICLES * 4 * 3];
    translucid_draw *draws;
    /* The draws: three panes, the particles, the small panes, then the streamed pane. */
    uint32_t draw_count, small_panes;
} scene;

static float hash01(uint32_t i) {
    i = (i ^ 61u) ^ (i >> 16);
    i *= 9u;
    i ^= i >> 4;
    i *= 0x27d4eb2du;
    i ^= i >> 15;
    return (float)(i & 0xFFFFu) / 65535.0f;
}

/* Frame `k`'s particles: small quads facing +Z, rising and swaying. */
static void place_particles(scene *s, int k) {
    int p, c;
    for (p = 0; p < PARTICLES; p++) {
        float x = -1.2f + 2.4f * hash01((uint32_t)p * 3u);
        float z = -0.8f + 1.6f * hash01((uint32_t)p * 3u + 1u);
        float rise = fmodf(hash01((uint32_t)p * 3u + 2u) * 2.4f + 0.02f * (float)k, 2.4f);
        float y = -1.2f + rise, sway = 0.1f * sinf(0.1f * (float)k + (float)p);
        float size = 0.12f;
        for (c = 0; c < 4; c++) {
            float *v = &s->particle_positions[(p * 4 + c) * 3];
            v[0] = x + sway + (c == 1 || c == 2 ? size : -size);
            v[1] = y + (c >= 2 ? size : -size);
            v[2] = z;
        }
    }
}

static translucid_material make_material(float r, float g, float b, float a, uint32_t flags) {
    translucid_material_create_info info;
    translucid_material material;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_MATERIAL_CREATE_INFO;
    info.base_colour[0] = r;
    info.base_colour[1] = g;
    info.base_colour[2] = b;
    info.base_colour[3] = a;
    info.flags = flags;
    CHECK(translucid_material_create(g_context, &info, &material));
    return material;
}

/* A mesh of `vertex_count` vertices, one quad for each four of them in order. */
static translucid_mesh make_quads(const float *positions, uint32_t vertex_count,
                                  const char *name) {
    static uint32_t corners[PARTICLES * 4];
    translucid_mesh_create_info mesh;
    translucid_mesh made;
    uint32_t i;
    for (i = 0; i < vertex_count; i++) corners[i] = i;
    memset(&mesh, 0, sizeof mesh);
    mesh.s_type = TRANSLUCID_STRUCTURE_TYPE_MESH_CREATE_INFO;
    mesh.primitive = TRANSLUCID_PRIMITIVE_QUADS;
    mesh.vertex_count = vertex_count;
    mesh.positions = positions;
    mesh.index_count = vertex_count;
    mesh.indices = corners;
    mesh.name = name;
    CHECK(translucid_mesh_create(g_context, &mesh, &made));
    return made;
}

static void make_scene(scene *s, uint32_t extra_draws) {
    static const float pane[] = {-0.7f, -0.7f, 0, 0.7f, -0.7f, 0, 0.7f, 0.7f, 0, -0.7f, 0.7f, 0};
    int i;

    s->pane = make_quads(pane, 4, "pane");
    s->streamed.id = 0;
    place_particles(s, 0);
    s->particles = make_quads(s->particle_positions, PARTICLES * 4, "particles");
    s->glass[0] = make_material(1.0f, 0.15f, 0.1f, 0.5f, 0);
    s->glass[1] = make_material(0.1f, 1.0f, 0.2f, 0.5f, 0);
    s->glass[2] = make_material(0.1f, 0.3f, 1.0f, 0.5f, 0);
    s->smoke = make_material(0.9f, 0.8f, 0.7f, 0.15f, 0);
    s->draw_count = 4 + extra_draws;
    s->small_panes = extra_draws;
    s->draws = calloc(s->draw_count + 1, sizeof *s->draws);
    if (s->draws == NULL) exit(1);
    for (i = 0; i < 3; i++) {
        s->draws[i].mesh = s->pane;
        s->draws[i].material = s->glass[i];
    }
    s->draws[3].mesh = s->particles;
    s->draws[3].material = s->smoke;
    s->draws[3].transform[0] = s->draws[3].transform[5] = s->draws[3].transform[10] =
        s->draws[3].transform[15] = 1.0f;
}

/* Frame `k`: the panes turn about y, each about its own spot; the small ones drift. */
static void move_panes(scene *s, int k) {
    uint32_t i;
    for (i = 0; i < 3; i++) {
        float a = 0.03f * (float)k + 2.1f * (float)i, c = cosf(a), sn = sinf(a);
        float *m = s->draws[i].transform;
        memset(m, 0, 16 * sizeof(float));
        m[0] = c;
        m[2] = -sn;
        m[5] = 1.0f;
        m[8] = sn;
        m[10] = c;
        m[12] = -0.6f + 0.6f * (float)i;
        m[13] = -0.2f + 0.2f * (float)i;
        m[14] = -0.3f + 0.3f * (float)i;
        m[15] = 1.0f;
    }
    for (i = 4; i < 4 + s->small_panes; i++) {
        float *m = s->draws[i].transform;
        memset(m, 0, 16 * sizeof(float));
        m[0] = m[5] = m[10] = 0.05f;
        m[12] = -2.0f + 4.0f * hash01(i * 5u) + 0.01f * (float)k;
        m[13] = -1.2f + 2.4f * hash01(i * 5u + 1u);
        m[14] = -1.5f + 3.0f * hash01(i * 5u + 2u);
        m[15] = 1.0f;
    }
}

/* An asset streamed in mid-loop, as an engine loads a level's parts: a smaller amber pane
 * (its own mesh and lit material, created now), drawn from the next frame on. */
static void stream_in_pane(scene *s) {
    static const float pane[] = {-0.3f, -0.5f, 0, 0.3f, -0.5f, 0, 0.3f, 0.5f, 0, -0.3f, 0.5f, 0};
    translucid_draw *d = &s->draws[s->draw_count];
    s->streamed = make_quads(pane, 4, "streamed pane");
    s->amber = make_material(1.0f, 0.6f, 0.1f, 0.45f, TRANSLUCID_MATERIAL_LIT);
    d->mesh = s->streamed;
    d->material = s->amber;
    d->transform[0] = d->transform[5] = d->transform[10] = d->transform[15] = 1.0f;
    d->transform[12] = 0.9f;
    d->transform[14] = 0.6f;
    s->draw_count++;
}

/* A camera circling the scene at 4 units, 0.8 radians of vertical field of view. */
static translucid_camera orbit_camera(int k) {
    translucid_camera camera;
    float a = 0.02f * (float)k, c = cosf(a), sn = sinf(a), d = 4.0f;
    memset(&camera, 0, sizeof camera);
    /* Rows of the view's rotation: right (c, 0, -s), up (0, 1, 0), back (s, 0, c). */
    camera.view[0] = c;
    camera.view[8] = -sn;
    camera.view[5] = 1.0f;
    camera.view[2] = sn;
    camera.view[10] = c;
    camera.view[14] = -d;
    camera.view[15] = 1.0f;
    camera.fov_y = 0.8f;
    camera.z_near = 0.1f;
    camera.z_far = 50.0f;
    return camera;
}

static int compare_doubles(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n) {
    qsort(v, (size_t)n, sizeof *v, compare_doubles);
    return v[n / 2];
}

/* Ends the frame in flight in `s`: waits for its fence, completes its frame (and so the
 * yardstick recorded before it), prints its times (both views together: a frame's statistics
 * add up its views', and each eye's share is chained to them); its GPU time and its ratio to
 * the yardstick's. */
static void finish(frame_slot *s, int k, double *gpu_ms, double *ratio) {
    translucid_frame_statistics stats, native;
    translucid_frame_view_statistics eyes;
    translucid_result done;
    double translucid_ms, method_ms, native_ms;
    uint64_t dispatches, pipelines, bytes;
    wait_fence(s->fence);
    done = translucid_frame_complete(g_context, s->frame);
    CHECK(done);
    memset(&stats, 0, sizeof stats);
    memset(&eyes, 0, sizeof eyes);
    stats.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS;
    stats.next = &eyes;
    eyes.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_VIEW_STATISTICS;
    CHECK(translucid_frame_get_statistics(g_context, s->frame, &stats));
    memset(&native, 0, sizeof native);
    native.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS;
    CHECK(translucid_frame_get_statistics(g_context, s->native, &native));
    translucid_ms = stats.gpu_milliseconds;
    method_ms = stats.method_milliseconds;
    native_ms = native.gpu_milliseconds;
    dispatches = stats.dispatches;
    pipelines = stats.pipelines_created;
    bytes = stats.bytes_allocated;
    CHECK(translucid_frame_destroy(g_context, s->native));
    CHECK(translucid_frame_destroy(g_context, s->frame));
    *gpu_ms = translucid_ms;
    *ratio = translucid_ms / native_ms;
    printf("  frame %3d: record %.3f ms (CPU), GPU %.3f ms (eyes %.3f + %.3f; method %.3f, %llu "
           "dispatches), x%.2f the engine's blend (%.3f ms)%s",
           k, s->record_ms, translucid_ms, eyes.views[0].gpu_milliseconds,
           eyes.view_count > 1 ? eyes.views[1].gpu_milliseconds : 0.0, method_ms,
           (unsigned long long)dispatches, *ratio, native_ms,
           done == TRANSLUCID_RESULT_FRAME_DEGRADED ? ", past a limit: see the README" : "");
    /* What its recording and completion built: no pipeline (the loop was prepared); buffers
     * and uploads (the first frames', the streamed pane's). */
    if (pipelines != 0) printf(", built %llu pipelines", (unsigned long long)pipelines);
    if (bytes != 0) printf(", allocated %.1f KB of GPU memory", bytes / 1024.0);
    printf("\n");
    s->in_flight = 0;
}

/* The share of the images' size frame `k` of `frames` renders at: all of it, but for a
 * dynamic resolution in the last quarter (the last frame, which is written out, whole). */
static float render_scale(int k, int frames) {
    static const float steps[4] = {0.9f, 0.8f, 0.7f, 0.8f};
    if (k < frames * 3 / 4 || k == frames - 1) return 1.0f;
    return steps[k % 4];
}

/* `frames` frames of the loop with `method`; the last one written to `png`. */
static void run(uint32_t method, int frames, uint32_t extra_draws, const char *png) {
    scene sc;
    double *record = malloc(sizeof(double) * (size_t)frames);
    double *gpu = malloc(sizeof(double) * (size_t)frames);
    double *wall = malloc(sizeof(double) * (size_t)frames);
    double *ratio = malloc(sizeof(double) * (size_t)frames);
    double last = now_ms();
    translucid_host_image_formats formats;
    translucid_prepare_info prepare;
    translucid_frame_info like;
    /* The streamed pane's level: its preparation's first frame, and whether it is ready. */
    int level_from = frames / 8, level_ready = 0;
    int k;
    uint32_t v;
    if (record == NULL || gpu == NULL || wall == NULL || ratio == NULL) exit(1);
    make_scene(&sc, extra_draws);
    for (k = 4; k < (int)sc.draw_count; k++) {
        sc.draws[k].mesh = sc.pane;
        sc.draws[k].material = sc.glass[k % 3];
    }
    printf("%s, %d stereo frames at %dx%d a view, %u draws, %d in flight:\n",
           translucid_method_name(method), frames, WIDTH, HEIGHT, sc.draw_count, IN_FLIGHT);
    {
        /* At load time, what the loop needs is built: no frame compiles a shader, the
         * first's included. The panes and particles are unlit and untextured, one colour
         * each: nothing to declare (an engine declares what its levels may hold). The images'
         * formats and layouts are those of the frame targets below. */
        uint64_t built = 0;
        memset(&formats, 0, sizeof formats);
        formats.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_IMAGE_FORMATS;
        formats.colour_format = VK_FORMAT_R8G8B8A8_SRGB;
        formats.colour_layout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
        formats.colour_final_layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        formats.depth_format = VK_FORMAT_D32_SFLOAT;
        formats.depth_layout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
        formats.depth_final_layout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
        memset(&like, 0, sizeof like);
        like.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
        like.method = method;
        like.width = WIDTH;
        like.height = HEIGHT;
        like.camera = orbit_camera(0);
        memset(&prepare, 0, sizeof prepare);
        prepare.s_type = TRANSLUCID_STRUCTURE_TYPE_PREPARE_INFO;
        prepare.next = &formats;
        prepare.frame = &like;
        prepare.content = 0;
        CHECK(translucid_context_prepare(g_context, &prepare, &built));
        printf("  prepared: %llu pipelines built\n", (unsigned long long)built);
    }
    for (k = 0; k < frames + IN_FLIGHT; k++) {
        frame_slot *s = &g_slots[k % IN_FLIGHT];
        translucid_frame_info info;
        translucid_frame_view eyes[VIEWS];
        translucid_host_frame_views views;
        translucid_host_frame_targets targets;
        double started;
        /* Back at this slot: its frame (two frames ago) has to finish first. */
        if (s->in_flight) finish(s, k - IN_FLIGHT, &gpu[k - IN_FLIGHT], &ratio[k - IN_FLIGHT]);
        if (k >= frames) continue;

        /* The next level's pane is lit: its shaders are built in the background while the
         * loop goes on, and it streams in once they are ready. */
        if (k == level_from) {
            prepare.content = TRANSLUCID_CONTENT_LIT;
            CHECK(translucid_context_prepare_in_background(g_context, &prepare));
            printf("  frame %3d: the next level's shaders building in the background "
                   "(translucid_context_prepare_in_background)\n",
                   k);
        }
        if (k > level_from && !level_ready) {
            uint64_t built = 0;
            translucid_result status = translucid_context_get_prepare_status(g_context, &built);
            if (status != TRANSLUCID_RESULT_NOT_READY) {
                CHECK(status);
                level_ready = 1;
                printf("  frame %3d: ready, %llu pipelines built in the background over %d "
                       "frames\n",
                       k, (unsigned long long)built, k - level_from);
            }
        }
        if (k >= frames / 2 && level_ready && sc.streamed.id == 0) {
            stream_in_pane(&sc);
            printf("  frame %3d: a lit pane streamed in (translucid_mesh_create, "
                   "translucid_material_create)\n",
                   k);
        }
        if (k == frames * 3 / 4 && k < frames - 1) {
            printf("  frame %3d: a dynamic resolution from here on (70-90 %% of %dx%d, "
                   "into the same images)\n",
                   k, WIDTH, HEIGHT);
        }
        place_particles(&sc, k);
        CHECK(translucid_mesh_update(g_context, sc.particles, 0, PARTICLES * 4,
                                     sc.particle_positions));
        move_panes(&sc, k);
        memset(&info, 0, sizeof info);
        info.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
        info.method = method;
        info.width = (uint32_t)(WIDTH * render_scale(k, frames));
        info.height = (uint32_t)(HEIGHT * render_scale(k, frames));
        info.draws = sc.draws;
        info.draw_count = sc.draw_count;

        begin_commands(s->cmd);
        /* The eyes 6.4 cm apart, one in each layer. */
        memset(eyes, 0, sizeof eyes);
        for (v = 0; v < VIEWS; v++) {
            eyes[v].camera = orbit_camera(k);
            eyes[v].camera.view[12] += v == 0 ? 0.032f : -0.032f;
            eyes[v].colour_layer = eyes[v].depth_layer = v;
        }
        memset(&views, 0, sizeof views);
        views.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_FRAME_VIEWS;
        views.colour_layer_count = views.depth_layer_count = VIEWS;
        views.view_count = VIEWS;
        views.views = eyes;
        memset(&targets, 0, sizeof targets);
        targets.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_FRAME_TARGETS;
        targets.next = &views;
        targets.command_buffer = s->cmd;
        targets.colour.image = s->colour;
        targets.colour.format = VK_FORMAT_R8G8B8A8_SRGB;
        targets.colour.width = targets.depth.width = WIDTH;
        targets.colour.height = targets.depth.height = HEIGHT;
        targets.colour.layout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
        targets.colour.final_layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        targets.depth.image = s->depth;
        targets.depth.format = VK_FORMAT_D32_SFLOAT;
        targets.depth.layout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
        targets.depth.final_layout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
        /* The yardstick: the engine's own blend of the same draws in both views, then its
         * opaque pass again. */
        record_opaque(s->cmd, s);
        CHECK(translucid_frame_record_native_blend(g_context, &info, &targets, &s->native));
        record_opaque(s->cmd, s);
        started = now_ms();
        CHECK(translucid_frame_record(g_context, &info, &targets, &s->frame));
        s->record_ms = now_ms() - started;
        if (k == frames - 1) {
            /* The engine reads its last frame's left view back (translucid left it in
             * TRANSFER_SRC). */
            VkBufferImageCopy copy = region(VK_IMAGE_ASPECT_COLOR_BIT, 0, WIDTH, HEIGHT);
            vkCmdCopyImageToBuffer(s->cmd, s->colour, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                   s->readback, 1, &copy);
        }
        record[k] = s->record_ms;
        submit_commands(s->cmd, s->fence);
        s->in_flight = 1;
        wall[k] = now_ms() - last;
        last = now_ms();
    }
    /* The readback's memory is host-coherent and the fence was waited for. */
    write_png(png, g_slots[(frames - 1) % IN_FLIGHT].pixels);
    printf("%s: median record %.3f ms (CPU), GPU %.3f ms (x%.2f the engine's blend), wall %.3f "
           "ms a frame; wrote %s\n",
           translucid_method_name(method), median(record, frames), median(gpu, frames),
           median(ratio, frames), median(wall, frames), png);
    free(ratio);
    free(record);
    free(gpu);
    free(wall);
    free(sc.draws);
}

int main(int argc, char **argv) {
    const char *out_dir = argc > 1 ? argv[1] : "out";
    int frames = argc > 2 ? atoi(argv[2]) : 120;
    long draws = argc > 3 ? atol(argv[3]) : 0;
    static const uint32_t methods[2] = {TRANSLUCID_METHOD_EXACT, TRANSLUCID_METHOD_BLEND};
    translucid_host_device_create_info host;
    translucid_host_views_create_info views;
    translucid_context_create_info info;
    char path[1024];
    int m;

    if (frames < 1) frames = 1;
    if (draws < 0 || draws > (long)TRANSLUCID_MAX_DRAWS - 4) draws = 0;
    create_engine();
    create_slots();
    host = host_device_info();
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_CONTEXT_CREATE_INFO;
    info.header_version = TRANSLUCID_HEADER_VERSION;
    info.mode = TRANSLUCID_CONTEXT_MODE_HOST_DEVICE;
    info.next = &host;
    /* Each engine frame records two of translucid's, the yardstick's and the method's, each
     * of two views. */
    info.frames_in_flight = 2 * IN_FLIGHT;
    memset(&views, 0, sizeof views);
    views.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_VIEWS_CREATE_INFO;
    views.next = host.next;
    views.views_per_frame = VIEWS;
    host.next = &views;
    CHECK(translucid_context_create(&info, &g_context));
    printf("translucid %s on %s\n", translucid_version_string(),
           translucid_context_get_device_name(g_context));
    for (m = 0; m < 2; m++) {
        snprintf(path, sizeof path, "%s/frame_loop-%s.png", out_dir,
                 translucid_method_name(methods[m]));
        run(methods[m], frames, (uint32_t)draws, path);
    }
    /* Every frame was completed: the GPU is done with translucid's commands. */
    translucid_context_destroy(g_context);
    destroy_slots();
    destroy_engine();
    printf("frame_loop: %d validation messages\n", g_validation_messages);
    return g_validation_messages == 0 ? 0 : 1;
}
