/*
 * Frames from C with known answers, for every available method:
 * - over the host's opaque layer: where the host's depth is nearer than the transparent quad
 *   the host's colour stays; elsewhere the quad is blended over it (wavelet: at every rank and
 *   in both storages);
 * - exact with a threshold stops under it: of two stacked quads, only the front one shows;
 * - over a background colour with no draws at all;
 * - a quad moved, then the camera moved, frame after frame on one context;
 * - a tinted instance;
 * - frames of other sizes on one context (a dynamic resolution), each as a context that drew
 *   only that size draws it;
 * - both pixel formats agree; statistics are filled in; frames outlive their meshes;
 * - the pipeline cache is read out and handed to a new context.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "translucid.h"

#define W 16
#define H 8

static int g_failed = 0, g_passed = 0;
static translucid_context *g_ctx = NULL;

static void check(translucid_result result, const char *call, int line) {
    if (result != TRANSLUCID_RESULT_SUCCESS) {
        printf("FAIL line %d: %s returned %s: %s\n", line, call, translucid_result_string(result),
               translucid_context_get_last_error(g_ctx));
        exit(1);
    }
}
#define CHECK(call) check((call), #call, __LINE__)

static void near_or_fail(float got, float want, float tolerance, const char *what, size_t pixel) {
    if (fabsf(got - want) > tolerance) {
        if (g_failed < 20) {
            printf("FAIL %s at pixel %u: got %f, expected %f\n", what, (unsigned)pixel, got, want);
        }
        g_failed++;
    } else {
        g_passed++;
    }
}

static float srgb(float v) {
    v = v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v;
    return v <= 0.0031308f ? v * 12.92f : 1.055f * powf(v, 1.0f / 2.4f) - 0.055f;
}

static translucid_frame_info base_frame(uint32_t method) {
    translucid_frame_info info;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
    info.method = method;
    info.width = W;
    info.height = H;
    /* Identity view: the camera at the origin looks down -Z. */
    info.camera.view[0] = info.camera.view[5] = info.camera.view[10] = info.camera.view[15] = 1;
    info.camera.fov_y = 0.8f;
    info.camera.z_near = 1.0f;
    info.camera.z_far = 3.0f;
    return info;
}

/* A transparent draw of `mesh` with `material`, where the mesh is (identity transform). */
static translucid_draw draw_of(translucid_mesh mesh, translucid_material material) {
    translucid_draw draw;
    memset(&draw, 0, sizeof draw);
    draw.mesh = mesh;
    draw.material = material;
    draw.layer = TRANSLUCID_LAYER_TRANSPARENT;
    draw.transform[0] = draw.transform[5] = draw.transform[10] = draw.transform[15] = 1.0f;
    return draw;
}

/* `count` draws of `quad` in `material`, each `step` further from the camera than the one
 * before. */
static void stacked_draws(translucid_draw *draws, size_t count, translucid_mesh quad,
                          translucid_material material, float step) {
    size_t d;
    for (d = 0; d < count; d++) {
        draws[d] = draw_of(quad, material);
        draws[d].transform[14] = -step * (float)d;
    }
}

/* What `frame` cost, as translucid_frame_get_statistics reports it. */
static translucid_frame_statistics statistics_of(translucid_frame frame) {
    translucid_frame_statistics stats;
    memset(&stats, 0, sizeof stats);
    stats.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS;
    CHECK(translucid_frame_get_statistics(g_ctx, frame, &stats));
    return stats;
}

/* Both formats of one frame must agree; returns the linear pixels (caller frees). */
static float *read_both(translucid_frame frame) {
    float *linear = malloc(W * H * 16);
    uint8_t *bytes = malloc(W * H * 4);
    size_t i;
    CHECK(translucid_frame_read(g_ctx, frame, TRANSLUCID_PIXEL_FORMAT_RGBA32F_LINEAR, linear,
                                W * H * 16));
    CHECK(translucid_frame_read(g_ctx, frame, TRANSLUCID_PIXEL_FORMAT_RGBA8_SRGB, bytes, W * H * 4));
    for (i = 0; i < W * H * 4; i++) {
        float want = (i % 4 == 3) ? 1.0f : srgb(linear[i]);
        near_or_fail((float)bytes[i] / 255.0f, want, 0.6f / 255.0f, "RGBA8 vs RGBA32F", i / 4);
    }
    free(bytes);
    return linear;
}

/* `info` is a base_frame with the method's settings. */
static void over_host_layer(translucid_frame_info info, translucid_mesh quad,
                            translucid_material red) {
    const float host[3] = {0.2f, 0.4f, 0.6f};
    const uint32_t method = info.method;
    float colour[W * H * 4], depth[W * H];
    translucid_draw draw;
    translucid_opaque_layer layer;
    translucid_frame frame;
    translucid_frame_statistics stats;
    float *pixels;
    size_t i, c;

    /* Left half: host depth 0 (in front of everything); right half: 1 (far plane). */
    for (i = 0; i < W * H; i++) {
        for (c = 0; c < 3; c++) colour[i * 4 + c] = host[c];
        colour[i * 4 + 3] = 1.0f;
        depth[i] = (i % W) < W / 2 ? 0.0f : 1.0f;
    }
    memset(&layer, 0, sizeof layer);
    layer.s_type = TRANSLUCID_STRUCTURE_TYPE_OPAQUE_LAYER;
    layer.colour_format = TRANSLUCID_PIXEL_FORMAT_RGBA32F_LINEAR;
    layer.colour = colour;
    layer.depth = depth;
    draw = draw_of(quad, red);
    info.draws = &draw;
    info.draw_count = 1;
    info.opaque_layer = &layer;
    CHECK(translucid_frame_render(g_ctx, &info, &frame));

    pixels = read_both(frame);
    for (i = 0; i < W * H; i++) {
        int hidden = (i % W) < W / 2;
        for (c = 0; c < 3; c++) {
            float quad_colour = c == 0 ? 1.0f : 0.0f;
            float want = hidden ? host[c] : 0.5f * quad_colour + 0.5f * host[c];
            near_or_fail(pixels[i * 4 + c], want, 2e-3f, "over the host layer", i);
        }
    }
    free(pixels);

    stats = statistics_of(frame);
    near_or_fail((float)stats.method, (float)method, 0.0f, "statistics: method", 0);
    near_or_fail((float)stats.width, W, 0.0f, "statistics: width", 0);
    near_or_fail((float)stats.stage_count >= 2.0f, 1.0f, 0.0f, "statistics: at least 2 stages", 0);
    near_or_fail(strcmp(stats.stages[0].name, "opaque") == 0, 1.0f, 0.0f,
                 "statistics: first stage is the opaque layer", 0);
    near_or_fail(stats.peak_gpu_bytes > 0, 1.0f, 0.0f, "statistics: peak memory", 0);
    near_or_fail(stats.gpu_milliseconds >= stats.method_milliseconds, 1.0f, 0.0f,
                 "statistics: total time covers the method", 0);
    CHECK(translucid_frame_destroy(g_ctx, frame));
}

/* Two red quads at alpha 0.5 over black: 0.75 red in all, 0.5 once a pixel stops under a
   threshold of 0.6 (its transmittance is 0.5 after the front quad). */
static void exact_threshold(float threshold, float want, translucid_mesh quad,
                            translucid_material red) {
    translucid_frame_info info = base_frame(TRANSLUCID_METHOD_EXACT);
    translucid_exact_settings exact;
    translucid_draw draws[2];
    translucid_frame frame;
    float *pixels;
    size_t i;
    stacked_draws(draws, 2, quad, red, 0.5f); /* the second behind the first */
    info.draws = draws;
    info.draw_count = 2;
    memset(&exact, 0, sizeof exact);
    exact.s_type = TRANSLUCID_STRUCTURE_TYPE_EXACT_SETTINGS;
    exact.threshold = threshold;
    info.next = &exact;
    CHECK(translucid_frame_render(g_ctx, &info, &frame));
    pixels = read_both(frame);
    for (i = 0; i < W * H; i++) near_or_fail(pixels[i * 4], want, 2e-3f, "exact threshold", i);
    free(pixels);
    CHECK(translucid_frame_destroy(g_ctx, frame));
}

/* linked_list's node pool: by default it holds the frame (two full-frame quads, every pixel
 * red over red over black); a budget below the frame's fragments blends the rest unsorted and
 * counts them, exactly. */
static void linked_list_budget(uint32_t budget, translucid_mesh quad, translucid_material red) {
    translucid_frame_info info = base_frame(TRANSLUCID_METHOD_LINKED_LIST);
    translucid_linked_list_settings settings;
    translucid_frame_statistics stats;
    translucid_draw draws[2];
    translucid_frame frame;
    float *pixels;
    size_t i;
    stacked_draws(draws, 2, quad, red, 0.5f);
    info.draws = draws;
    info.draw_count = 2;
    memset(&settings, 0, sizeof settings);
    settings.s_type = TRANSLUCID_STRUCTURE_TYPE_LINKED_LIST_SETTINGS;
    settings.node_budget = budget;
    info.next = &settings;
    CHECK(translucid_frame_render(g_ctx, &info, &frame));
    stats = statistics_of(frame);
    near_or_fail((float)stats.fragments, 2 * W * H, 0.0f, "linked_list: fragments", 0);
    near_or_fail((float)stats.tail_fragments, budget == 0 ? 0.0f : (float)(2 * W * H - budget),
                 0.0f, "linked_list: fragments past the budget", 0);
    /* Two equal layers: the order does not show, so the tail is right here too. */
    pixels = read_both(frame);
    for (i = 0; i < W * H; i++) near_or_fail(pixels[i * 4], 0.75f, 2e-3f, "linked_list", i);
    free(pixels);
    CHECK(translucid_frame_destroy(g_ctx, frame));
}

/* depth_peeling's passes: three full-frame quads, each pixel red over red over red over black
 * (0.875). By default the passes cover the three layers; one pass peels the front and the back
 * layer only, and every pixel, missing its middle layer (0.75), is counted. */
static void depth_peeling_passes(uint32_t passes, translucid_mesh quad, translucid_material red) {
    translucid_frame_info info = base_frame(TRANSLUCID_METHOD_DEPTH_PEELING);
    translucid_depth_peeling_settings settings;
    translucid_frame_statistics stats;
    translucid_draw draws[3];
    translucid_frame frame;
    float *pixels;
    size_t i;
    stacked_draws(draws, 3, quad, red, 0.4f); /* z -2, -2.4, -2.8: before the far plane */
    info.draws = draws;
    info.draw_count = 3;
    memset(&settings, 0, sizeof settings);
    settings.s_type = TRANSLUCID_STRUCTURE_TYPE_DEPTH_PEELING_SETTINGS;
    settings.passes = passes;
    info.next = &settings;
    CHECK(translucid_frame_render(g_ctx, &info, &frame));
    stats = statistics_of(frame);
    near_or_fail((float)stats.unpeeled_pixels, passes == 1 ? (float)(W * H) : 0.0f, 0.0f,
                 "depth_peeling: pixels left unpeeled", 0);
    pixels = read_both(frame);
    for (i = 0; i < W * H; i++) {
        near_or_fail(pixels[i * 4], passes == 1 ? 0.75f : 0.875f, 2e-3f, "depth_peeling", i);
    }
    free(pixels);
    CHECK(translucid_frame_destroy(g_ctx, frame));
}

/* A quad of four corners (12 floats) as two triangles, with texture coordinates (8 floats)
 * or none. */
static translucid_mesh quad_mesh(const float *positions, const float *uvs) {
    static const uint32_t triangles[] = {0, 1, 2, 0, 2, 3};
    translucid_mesh_create_info info;
    translucid_mesh mesh;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_MESH_CREATE_INFO;
    info.primitive = TRANSLUCID_PRIMITIVE_TRIANGLES;
    info.vertex_count = 4;
    info.positions = positions;
    info.uvs = uvs;
    info.index_count = 6;
    info.indices = triangles;
    CHECK(translucid_mesh_create(g_ctx, &info, &mesh));
    return mesh;
}

static const translucid_texture NO_TEXTURE = {0};

/* An unlit material of linear base colour (r, g, b) and coverage a, with `texture`
 * (NO_TEXTURE for none). */
static translucid_material plain_material(float r, float g, float b, float a,
                                          translucid_texture texture) {
    translucid_material_create_info info;
    translucid_material material;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_MATERIAL_CREATE_INFO;
    info.base_colour[0] = r;
    info.base_colour[1] = g;
    info.base_colour[2] = b;
    info.base_colour[3] = a;
    info.texture = texture;
    CHECK(translucid_material_create(g_ctx, &info, &material));
    return material;
}

/* A 2x1 black and white texture, nearest, on a quad whose u runs from -0.29 at the left pixel
   to 1.29 at the right one (u = 0.5 + x / 2 at z = -2): columns 7 and 8 straddle u = 0.5, and
   the wrap mode decides the outer ones. Opaque texels over black: the pixel is the texel. */
static void sampled_texture(uint32_t method, uint32_t wrap, float left, float right) {
    static const float positions[] = {-5, -5, -2, 5, -5, -2, 5, 5, -2, -5, 5, -2};
    static const float uvs[] = {-2, 0, 3, 0, 3, 1, -2, 1};
    static const uint8_t texels[] = {0, 0, 0, 255, 255, 255, 255, 255};
    translucid_frame_info info = base_frame(method);
    translucid_sampler_info sampler;
    translucid_texture_create_info texture_info;
    translucid_mesh mesh = quad_mesh(positions, uvs);
    translucid_texture texture;
    translucid_material material;
    translucid_draw draw;
    translucid_frame frame;
    float *pixels;
    size_t row;
    char what[64], text[96];

    memset(&sampler, 0, sizeof sampler);
    sampler.s_type = TRANSLUCID_STRUCTURE_TYPE_SAMPLER_INFO;
    sampler.wrap_s = wrap;
    sampler.mag_filter = TRANSLUCID_FILTER_NEAREST;
    sampler.min_filter = TRANSLUCID_FILTER_NEAREST;
    memset(&texture_info, 0, sizeof texture_info);
    texture_info.s_type = TRANSLUCID_STRUCTURE_TYPE_TEXTURE_CREATE_INFO;
    texture_info.next = &sampler;
    texture_info.width = 2;
    texture_info.height = 1;
    texture_info.texels = texels;
    CHECK(translucid_texture_create(g_ctx, &texture_info, &texture));
    material = plain_material(1.0f, 1.0f, 1.0f, 1.0f, texture);
    draw = draw_of(mesh, material);
    info.draws = &draw;
    info.draw_count = 1;
    CHECK(translucid_frame_render(g_ctx, &info, &frame));
    pixels = read_both(frame);
    snprintf(what, sizeof what, "method %u, wrap %u: ", (unsigned)method, (unsigned)wrap);
    for (row = 0; row < H; row++) {
        const float *p = pixels + row * W * 4;
        near_or_fail(p[0], left, 2e-3f, strcat(strcpy(text, what), "left column"), row * W);
        near_or_fail(p[7 * 4], 0.0f, 2e-3f, strcat(strcpy(text, what), "column 7"), row * W + 7);
        near_or_fail(p[8 * 4], 1.0f, 2e-3f, strcat(strcpy(text, what), "column 8"), row * W + 8);
        near_or_fail(p[(W - 1) * 4], right, 2e-3f, strcat(strcpy(text, what), "right column"),
                     row * W + W - 1);
    }
    free(pixels);
    CHECK(translucid_frame_destroy(g_ctx, frame));
    CHECK(translucid_material_destroy(g_ctx, material));
    CHECK(translucid_texture_destroy(g_ctx, texture));
    CHECK(translucid_mesh_destroy(g_ctx, mesh));
}

/* GPU bytes the call that rendered `frame` allocated (destroying the frame). */
static uint64_t allocated_by(translucid_frame frame) {
    translucid_frame_statistics stats = statistics_of(frame);
    CHECK(translucid_frame_destroy(g_ctx, frame));
    return stats.bytes_allocated;
}

/* `got` bytes allocated by the frame after `what`: at least `low`, under `high`. */
static void allocated_within(uint32_t method, const char *what, uint64_t got, uint64_t low,
                             uint64_t high) {
    if (got < low || got >= high) {
        printf("FAIL method %u: %s: %llu bytes allocated, not in [%llu, %llu)\n",
               (unsigned)method, what, (unsigned long long)got, (unsigned long long)low,
               (unsigned long long)high);
        g_failed++;
    } else {
        g_passed++;
    }
}

/* A frame larger than the ones before gets a renderer of its own over the context's assets,
 * uploaded once: a 512x512 texture (1 MB, and as much again for the compute rasters' copy) is
 * allocated for the first size only. Then a mesh and a material
 * created are appended to the uploads: the next frame draws them without uploading the
 * texture again; and a mesh created and not drawn costs the frame after it nothing, nor does
 * destroying it (the uploads keep its place while most of them is alive). */
static void uploads_are_shared_and_extended(uint32_t method, translucid_mesh quad) {
    static const float small[] = {-1, -1, -2, 1, -1, -2, 1, 1, -2, -1, 1, -2};
    translucid_mesh added_mesh;
    translucid_material added_material;
    translucid_draw draws[2];
    float *pixels;
    translucid_mesh unused;
    enum { SIDE = 512 };
    const uint64_t texture_bytes = SIDE * SIDE * 4;
    uint8_t *texels = calloc(texture_bytes, 1);
    translucid_texture_create_info texture_info;
    translucid_frame_info info = base_frame(method);
    translucid_texture texture;
    translucid_material material;
    translucid_draw draw;
    translucid_frame frame;
    uint64_t first, second;
    memset(&texture_info, 0, sizeof texture_info);
    texture_info.s_type = TRANSLUCID_STRUCTURE_TYPE_TEXTURE_CREATE_INFO;
    texture_info.width = texture_info.height = SIDE;
    texture_info.texels = texels;
    CHECK(translucid_texture_create(g_ctx, &texture_info, &texture));
    free(texels);
    material = plain_material(0.5f, 0.0f, 0.0f, 0.5f, texture);
    draw = draw_of(quad, material);
    info.draws = &draw;
    info.draw_count = 1;
    CHECK(translucid_frame_render(g_ctx, &info, &frame));
    first = allocated_by(frame);
    info.width = W + 8;
    info.height = H + 4;
    CHECK(translucid_frame_render(g_ctx, &info, &frame));
    second = allocated_by(frame);
    allocated_within(method, "the first size", first, texture_bytes, UINT64_MAX);
    allocated_within(method, "another size", second, 0, texture_bytes);

    added_mesh = quad_mesh(small, NULL);
    added_material = plain_material(0.0f, 1.0f, 0.0f, 0.5f, NO_TEXTURE);
    draws[0] = draw;
    draws[1] = draw;
    draws[1].mesh = added_mesh;
    draws[1].material = added_material;
    info.draws = draws;
    info.draw_count = 2;
    info.width = W;
    info.height = H;
    CHECK(translucid_frame_render(g_ctx, &info, &frame));
    /* The texture's texels are transparent: the added quad, green at half coverage over
     * black, is what shows in the middle. */
    pixels = read_both(frame);
    near_or_fail(pixels[((H / 2) * W + W / 2) * 4 + 1], 0.5f, 2e-3f, "added quad, green",
                 (H / 2) * W + W / 2);
    free(pixels);
    allocated_within(method, "a mesh created", allocated_by(frame), 0, texture_bytes);
    unused = quad_mesh(small, NULL);
    CHECK(translucid_frame_render(g_ctx, &info, &frame));
    allocated_within(method, "a mesh not drawn created", allocated_by(frame), 0, 1);
    CHECK(translucid_mesh_destroy(g_ctx, unused));
    CHECK(translucid_frame_render(g_ctx, &info, &frame));
    pixels = read_both(frame);
    near_or_fail(pixels[((H / 2) * W + W / 2) * 4 + 1], 0.5f, 2e-3f,
                 "added quad after a mesh was destroyed, green", (H / 2) * W + W / 2);
    free(pixels);
    allocated_within(method, "a mesh not drawn destroyed", allocated_by(frame), 0, 1);
    CHECK(translucid_mesh_destroy(g_ctx, added_mesh));
    CHECK(translucid_material_destroy(g_ctx, added_material));
    CHECK(translucid_material_destroy(g_ctx, material));
    CHECK(translucid_texture_destroy(g_ctx, texture));
}

/* A new standalone context with the validation layer on. */
static translucid_context *fresh_context(void) {
    translucid_context_create_info info;
    translucid_context *ctx = NULL;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_CONTEXT_CREATE_INFO;
    info.header_version = TRANSLUCID_HEADER_VERSION;
    info.flags = TRANSLUCID_CONTEXT_CREATE_VALIDATION;
    CHECK(translucid_context_create(&info, &ctx));
    return ctx;
}

/* The linear pixels of a frame of `info` drawing `quad` in `red`, rendered on `g_ctx`
 * (caller frees), and the GPU bytes the call allocated. */
static float *red_quad_frame(translucid_frame_info info, translucid_mesh quad,
                             translucid_material red, uint64_t *allocated) {
    size_t bytes = (size_t)info.width * info.height * 16;
    float *pixels = malloc(bytes);
    translucid_draw draw = draw_of(quad, red);
    translucid_frame frame;
    info.draws = &draw;
    info.draw_count = 1;
    CHECK(translucid_frame_render(g_ctx, &info, &frame));
    CHECK(translucid_frame_read(g_ctx, frame, TRANSLUCID_PIXEL_FORMAT_RGBA32F_LINEAR, pixels,
                                bytes));
    *allocated = allocated_by(frame);
    return pixels;
}

/* A dynamic resolution: frames of other sizes (and aspect ratios) follow one another on one
 * context. A frame no larger in either side than one before allocates nothing; a larger one
 * allocates once, after which the smaller sizes are free again. Each frame is what a
 * context that only ever drew its size draws, pixel for pixel. */
static void dynamic_resolution(uint32_t method, translucid_material red) {
    /* Off-centre, so that a frame drawn at the wrong place or aspect shows. */
    static const float off_centre[] = {-1.5f, -0.5f, -2, 0.5f, -0.5f, -2,
                                       0.5f,  1.0f,  -2, -1.5f, 1.0f, -2};
    static const uint32_t sizes[][2] = {{W, H},     {W - 5, H - 3}, {W / 2, H}, {1, 1},
                                        {W + 6, H + 4}, {W, H},     {W - 1, H + 4}};
    /* -1: the first frame, which allocates its renderer. */
    static const int allocates[] = {-1, 0, 0, 0, 1, 0, 0};
    translucid_context *shared = g_ctx;
    translucid_mesh quad = quad_mesh(off_centre, NULL);
    size_t k;
    for (k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        translucid_frame_info info = base_frame(method);
        translucid_context *fresh = fresh_context();
        translucid_mesh fresh_quad;
        translucid_material fresh_red;
        float *got, *want;
        uint64_t allocated, ignored;
        size_t i;
        char what[96];
        info.width = sizes[k][0];
        info.height = sizes[k][1];
        got = red_quad_frame(info, quad, red, &allocated);
        g_ctx = fresh;
        fresh_quad = quad_mesh(off_centre, NULL);
        fresh_red = plain_material(1.0f, 0.0f, 0.0f, 0.5f, NO_TEXTURE);
        want = red_quad_frame(info, fresh_quad, fresh_red, &ignored);
        g_ctx = shared;
        translucid_context_destroy(fresh);
        snprintf(what, sizeof what, "dynamic resolution, %ux%u", info.width, info.height);
        for (i = 0; i < (size_t)info.width * info.height * 4; i++) {
            near_or_fail(got[i], want[i], 1e-6f, what, i / 4);
        }
        if (allocates[k] >= 0) {
            allocated_within(method, what, allocated, allocates[k] ? 1 : 0,
                             allocates[k] ? UINT64_MAX : 1);
        }
        free(got);
        free(want);
    }
    CHECK(translucid_mesh_destroy(g_ctx, quad));
}

static void background_only(uint32_t method) {
    translucid_frame_info info = base_frame(method);
    translucid_frame frame;
    float *pixels;
    size_t i;
    info.background[0] = 0.0f;
    info.background[1] = 0.25f;
    info.background[2] = 1.0f;
    CHECK(translucid_frame_render(g_ctx, &info, &frame));
    pixels = read_both(frame);
    for (i = 0; i < W * H; i++) {
        near_or_fail(pixels[i * 4 + 1], 0.25f, 1e-3f, "background green", i);
        near_or_fail(pixels[i * 4 + 2], 1.0f, 1e-3f, "background blue", i);
    }
    free(pixels);
    CHECK(translucid_frame_destroy(g_ctx, frame));
}

/* A small quad at view x `x` in frame 1, the other side in frame 2, then the camera moved so
 * that it is back where it was: the context keeps its renderer for these frames (same mesh,
 * material and settings), and each frame must show the quad where that frame put it. */
static void moving_draws(uint32_t method, translucid_mesh quad, translucid_material red) {
    /* quad x (world), camera x: the quad lands left (column 3) or right (column 12). */
    static const float cases[3][2] = {{-1.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 2.0f}};
    static const int left[3] = {1, 0, 1};
    size_t k;
    for (k = 0; k < 3; k++) {
        translucid_frame_info info = base_frame(method);
        translucid_draw draw;
        translucid_frame frame;
        float pixels[W * H * 4];
        const size_t row = H / 2;
        memset(&draw, 0, sizeof draw);
        draw.mesh = quad;
        draw.material = red;
        draw.layer = TRANSLUCID_LAYER_TRANSPARENT;
        /* The 10-wide quad scaled to 0.5, moved along x. */
        draw.transform[0] = draw.transform[5] = 0.05f;
        draw.transform[10] = draw.transform[15] = 1.0f;
        draw.transform[12] = cases[k][0];
        info.draws = &draw;
        info.draw_count = 1;
        info.camera.view[12] = -cases[k][1];
        CHECK(translucid_frame_render(g_ctx, &info, &frame));
        CHECK(translucid_frame_read(g_ctx, frame, TRANSLUCID_PIXEL_FORMAT_RGBA32F_LINEAR, pixels,
                                    sizeof pixels));
        near_or_fail(pixels[(row * W + 3) * 4], left[k] ? 0.5f : 0.0f, 2e-3f,
                     "moving draws: left pixel", row * W + 3);
        near_or_fail(pixels[(row * W + 12) * 4], left[k] ? 0.0f : 0.5f, 2e-3f,
                     "moving draws: right pixel", row * W + 12);
        CHECK(translucid_frame_destroy(g_ctx, frame));
    }
}

/* A tinted instance: red at alpha 0.5, tinted (0.5, 1, 1, 0.5), over black: coverage 0.25,
 * red 0.25 x 0.5. Every method composites one layer exactly. */
static void tinted_draw(uint32_t method, translucid_mesh quad, translucid_material red) {
    translucid_frame_info info = base_frame(method);
    translucid_draw draw;
    translucid_frame frame;
    float pixels[W * H * 4];
    draw = draw_of(quad, red);
    draw.tint[0] = 0.5f;
    draw.tint[1] = draw.tint[2] = 1.0f;
    draw.tint[3] = 0.5f;
    info.draws = &draw;
    info.draw_count = 1;
    CHECK(translucid_frame_render(g_ctx, &info, &frame));
    CHECK(translucid_frame_read(g_ctx, frame, TRANSLUCID_PIXEL_FORMAT_RGBA32F_LINEAR, pixels,
                                sizeof pixels));
    near_or_fail(pixels[0], 0.125f, 2e-3f, "tinted draw: red", 0);
    CHECK(translucid_frame_destroy(g_ctx, frame));
    draw.tint[1] = -1.0f;
    if (translucid_frame_render(g_ctx, &info, &frame) != TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT ||
        strstr(translucid_context_get_last_error(g_ctx), "draws[0]: tint") == NULL) {
        printf("FAIL a negative tint was not refused with its draw named\n");
        g_failed++;
    }
}

/* Counts `got` against `want`. */
static void expect_result(translucid_result got, translucid_result want, const char *what) {
    if (got != want) {
        printf("FAIL %s: %s, expected %s: %s\n", what, translucid_result_string(got),
               translucid_result_string(want), translucid_context_get_last_error(g_ctx));
        g_failed++;
    } else {
        g_passed++;
    }
}

/* The pipeline cache an engine saves and hands back: read in two calls (or cut short), and
 * taken by a new context; data from elsewhere is ignored. */
static void pipeline_cache(void) {
    translucid_context_create_info info;
    translucid_context *second = NULL;
    unsigned char garbage[64];
    unsigned char *data;
    size_t size = 0, got;
    CHECK(translucid_context_get_pipeline_cache_data(g_ctx, NULL, &size));
    data = malloc(size + 1);
    if (data == NULL) exit(1);
    got = size + 1;
    CHECK(translucid_context_get_pipeline_cache_data(g_ctx, data, &got));
    if (got != size) g_failed++;
    if (size > 0) {
        got = size - 1;
        expect_result(translucid_context_get_pipeline_cache_data(g_ctx, data, &got),
                      TRANSLUCID_RESULT_INCOMPLETE, "pipeline cache data cut short");
        if (got != size - 1) g_failed++;
    }
    expect_result(translucid_context_get_pipeline_cache_data(g_ctx, data, NULL),
                  TRANSLUCID_RESULT_ERROR_NULL_POINTER, "pipeline cache size NULL");

    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_CONTEXT_CREATE_INFO;
    info.header_version = TRANSLUCID_HEADER_VERSION;
    info.pipeline_cache_data = data;
    info.pipeline_cache_size = size;
    CHECK(translucid_context_create(&info, &second));
    translucid_context_destroy(second);
    memset(garbage, 0xAB, sizeof garbage);
    info.pipeline_cache_data = garbage;
    info.pipeline_cache_size = sizeof garbage;
    CHECK(translucid_context_create(&info, &second));
    translucid_context_destroy(second);
    info.pipeline_cache_data = NULL;
    expect_result(translucid_context_create(&info, &second), TRANSLUCID_RESULT_ERROR_NULL_POINTER,
                  "pipeline cache size without data");
    free(data);
    printf("pipeline cache: %u bytes saved and handed back\n", (unsigned)size);
}

int main(int argc, char **argv) {
    static const float positions[] = {-5, -5, -2, 5, -5, -2, 5, 5, -2, -5, 5, -2};
    translucid_mesh quad;
    translucid_material red;
    uint32_t methods[8];
    size_t count = 0, m;
    const char *out_dir = argc > 1 ? argv[1] : NULL;

    g_ctx = fresh_context();

    quad = quad_mesh(positions, NULL);
    red = plain_material(1.0f, 0.0f, 0.0f, 0.5f, NO_TEXTURE);

    CHECK(translucid_method_get_available(methods, 8, &count));
    for (m = 0; m < count; m++) {
        translucid_frame_info info = base_frame(methods[m]);
        over_host_layer(info, quad, red);
        background_only(methods[m]);
        moving_draws(methods[m], quad, red);
        tinted_draw(methods[m], quad, red);
        uploads_are_shared_and_extended(methods[m], quad);
        dynamic_resolution(methods[m], red);
        /* u -0.29 is texel -1 and u 1.29 texel 2, wrapped: */
        sampled_texture(methods[m], TRANSLUCID_WRAP_REPEAT, 1.0f, 0.0f);
        sampled_texture(methods[m], TRANSLUCID_WRAP_CLAMP_TO_EDGE, 0.0f, 1.0f);
        sampled_texture(methods[m], TRANSLUCID_WRAP_MIRRORED_REPEAT, 0.0f, 1.0f);
        if (methods[m] == TRANSLUCID_METHOD_WAVELET) {
            /* One layer is exact at every rank, in both storages. */
            uint32_t coefficients;
            translucid_wavelet_settings wavelet;
            memset(&wavelet, 0, sizeof wavelet);
            wavelet.s_type = TRANSLUCID_STRUCTURE_TYPE_WAVELET_SETTINGS;
            info.next = &wavelet;
            for (coefficients = 2; coefficients <= 8; coefficients *= 2) {
                wavelet.coefficients = coefficients;
                wavelet.storage = TRANSLUCID_WAVELET_STORAGE_BINS;
                over_host_layer(info, quad, red);
                wavelet.storage = TRANSLUCID_WAVELET_STORAGE_IMAGES;
                over_host_layer(info, quad, red);
            }
            info.next = NULL;
        }
        if (methods[m] == TRANSLUCID_METHOD_DEPTH_PEELING) {
            depth_peeling_passes(0, quad, red);
            depth_peeling_passes(1, quad, red);
            depth_peeling_passes(2, quad, red);
        }
        if (methods[m] == TRANSLUCID_METHOD_LINKED_LIST) {
            linked_list_budget(0, quad, red);
            linked_list_budget(W * H + W * H / 2, quad, red);
        }
        if (methods[m] == TRANSLUCID_METHOD_EXACT) {
            exact_threshold(0.0f, 0.75f, quad, red);
            exact_threshold(0.6f, 0.5f, quad, red);
        }
    }

    pipeline_cache();

    /* A frame keeps its pixels after the objects it drew are gone. */
    {
        translucid_frame_info info = base_frame(TRANSLUCID_METHOD_BLEND);
        translucid_draw draw;
        translucid_frame frame;
        uint8_t pixel[W * H * 4];
        draw = draw_of(quad, red);
        info.draws = &draw;
        info.draw_count = 1;
        CHECK(translucid_frame_render(g_ctx, &info, &frame));
        CHECK(translucid_mesh_destroy(g_ctx, quad));
        CHECK(translucid_material_destroy(g_ctx, red));
        CHECK(translucid_frame_read(g_ctx, frame, TRANSLUCID_PIXEL_FORMAT_RGBA8_SRGB, pixel,
                                    sizeof pixel));
        near_or_fail(pixel[0], 188.0f, 1.0f, "red over black, sRGB", 0);
        if (out_dir != NULL) {
            char path[1024];
            snprintf(path, sizeof path, "%s/render-test.png", out_dir);
            CHECK(translucid_frame_write_png(g_ctx, frame, path));
        }
    }

    translucid_context_destroy(g_ctx);
    printf("render: %d passed, %d failed\n", g_passed, g_failed);
    return g_failed == 0 ? 0 : 1;
}
