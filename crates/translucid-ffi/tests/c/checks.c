/* The host-device tests' checks and shared scenes over the example engine: see checks.h. */
#include "checks.h"

int g_failed = 0, g_passed = 0;

void check(translucid_context *ctx, translucid_result got, translucid_result want,
           const char *call, int line) {
    if (got != want) {
        printf("FAIL line %d: %s returned %s (%d), expected %s: %s\n", line, call,
               translucid_result_string(got), got, translucid_result_string(want),
               translucid_context_get_last_error(ctx));
        g_failed++;
        if (want == TRANSLUCID_RESULT_SUCCESS) exit(1);
    } else {
        g_passed++;
    }
}

void create_engine(const translucid_host_requirements *req) {
    create_instance(req->api_version);
    /* The engine refuses a device older than req->api_version or without a feature asked
     * for. */
    create_device(req);
    TRUE_OR_FAIL(g_features.shaderInt64 == VK_TRUE);
    TRUE_OR_FAIL(g_features.dualSrcBlend == VK_TRUE);
}

const float g_test_quads[TEST_QUADS][12] = {
    {-1.2f, -0.9f, -2.0f, 0.4f, -0.9f, -2.0f, 0.4f, 0.6f, -2.0f, -1.2f, 0.6f, -2.0f},
    {-0.6f, -0.5f, -3.0f, 1.4f, -0.5f, -3.0f, 1.4f, 1.0f, -3.0f, -0.6f, 1.0f, -3.0f},
    {-1.5f, -0.2f, -1.6f, 1.5f, -0.2f, -3.6f, 1.5f, 0.3f, -3.6f, -1.5f, 0.3f, -1.6f},
    {-0.3f, -1.0f, -2.5f, 0.3f, -1.0f, -2.5f, 0.3f, 1.0f, -2.5f, -0.3f, 1.0f, -2.5f},
};

void make_quad(translucid_context *ctx, size_t i, uint32_t material_flags,
               translucid_mesh *mesh, translucid_material *material, translucid_draw *draw) {
    static const float colours[TEST_QUADS][4] = {{1.0f, 0.1f, 0.1f, 0.5f},
                                                 {0.1f, 0.3f, 1.0f, 0.7f},
                                                 {0.2f, 1.0f, 0.3f, 0.6f},
                                                 {1.0f, 1.0f, 0.2f, 0.4f}};
    static const uint32_t triangles[] = {0, 1, 2, 0, 2, 3};
    translucid_mesh_create_info mesh_info;
    translucid_material_create_info material_info;
    memset(&mesh_info, 0, sizeof mesh_info);
    mesh_info.s_type = TRANSLUCID_STRUCTURE_TYPE_MESH_CREATE_INFO;
    mesh_info.primitive = TRANSLUCID_PRIMITIVE_TRIANGLES;
    mesh_info.vertex_count = 4;
    mesh_info.positions = g_test_quads[i];
    mesh_info.index_count = 6;
    mesh_info.indices = triangles;
    CHECK(ctx, translucid_mesh_create(ctx, &mesh_info, mesh));
    memset(&material_info, 0, sizeof material_info);
    material_info.s_type = TRANSLUCID_STRUCTURE_TYPE_MATERIAL_CREATE_INFO;
    memcpy(material_info.base_colour, colours[i], sizeof colours[i]);
    material_info.flags = material_flags;
    CHECK(ctx, translucid_material_create(ctx, &material_info, material));
    memset(draw, 0, sizeof *draw);
    draw->mesh = *mesh;
    draw->material = *material;
    draw->layer = TRANSLUCID_LAYER_TRANSPARENT;
    draw->transform[0] = draw->transform[5] = draw->transform[10] = draw->transform[15] = 1.0f;
}

void render_standalone(translucid_context *ctx, translucid_frame_info info, const uint8_t *colour,
                       const float *depth, uint8_t *out, size_t size) {
    translucid_opaque_layer layer;
    translucid_frame frame;
    memset(&layer, 0, sizeof layer);
    layer.s_type = TRANSLUCID_STRUCTURE_TYPE_OPAQUE_LAYER;
    layer.colour_format = TRANSLUCID_PIXEL_FORMAT_RGBA8_SRGB;
    layer.colour = colour;
    layer.depth = depth;
    info.opaque_layer = &layer;
    CHECK(ctx, translucid_frame_render(ctx, &info, &frame));
    CHECK(ctx, translucid_frame_read(ctx, frame, TRANSLUCID_PIXEL_FORMAT_RGBA8_SRGB, out, size));
    CHECK(ctx, translucid_frame_destroy(ctx, frame));
}

void fill_opaque_layer(uint8_t *colour, float *depth, size_t width, size_t height,
                       const float bands[3]) {
    size_t x, y;
    for (y = 0; y < height; y++) {
        for (x = 0; x < width; x++) {
            size_t i = y * width + x;
            colour[i * 4 + 0] = (uint8_t)(40 + 3 * x);
            colour[i * 4 + 1] = (uint8_t)(200 - 3 * y);
            colour[i * 4 + 2] = 90;
            colour[i * 4 + 3] = 255;
            depth[i] = x < width / 4 ? bands[0] : x < width / 2 ? bands[1] : bands[2];
        }
    }
}
