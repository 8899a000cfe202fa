/*
 * Bad input from C: every call below is wrong in one way and must return its documented
 * error code with a message, write no out-parameter, and never crash.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "red_quad.h"
#include "translucid.h"

static int g_passed = 0, g_failed = 0;

/* Checks one call's code, and that a failed call left a message behind. */
static void expect(translucid_result got, translucid_result want, const translucid_context *ctx,
                   const char *call, int line) {
    const char *message = translucid_context_get_last_error(ctx);
    if (got != want) {
        printf("FAIL line %d: %s\n  returned %s (%d), expected %s (%d)\n  last error: %s\n", line,
               call, translucid_result_string(got), (int)got, translucid_result_string(want),
               (int)want, message);
        g_failed++;
    } else if (want < 0 && (message == NULL || message[0] == '\0')) {
        printf("FAIL line %d: %s\n  returned the right code but no message\n", line, call);
        g_failed++;
    } else {
        g_passed++;
    }
}
#define EXPECT(ctx, call, want) expect((call), (want), (ctx), #call, __LINE__)
#define TRUE_OR_FAIL(cond)                                                                     \
    do {                                                                                       \
        if (cond) {                                                                            \
            g_passed++;                                                                        \
        } else {                                                                               \
            printf("FAIL line %d: %s\n", __LINE__, #cond);                                     \
            g_failed++;                                                                        \
        }                                                                                      \
    } while (0)

static translucid_context_create_info context_info(void) {
    translucid_context_create_info info;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_CONTEXT_CREATE_INFO;
    info.header_version = TRANSLUCID_HEADER_VERSION;
    return info;
}

static translucid_frame_info frame_info(translucid_draw *draw) {
    translucid_frame_info info;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
    info.method = TRANSLUCID_METHOD_BLEND;
    info.width = 8;
    info.height = 8;
    info.camera.view[0] = info.camera.view[5] = info.camera.view[10] = info.camera.view[15] = 1;
    info.camera.fov_y = 0.8f;
    info.camera.z_near = 0.1f;
    info.camera.z_far = 10.0f;
    info.draws = draw;
    info.draw_count = draw ? 1 : 0;
    return info;
}

static void context_creation(void) {
    translucid_context *const sentinel = (translucid_context *)&g_passed;
    translucid_context *ctx = sentinel;
    translucid_context_create_info info = context_info();
    translucid_base_in_structure link;

    EXPECT(NULL, translucid_context_create(NULL, &ctx), TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    EXPECT(NULL, translucid_context_create(&info, NULL), TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    memset(&info, 0, sizeof info);
    EXPECT(NULL, translucid_context_create(&info, &ctx),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    info = context_info();
    info.s_type = 0xdeadbeefu;
    EXPECT(NULL, translucid_context_create(&info, &ctx),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_MESH_CREATE_INFO;
    EXPECT(NULL, translucid_context_create(&info, &ctx),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    info = context_info();
    info.header_version = TRANSLUCID_HEADER_VERSION + (1u << 12);
    EXPECT(NULL, translucid_context_create(&info, &ctx),
           TRANSLUCID_RESULT_ERROR_HEADER_VERSION_MISMATCH);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(NULL), "header") != NULL);
    info.header_version = TRANSLUCID_HEADER_VERSION + (1u << 22);
    EXPECT(NULL, translucid_context_create(&info, &ctx),
           TRANSLUCID_RESULT_ERROR_HEADER_VERSION_MISMATCH);
    info = context_info();
    info.mode = TRANSLUCID_CONTEXT_MODE_HOST_DEVICE; /* without its device description */
    EXPECT(NULL, translucid_context_create(&info, &ctx), TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    info.mode = 77;
    EXPECT(NULL, translucid_context_create(&info, &ctx), TRANSLUCID_RESULT_ERROR_INVALID_ENUM);
    info = context_info();
    info.flags = 0x80;
    EXPECT(NULL, translucid_context_create(&info, &ctx),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    info.flags = TRANSLUCID_CONTEXT_CREATE_PROFILE_CPU | TRANSLUCID_CONTEXT_CREATE_PROFILE_GPU;
    EXPECT(NULL, translucid_context_create(&info, &ctx),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(NULL), "PROFILE") != NULL);
    info.flags = TRANSLUCID_CONTEXT_CREATE_PROFILE_GPU; /* one alone is taken */
    EXPECT(NULL, translucid_context_create(&info, &ctx), TRANSLUCID_RESULT_SUCCESS);
    translucid_context_destroy(ctx);
    ctx = sentinel;
    /* the software sampler kept where the GPU profile would sample in hardware */
    info.flags = TRANSLUCID_CONTEXT_CREATE_PROFILE_GPU | TRANSLUCID_CONTEXT_CREATE_SOFTWARE_SAMPLING;
    EXPECT(NULL, translucid_context_create(&info, &ctx), TRANSLUCID_RESULT_SUCCESS);
    translucid_context_destroy(ctx);
    ctx = sentinel;
    info = context_info();
    memset(&link, 0, sizeof link);
    link.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_DEVICE_CREATE_INFO;
    info.next = &link; /* a host device chained to a standalone context */
    EXPECT(NULL, translucid_context_create(&info, &ctx),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    link.s_type = 4242;
    EXPECT(NULL, translucid_context_create(&info, &ctx),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    {
        /* A budget, chained first: taken in standalone mode, with nothing after it. */
        translucid_memory_create_info memory;
        memset(&memory, 0, sizeof memory);
        memory.s_type = TRANSLUCID_STRUCTURE_TYPE_MEMORY_CREATE_INFO;
        memory.budget_bytes = 64u << 20;
        info = context_info();
        info.next = &memory;
        EXPECT(NULL, translucid_context_create(&info, &ctx), TRANSLUCID_RESULT_SUCCESS);
        translucid_context_destroy(ctx);
        ctx = sentinel;
        link.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_DEVICE_CREATE_INFO;
        memory.next = &link;
        EXPECT(NULL, translucid_context_create(&info, &ctx),
               TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
        /* Allocation callbacks are for an engine's device, and need all three functions. */
        {
            VkAllocationCallbacks callbacks;
            memset(&callbacks, 0, sizeof callbacks);
            memory.next = NULL;
            memory.allocation_callbacks = &callbacks;
            EXPECT(NULL, translucid_context_create(&info, &ctx),
                   TRANSLUCID_RESULT_ERROR_NULL_POINTER);
            TRUE_OR_FAIL(strstr(translucid_context_get_last_error(NULL), "pfnFree") != NULL);
            memory.allocation_callbacks = NULL;
        }
        /* A budget smaller than anything a context makes: its first allocation is refused. */
        memory.next = NULL;
        memory.budget_bytes = 1;
        EXPECT(NULL, translucid_context_create(&info, &ctx), TRANSLUCID_RESULT_SUCCESS);
        {
            translucid_frame rendered;
            translucid_frame_info frame;
            memset(&frame, 0, sizeof frame);
            frame.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
            frame.method = TRANSLUCID_METHOD_BLEND;
            frame.width = frame.height = 1;
            frame.camera.view[0] = frame.camera.view[5] = frame.camera.view[10] = 1;
            frame.camera.view[15] = 1;
            frame.camera.fov_y = 1;
            frame.camera.z_near = 0.1f;
            frame.camera.z_far = 10;
            EXPECT(ctx, translucid_frame_render(ctx, &frame, &rendered),
                   TRANSLUCID_RESULT_ERROR_OUT_OF_MEMORY);
            TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "budget") != NULL);
        }
        translucid_context_destroy(ctx);
        ctx = sentinel;
    }
    info = context_info();
    info.device = "no device is called this";
    EXPECT(NULL, translucid_context_create(&info, &ctx), TRANSLUCID_RESULT_ERROR_NO_DEVICE);
    info.device = "\xff\xfe not UTF-8";
    EXPECT(NULL, translucid_context_create(&info, &ctx),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    TRUE_OR_FAIL(ctx == sentinel); /* never written on failure */
    translucid_context_destroy(NULL);
}

static void queries(void) {
    uint32_t methods[1];
    size_t count = 12345;
    TRUE_OR_FAIL(translucid_version() == TRANSLUCID_HEADER_VERSION);
    TRUE_OR_FAIL(strcmp(translucid_result_string(-999999), "unknown result code") == 0);
    TRUE_OR_FAIL(strcmp(translucid_result_string(TRANSLUCID_RESULT_SUCCESS), "success") == 0);
    TRUE_OR_FAIL(strcmp(translucid_result_string(TRANSLUCID_RESULT_FRAME_DEGRADED),
                        translucid_result_string(TRANSLUCID_RESULT_INCOMPLETE)) != 0);
    TRUE_OR_FAIL(translucid_method_name(99) == NULL);
    TRUE_OR_FAIL(strcmp(translucid_method_name(TRANSLUCID_METHOD_BLEND), "blend") == 0);
    TRUE_OR_FAIL(translucid_context_get_device_name(NULL)[0] == '\0');
    EXPECT(NULL, translucid_method_get_available(NULL, 0, NULL),
           TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    EXPECT(NULL, translucid_method_get_available(NULL, 5, &count),
           TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    TRUE_OR_FAIL(count == 12345);
    EXPECT(NULL, translucid_method_get_available(NULL, 0, &count), TRANSLUCID_RESULT_INCOMPLETE);
    TRUE_OR_FAIL(count >= 1);
    EXPECT(NULL, translucid_method_get_available(methods, 1, &count),
           count > 1 ? TRANSLUCID_RESULT_INCOMPLETE : TRANSLUCID_RESULT_SUCCESS);
    TRUE_OR_FAIL(methods[0] == TRANSLUCID_METHOD_BLEND);
}

static void meshes(translucid_context *ctx) {
    const translucid_mesh sentinel = {42};
    translucid_mesh mesh = sentinel;
    translucid_mesh_create_info info = mesh_info();
    float nan_positions[12];
    uint32_t bad_quad[4] = {0, 1, 2, 4};
    float nan_normals[12];

    EXPECT(NULL, translucid_mesh_create(NULL, &info, &mesh), TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    EXPECT(ctx, translucid_mesh_create(ctx, NULL, &mesh), TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    EXPECT(ctx, translucid_mesh_create(ctx, &info, NULL), TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    memset(&info, 0, sizeof info);
    EXPECT(ctx, translucid_mesh_create(ctx, &info, &mesh),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    info = mesh_info();
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_TEXTURE_CREATE_INFO;
    EXPECT(ctx, translucid_mesh_create(ctx, &info, &mesh),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    info = mesh_info();
    info.primitive = 9;
    EXPECT(ctx, translucid_mesh_create(ctx, &info, &mesh), TRANSLUCID_RESULT_ERROR_INVALID_ENUM);
    info = mesh_info();
    info.vertex_count = 0;
    EXPECT(ctx, translucid_mesh_create(ctx, &info, &mesh), TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
    info.vertex_count = TRANSLUCID_MAX_VERTICES + 1;
    EXPECT(ctx, translucid_mesh_create(ctx, &info, &mesh), TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
    info.vertex_count = 0xffffffffu;
    EXPECT(ctx, translucid_mesh_create(ctx, &info, &mesh), TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
    info = mesh_info();
    info.index_count = 0;
    EXPECT(ctx, translucid_mesh_create(ctx, &info, &mesh), TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
    info.index_count = 3; /* not a multiple of 4 for quads */
    EXPECT(ctx, translucid_mesh_create(ctx, &info, &mesh), TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
    info = mesh_info();
    info.positions = NULL;
    EXPECT(ctx, translucid_mesh_create(ctx, &info, &mesh), TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    info = mesh_info();
    info.indices = NULL;
    EXPECT(ctx, translucid_mesh_create(ctx, &info, &mesh), TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    info = mesh_info();
    info.indices = bad_quad;
    EXPECT(ctx, translucid_mesh_create(ctx, &info, &mesh),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "vertex 4") != NULL);
    info = mesh_info();
    memcpy(nan_positions, k_positions, sizeof nan_positions);
    nan_positions[4] = (float)NAN;
    info.positions = nan_positions;
    EXPECT(ctx, translucid_mesh_create(ctx, &info, &mesh),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "not finite") != NULL);
    nan_positions[4] = (float)INFINITY;
    EXPECT(ctx, translucid_mesh_create(ctx, &info, &mesh),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    info = mesh_info();
    memset(nan_normals, 0, sizeof nan_normals);
    nan_normals[0] = (float)NAN;
    info.normals = nan_normals;
    EXPECT(ctx, translucid_mesh_create(ctx, &info, &mesh),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    info = mesh_info();
    info.name = "\xc3\x28";
    EXPECT(ctx, translucid_mesh_create(ctx, &info, &mesh),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    TRUE_OR_FAIL(mesh.id == sentinel.id); /* never written on failure */

    info = mesh_info();
    EXPECT(ctx, translucid_mesh_create(ctx, &info, &mesh), TRANSLUCID_RESULT_SUCCESS);
    TRUE_OR_FAIL(mesh.id != 0 && mesh.id != sentinel.id);
    EXPECT(ctx, translucid_mesh_destroy(ctx, mesh), TRANSLUCID_RESULT_SUCCESS);
    EXPECT(ctx, translucid_mesh_destroy(ctx, mesh), TRANSLUCID_RESULT_ERROR_STALE_HANDLE);
    EXPECT(ctx, translucid_mesh_destroy(ctx, sentinel), TRANSLUCID_RESULT_ERROR_INVALID_HANDLE);
    {
        const translucid_mesh null_mesh = {0};
        EXPECT(ctx, translucid_mesh_destroy(ctx, null_mesh), TRANSLUCID_RESULT_ERROR_INVALID_HANDLE);
    }
}

static void textures_and_materials(translucid_context *ctx, translucid_context *other) {
    uint8_t texels[4 * 4 * 4];
    translucid_texture_create_info tinfo;
    translucid_texture texture, foreign_texture, sampled;
    translucid_sampler_info sinfo;
    translucid_material_create_info minfo = material_info();
    translucid_material material = {7};
    translucid_mesh mesh;
    translucid_mesh_create_info mesh_desc = mesh_info();

    memset(texels, 200, sizeof texels);
    memset(&tinfo, 0, sizeof tinfo);
    tinfo.s_type = TRANSLUCID_STRUCTURE_TYPE_TEXTURE_CREATE_INFO;
    tinfo.texels = texels;
    EXPECT(ctx, translucid_texture_create(ctx, &tinfo, &texture),
           TRANSLUCID_RESULT_ERROR_INVALID_SIZE); /* 0 x 0 */
    tinfo.width = 100000;
    tinfo.height = 4;
    EXPECT(ctx, translucid_texture_create(ctx, &tinfo, &texture),
           TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
    tinfo.width = 4;
    tinfo.texels = NULL;
    EXPECT(ctx, translucid_texture_create(ctx, &tinfo, &texture),
           TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    tinfo.texels = texels;
    tinfo.flags = 0x10;
    EXPECT(ctx, translucid_texture_create(ctx, &tinfo, &texture),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    tinfo.flags = TRANSLUCID_TEXTURE_SRGB;
    EXPECT(ctx, translucid_texture_create(ctx, &tinfo, &texture), TRANSLUCID_RESULT_SUCCESS);
    EXPECT(other, translucid_texture_create(other, &tinfo, &foreign_texture),
           TRANSLUCID_RESULT_SUCCESS);

    /* A sampler chained to the texture: unknown values and foreign structures are refused. */
    memset(&sinfo, 0, sizeof sinfo);
    sinfo.s_type = TRANSLUCID_STRUCTURE_TYPE_SAMPLER_INFO;
    sinfo.wrap_s = TRANSLUCID_WRAP_MIRRORED_REPEAT;
    sinfo.wrap_t = TRANSLUCID_WRAP_CLAMP_TO_EDGE;
    sinfo.mag_filter = TRANSLUCID_FILTER_NEAREST;
    sinfo.mipmap_mode = TRANSLUCID_MIPMAP_MODE_NONE;
    tinfo.next = &sinfo;
    EXPECT(ctx, translucid_texture_create(ctx, &tinfo, &sampled), TRANSLUCID_RESULT_SUCCESS);
    EXPECT(ctx, translucid_texture_destroy(ctx, sampled), TRANSLUCID_RESULT_SUCCESS);
    sinfo.wrap_t = 3;
    EXPECT(ctx, translucid_texture_create(ctx, &tinfo, &sampled),
           TRANSLUCID_RESULT_ERROR_INVALID_ENUM);
    sinfo.wrap_t = TRANSLUCID_WRAP_REPEAT;
    sinfo.min_filter = 2;
    EXPECT(ctx, translucid_texture_create(ctx, &tinfo, &sampled),
           TRANSLUCID_RESULT_ERROR_INVALID_ENUM);
    sinfo.min_filter = TRANSLUCID_FILTER_LINEAR;
    sinfo.mipmap_mode = 3;
    EXPECT(ctx, translucid_texture_create(ctx, &tinfo, &sampled),
           TRANSLUCID_RESULT_ERROR_INVALID_ENUM);
    sinfo.mipmap_mode = TRANSLUCID_MIPMAP_MODE_LINEAR;
    sinfo.s_type = TRANSLUCID_STRUCTURE_TYPE_MESH_CREATE_INFO;
    EXPECT(ctx, translucid_texture_create(ctx, &tinfo, &sampled),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    sinfo.s_type = TRANSLUCID_STRUCTURE_TYPE_SAMPLER_INFO;
    sinfo.next = &sinfo;
    EXPECT(ctx, translucid_texture_create(ctx, &tinfo, &sampled),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    tinfo.next = NULL;

    minfo.base_colour[3] = 2.0f;
    EXPECT(ctx, translucid_material_create(ctx, &minfo, &material),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    minfo = material_info();
    minfo.base_colour[1] = (float)NAN;
    EXPECT(ctx, translucid_material_create(ctx, &minfo, &material),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    minfo = material_info();
    minfo.transmission = -1.0f;
    EXPECT(ctx, translucid_material_create(ctx, &minfo, &material),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    minfo = material_info();
    minfo.flags = 0x100;
    EXPECT(ctx, translucid_material_create(ctx, &minfo, &material),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    minfo = material_info();
    minfo.texture = foreign_texture;
    EXPECT(ctx, translucid_material_create(ctx, &minfo, &material),
           TRANSLUCID_RESULT_ERROR_FOREIGN_HANDLE);
    minfo.texture.id = 0x123456789abcull;
    EXPECT(ctx, translucid_material_create(ctx, &minfo, &material),
           TRANSLUCID_RESULT_ERROR_INVALID_HANDLE);
    EXPECT(ctx, translucid_mesh_create(ctx, &mesh_desc, &mesh), TRANSLUCID_RESULT_SUCCESS);
    minfo.texture.id = mesh.id; /* a mesh handle where a texture belongs */
    EXPECT(ctx, translucid_material_create(ctx, &minfo, &material),
           TRANSLUCID_RESULT_ERROR_INVALID_HANDLE);
    minfo.texture = texture;
    EXPECT(ctx, translucid_texture_destroy(ctx, texture), TRANSLUCID_RESULT_SUCCESS);
    EXPECT(ctx, translucid_material_create(ctx, &minfo, &material),
           TRANSLUCID_RESULT_ERROR_STALE_HANDLE);
    TRUE_OR_FAIL(material.id == 7);
    EXPECT(ctx, translucid_mesh_destroy(ctx, mesh), TRANSLUCID_RESULT_SUCCESS);
}

static void frames(translucid_context *ctx, translucid_context *other) {
    translucid_mesh_create_info mesh_desc = mesh_info();
    translucid_material_create_info material_desc = material_info();
    translucid_mesh mesh, stale_mesh, foreign_mesh;
    translucid_material material;
    translucid_draw draw;
    translucid_frame_info info;
    translucid_frame frame = {99};
    translucid_light light;
    translucid_opaque_layer layer;
    translucid_frame_statistics stats;
    float colour[8 * 8 * 4], depth[8 * 8];
    uint8_t pixels[8 * 8 * 4];
    size_t i, count = 0;
    uint32_t methods[16];
    translucid_exact_settings exact;
    translucid_wavelet_settings wavelet;
    translucid_linked_list_settings linked_list;
    translucid_depth_peeling_settings depth_peeling;
    translucid_base_in_structure not_settings;

    memset(&exact, 0, sizeof exact);
    exact.s_type = TRANSLUCID_STRUCTURE_TYPE_EXACT_SETTINGS;
    memset(&wavelet, 0, sizeof wavelet);
    wavelet.s_type = TRANSLUCID_STRUCTURE_TYPE_WAVELET_SETTINGS;
    memset(&linked_list, 0, sizeof linked_list);
    linked_list.s_type = TRANSLUCID_STRUCTURE_TYPE_LINKED_LIST_SETTINGS;
    memset(&depth_peeling, 0, sizeof depth_peeling);
    depth_peeling.s_type = TRANSLUCID_STRUCTURE_TYPE_DEPTH_PEELING_SETTINGS;
    memset(&not_settings, 0, sizeof not_settings);
    not_settings.s_type = TRANSLUCID_STRUCTURE_TYPE_OPAQUE_LAYER;
    EXPECT(ctx, translucid_mesh_create(ctx, &mesh_desc, &mesh), TRANSLUCID_RESULT_SUCCESS);
    EXPECT(ctx, translucid_mesh_create(ctx, &mesh_desc, &stale_mesh), TRANSLUCID_RESULT_SUCCESS);
    EXPECT(ctx, translucid_mesh_destroy(ctx, stale_mesh), TRANSLUCID_RESULT_SUCCESS);
    EXPECT(other, translucid_mesh_create(other, &mesh_desc, &foreign_mesh),
           TRANSLUCID_RESULT_SUCCESS);
    EXPECT(ctx, translucid_material_create(ctx, &material_desc, &material),
           TRANSLUCID_RESULT_SUCCESS);
    memset(&draw, 0, sizeof draw);
    draw.mesh = mesh;
    draw.material = material;
    draw.transform[0] = draw.transform[5] = draw.transform[10] = draw.transform[15] = 1.0f;

    info = frame_info(&draw);
    EXPECT(ctx, translucid_frame_render(ctx, NULL, &frame), TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    EXPECT(ctx, translucid_frame_render(ctx, &info, NULL), TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    memset(&info, 0, sizeof info);
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    info = frame_info(&draw);
    info.method = 99;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame), TRANSLUCID_RESULT_ERROR_INVALID_ENUM);
    EXPECT(NULL, translucid_method_get_available(methods, 16, &count), TRANSLUCID_RESULT_SUCCESS);
    for (info.method = TRANSLUCID_METHOD_BLEND; info.method <= TRANSLUCID_METHOD_DEPTH_PEELING;
         info.method++) {
        int available = 0;
        for (i = 0; i < count; i++) available |= methods[i] == info.method;
        if (!available) {
            EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
                   TRANSLUCID_RESULT_ERROR_METHOD_UNAVAILABLE);
        }
    }
    info = frame_info(&draw);
    info.method = TRANSLUCID_METHOD_LINKED_LIST;
    info.next = &linked_list;
    linked_list.node_budget = UINT32_MAX; /* past the nodes one texel view reaches */
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "budget") != NULL);
    info = frame_info(&draw);
    info.method = TRANSLUCID_METHOD_DEPTH_PEELING;
    info.next = &depth_peeling;
    depth_peeling.passes = 129;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "passes") != NULL);
    info = frame_info(&draw);
    info.method = TRANSLUCID_METHOD_WAVELET;
    info.next = &wavelet;
    wavelet.coefficients = 3;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    wavelet.coefficients = 32;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    wavelet.coefficients = 0;
    wavelet.noise = -1.0f;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    wavelet.noise = 0.0f;
    wavelet.storage = 2;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame), TRANSLUCID_RESULT_ERROR_INVALID_ENUM);
    wavelet.storage = TRANSLUCID_WAVELET_STORAGE_BINS;
    info = frame_info(&draw);
    info.method = TRANSLUCID_METHOD_EXACT;
    info.next = &exact;
    exact.threshold = -0.5f;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    exact.threshold = 1.5f;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    exact.threshold = (float)NAN;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    /* Another method's settings are checked too, and ignored otherwise. */
    exact.threshold = 0.0f;
    exact.next = &wavelet;
    wavelet.coefficients = 3;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    wavelet.coefficients = 0;
    /* Each structure once, and method settings only. */
    wavelet.next = &exact;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "two") != NULL);
    wavelet.next = &not_settings;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    wavelet.next = NULL;
    exact.next = NULL;
    info = frame_info(&draw);
    info.width = 0;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame), TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
    info.width = 1u << 20;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame), TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
    info = frame_info(&draw);
    info.draw_count = TRANSLUCID_MAX_DRAWS + 1;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame), TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
    info = frame_info(&draw);
    info.draws = NULL;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame), TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    info = frame_info(&draw);
    info.camera.fov_y = 0.0f;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    info = frame_info(&draw);
    info.camera.view[3] = (float)NAN;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    info = frame_info(&draw);
    memset(&light, 0, sizeof light);
    info.light = &light;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    info = frame_info(&draw);
    info.background[0] = -1.0f;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);

    info = frame_info(&draw);
    draw.mesh = stale_mesh;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame), TRANSLUCID_RESULT_ERROR_STALE_HANDLE);
    TRUE_OR_FAIL(strstr(translucid_context_get_last_error(ctx), "draws[0]") != NULL);
    draw.mesh = foreign_mesh;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_FOREIGN_HANDLE);
    draw.mesh.id = 0;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_HANDLE);
    draw.mesh = mesh;
    draw.material.id = mesh.id;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_HANDLE);
    draw.material = material;
    draw.layer = 5;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame), TRANSLUCID_RESULT_ERROR_INVALID_ENUM);
    draw.layer = TRANSLUCID_LAYER_TRANSPARENT;
    draw.transform[13] = (float)INFINITY;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    draw.transform[13] = 0.0f;

    /* The host's opaque layer. */
    for (i = 0; i < 64; i++) {
        colour[i * 4 + 0] = colour[i * 4 + 1] = colour[i * 4 + 2] = 0.5f;
        colour[i * 4 + 3] = 1.0f;
        depth[i] = 1.0f;
    }
    memset(&layer, 0, sizeof layer);
    info.opaque_layer = &layer;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    layer.s_type = TRANSLUCID_STRUCTURE_TYPE_OPAQUE_LAYER;
    layer.colour_format = TRANSLUCID_PIXEL_FORMAT_RGBA32F_LINEAR;
    layer.depth = depth;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame), TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    layer.colour = colour;
    layer.colour_format = 3;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame), TRANSLUCID_RESULT_ERROR_INVALID_ENUM);
    layer.colour_format = TRANSLUCID_PIXEL_FORMAT_RGBA32F_LINEAR;
    depth[5] = (float)NAN;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    depth[5] = 2.0f;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    depth[5] = 1.0f;
    draw.layer = TRANSLUCID_LAYER_OPAQUE;
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame),
           TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    draw.layer = TRANSLUCID_LAYER_TRANSPARENT;
    TRUE_OR_FAIL(frame.id == 99); /* never written on failure */
    EXPECT(ctx, translucid_frame_render(ctx, &info, &frame), TRANSLUCID_RESULT_SUCCESS);

    /* Reading frames back. */
    EXPECT(ctx, translucid_frame_read(ctx, frame, TRANSLUCID_PIXEL_FORMAT_RGBA8_SRGB, pixels,
                                      sizeof pixels - 1),
           TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
    EXPECT(ctx, translucid_frame_read(ctx, frame, TRANSLUCID_PIXEL_FORMAT_RGBA32F_LINEAR, pixels,
                                      sizeof pixels),
           TRANSLUCID_RESULT_ERROR_INVALID_SIZE);
    EXPECT(ctx, translucid_frame_read(ctx, frame, TRANSLUCID_PIXEL_FORMAT_RGBA8_SRGB, NULL,
                                      sizeof pixels),
           TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    EXPECT(ctx, translucid_frame_read(ctx, frame, 17, pixels, sizeof pixels),
           TRANSLUCID_RESULT_ERROR_INVALID_ENUM);
    EXPECT(ctx, translucid_frame_read(ctx, frame, TRANSLUCID_PIXEL_FORMAT_RGBA8_SRGB, pixels,
                                      sizeof pixels),
           TRANSLUCID_RESULT_SUCCESS);
    memset(&stats, 0, sizeof stats);
    EXPECT(ctx, translucid_frame_get_statistics(ctx, frame, &stats),
           TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE);
    EXPECT(ctx, translucid_frame_get_statistics(ctx, frame, NULL),
           TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    EXPECT(ctx, translucid_frame_write_png(ctx, frame, NULL), TRANSLUCID_RESULT_ERROR_NULL_POINTER);
    EXPECT(ctx, translucid_frame_write_png(ctx, frame, ""), TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT);
    EXPECT(ctx, translucid_frame_write_png(ctx, frame, "/dev/null/not-a-directory/x.png"),
           TRANSLUCID_RESULT_ERROR_IO);
    EXPECT(other, translucid_frame_destroy(other, frame), TRANSLUCID_RESULT_ERROR_FOREIGN_HANDLE);
    EXPECT(ctx, translucid_frame_destroy(ctx, frame), TRANSLUCID_RESULT_SUCCESS);
    EXPECT(ctx, translucid_frame_read(ctx, frame, TRANSLUCID_PIXEL_FORMAT_RGBA8_SRGB, pixels,
                                      sizeof pixels),
           TRANSLUCID_RESULT_ERROR_STALE_HANDLE);
    EXPECT(ctx, translucid_frame_destroy(ctx, frame), TRANSLUCID_RESULT_ERROR_STALE_HANDLE);
    EXPECT(ctx, translucid_material_destroy(ctx, material), TRANSLUCID_RESULT_SUCCESS);
    /* Objects left alive are freed with their context. */
}

int main(void) {
    translucid_context *ctx = NULL, *other = NULL;
    translucid_context_create_info info = context_info();

    context_creation();
    queries();
    if (translucid_context_create(&info, &ctx) < 0 ||
        translucid_context_create(&info, &other) < 0) {
        printf("FAIL: cannot create contexts: %s\n", translucid_context_get_last_error(NULL));
        return 1;
    }
    meshes(ctx);
    textures_and_materials(ctx, other);
    frames(ctx, other);
    translucid_context_destroy(other);
    translucid_context_destroy(ctx);
    printf("misuse: %d passed, %d failed\n", g_passed, g_failed);
    return g_failed == 0 ? 0 : 1;
}
