/*
 * translucid from C: build a small scene procedurally, render it with every method this
 * build has, write one PNG per method and print what each frame cost.
 *
 *   example [OUTPUT_DIR]      (default: out)
 *
 * Every call's result is checked: on an error the program prints the code's name and the
 * context's message, and exits with status 1.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "translucid.h"

#define WIDTH 320
#define HEIGHT 240

static translucid_context *g_context = NULL;

/* Stops the program with a readable message when a call fails. */
static void check(translucid_result result, const char *call) {
    if (result < 0) {
        fprintf(stderr, "%s failed: %s (%d)\n  %s\n", call, translucid_result_string(result),
                (int)result, translucid_context_get_last_error(g_context));
        translucid_context_destroy(g_context);
        exit(1);
    }
}
#define CHECK(call) check((call), #call)

/* A column-major world-to-view matrix looking from eye at target, +Y up. */
static void look_at(const float eye[3], const float target[3], float view[16]) {
    float f[3], s[3], u[3], len;
    int i;
    for (i = 0; i < 3; i++) f[i] = target[i] - eye[i];
    len = sqrtf(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (i = 0; i < 3; i++) f[i] /= len;
    /* s = f x up, with up = (0, 1, 0) */
    s[0] = -f[2];
    s[1] = 0.0f;
    s[2] = f[0];
    len = sqrtf(s[0] * s[0] + s[2] * s[2]);
    s[0] /= len;
    s[2] /= len;
    u[0] = s[1] * f[2] - s[2] * f[1];
    u[1] = s[2] * f[0] - s[0] * f[2];
    u[2] = s[0] * f[1] - s[1] * f[0];
    memset(view, 0, 16 * sizeof(float));
    for (i = 0; i < 3; i++) {
        view[i * 4 + 0] = s[i];
        view[i * 4 + 1] = u[i];
        view[i * 4 + 2] = -f[i];
    }
    view[12] = -(s[0] * eye[0] + s[1] * eye[1] + s[2] * eye[2]);
    view[13] = -(u[0] * eye[0] + u[1] * eye[1] + u[2] * eye[2]);
    view[14] = f[0] * eye[0] + f[1] * eye[1] + f[2] * eye[2];
    view[15] = 1.0f;
}

/* A column-major transform: rotation about Y by `angle`, then translation. */
static void transform(float angle, float x, float y, float z, float m[16]) {
    memset(m, 0, 16 * sizeof(float));
    m[0] = cosf(angle);
    m[2] = -sinf(angle);
    m[5] = 1.0f;
    m[8] = sinf(angle);
    m[10] = cosf(angle);
    m[12] = x;
    m[13] = y;
    m[14] = z;
    m[15] = 1.0f;
}

/* A unit square in the XY plane, as one quad with UVs and normals. */
static translucid_mesh make_square(void) {
    static const float positions[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    static const float normals[] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    static const float uvs[] = {0, 1, 1, 1, 1, 0, 0, 0};
    static const uint32_t quad[] = {0, 1, 2, 3};
    translucid_mesh_create_info info;
    translucid_mesh mesh;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_MESH_CREATE_INFO;
    info.primitive = TRANSLUCID_PRIMITIVE_QUADS;
    info.vertex_count = 4;
    info.positions = positions;
    info.normals = normals;
    info.uvs = uvs;
    info.index_count = 4;
    info.indices = quad;
    info.name = "square";
    CHECK(translucid_mesh_create(g_context, &info, &mesh));
    return mesh;
}

/* An octahedron from triangles, with a colour per vertex. */
static translucid_mesh make_octahedron(void) {
    static const float positions[] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    static const float colours[] = {1, 0.2f, 0.2f, 1, 0.2f, 1, 0.2f, 1, 0.2f, 0.2f, 1, 1,
                                    1, 1, 0.2f, 1, 0.2f, 1, 1, 1, 1, 0.2f, 1, 1};
    static const uint32_t triangles[] = {0, 2, 4, 4, 2, 1, 1, 2, 5, 5, 2, 0,
                                         4, 3, 0, 1, 3, 4, 5, 3, 1, 0, 3, 5};
    translucid_mesh_create_info info;
    translucid_mesh mesh;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_MESH_CREATE_INFO;
    info.primitive = TRANSLUCID_PRIMITIVE_TRIANGLES;
    info.vertex_count = 6;
    info.positions = positions;
    info.normals = positions; /* unit vertices: each is its own normal */
    info.colours = colours;
    info.index_count = 24;
    info.indices = triangles;
    info.name = "octahedron";
    CHECK(translucid_mesh_create(g_context, &info, &mesh));
    return mesh;
}

/* An 8x8 sRGB checkerboard. */
static translucid_texture make_checker(void) {
    uint8_t texels[8 * 8 * 4];
    translucid_texture_create_info info;
    translucid_texture texture;
    int x, y;
    for (y = 0; y < 8; y++) {
        for (x = 0; x < 8; x++) {
            uint8_t v = ((x + y) % 2) ? 255 : 60;
            uint8_t *t = &texels[(y * 8 + x) * 4];
            t[0] = v;
            t[1] = v;
            t[2] = v;
            t[3] = 255;
        }
    }
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_TEXTURE_CREATE_INFO;
    info.width = 8;
    info.height = 8;
    info.flags = TRANSLUCID_TEXTURE_SRGB;
    info.texels = texels;
    info.name = "checker";
    CHECK(translucid_texture_create(g_context, &info, &texture));
    return texture;
}

static translucid_material make_material(float r, float g, float b, float a, uint32_t flags,
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
    info.flags = flags;
    CHECK(translucid_material_create(g_context, &info, &material));
    return material;
}

int main(int argc, char **argv) {
    const char *out_dir = argc > 1 ? argv[1] : "out";
    const translucid_texture no_texture = {0};
    translucid_context_create_info context_info;
    translucid_mesh square, octahedron;
    translucid_texture checker;
    translucid_material wall, glass[3], gem;
    translucid_draw draws[5];
    translucid_frame_info frame_info;
    translucid_exact_settings exact_settings;
    translucid_wavelet_settings wavelet_settings;
    uint32_t methods[8];
    size_t method_count = 0, m;
    const float eye[3] = {1.5f, 2.0f, 5.0f}, target[3] = {0.0f, 0.0f, 0.0f};
    int i;

    memset(&context_info, 0, sizeof context_info);
    context_info.s_type = TRANSLUCID_STRUCTURE_TYPE_CONTEXT_CREATE_INFO;
    context_info.header_version = TRANSLUCID_HEADER_VERSION;
    context_info.mode = TRANSLUCID_CONTEXT_MODE_STANDALONE;
    CHECK(translucid_context_create(&context_info, &g_context));
    printf("translucid %s on %s\n", translucid_version_string(),
           translucid_context_get_device_name(g_context));

    square = make_square();
    octahedron = make_octahedron();
    checker = make_checker();
    wall = make_material(0.8f, 0.8f, 0.8f, 1.0f, TRANSLUCID_MATERIAL_LIT, checker);
    glass[0] = make_material(1.0f, 0.1f, 0.1f, 0.5f, 0, no_texture);
    glass[1] = make_material(0.1f, 1.0f, 0.1f, 0.5f, 0, no_texture);
    glass[2] = make_material(0.1f, 0.1f, 1.0f, 0.5f, 0, no_texture);
    gem = make_material(1.0f, 1.0f, 1.0f, 0.6f, TRANSLUCID_MATERIAL_LIT, no_texture);

    /* An opaque checkered wall, three interpenetrating coloured panes, a glass gem. */
    memset(draws, 0, sizeof draws);
    draws[0].mesh = square;
    draws[0].material = wall;
    draws[0].layer = TRANSLUCID_LAYER_OPAQUE;
    transform(0.0f, 0.0f, 0.0f, -1.5f, draws[0].transform);
    draws[0].transform[0] = draws[0].transform[5] = 3.0f;
    for (i = 0; i < 3; i++) {
        draws[1 + i].mesh = square;
        draws[1 + i].material = glass[i];
        draws[1 + i].layer = TRANSLUCID_LAYER_TRANSPARENT;
        transform(-0.9f + 0.9f * (float)i, -0.4f + 0.4f * (float)i, 0.0f, 0.0f,
                  draws[1 + i].transform);
    }
    draws[4].mesh = octahedron;
    draws[4].material = gem;
    draws[4].layer = TRANSLUCID_LAYER_TRANSPARENT;
    transform(0.5f, 0.3f, 0.2f, 0.6f, draws[4].transform);

    memset(&frame_info, 0, sizeof frame_info);
    frame_info.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
    frame_info.width = WIDTH;
    frame_info.height = HEIGHT;
    look_at(eye, target, frame_info.camera.view);
    frame_info.camera.fov_y = 0.8f;
    frame_info.camera.z_near = 0.1f;
    frame_info.camera.z_far = 50.0f;
    frame_info.draws = draws;
    frame_info.draw_count = 5;
    frame_info.background[0] = 0.05f;
    frame_info.background[1] = 0.05f;
    frame_info.background[2] = 0.08f;
    memset(&exact_settings, 0, sizeof exact_settings);
    exact_settings.s_type = TRANSLUCID_STRUCTURE_TYPE_EXACT_SETTINGS;
    exact_settings.next = &wavelet_settings;
    memset(&wavelet_settings, 0, sizeof wavelet_settings);
    wavelet_settings.s_type = TRANSLUCID_STRUCTURE_TYPE_WAVELET_SETTINGS;
    wavelet_settings.storage = TRANSLUCID_WAVELET_STORAGE_BINS;

    CHECK(translucid_method_get_available(methods, sizeof methods / sizeof methods[0],
                                       &method_count));
    for (m = 0; m < method_count; m++) {
        const char *name = translucid_method_name(methods[m]);
        translucid_frame frame;
        translucid_frame_statistics stats;
        char path[1024];
        uint32_t s;

        frame_info.method = methods[m];
        /* Method settings are chained to the frame info, a structure per method, and each
           field's zero is its default (wavelet: 16 coefficients per channel, kept in the exact
           method's bins; exact: no threshold, every fragment composited). One chain serves
           every method: each reads its own. */
        frame_info.next = &exact_settings;
        CHECK(translucid_frame_render(g_context, &frame_info, &frame));
        snprintf(path, sizeof path, "%s/example-%s.png", out_dir, name);
        CHECK(translucid_frame_write_png(g_context, frame, path));

        memset(&stats, 0, sizeof stats);
        stats.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS;
        CHECK(translucid_frame_get_statistics(g_context, frame, &stats));
        printf("%-8s %s: %.3f ms on the GPU (method %.3f ms), peak %.1f MiB\n", name, path,
               stats.gpu_milliseconds, stats.method_milliseconds,
               (double)stats.peak_gpu_bytes / (1024.0 * 1024.0));
        for (s = 0; s < stats.stage_count; s++) {
            printf("           %-16s %8.3f ms\n", stats.stages[s].name,
                   stats.stages[s].milliseconds);
        }
        CHECK(translucid_frame_destroy(g_context, frame));
    }

    CHECK(translucid_material_destroy(g_context, gem));
    CHECK(translucid_mesh_destroy(g_context, octahedron));
    translucid_context_destroy(g_context);
    return 0;
}
