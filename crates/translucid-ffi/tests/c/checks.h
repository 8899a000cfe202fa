/*
 * What the C API's host-device tests add to the example engine (examples-c/engine.h): the
 * checks and their counts, the engine made with translucid's requirements checked, and the
 * scenes and opaque layers the tests share. Any validation error counts as a failure.
 */
#ifndef TRANSLUCID_TEST_CHECKS_H
#define TRANSLUCID_TEST_CHECKS_H

#include "engine.h"

#ifdef __cplusplus
extern "C" {
#endif

extern int g_failed, g_passed;

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

/* The engine's instance and device, made with `req` (create_instance, create_device), and
 * the checks that `req` asks for what translucid's shaders need of the device. */
void create_engine(const translucid_host_requirements *req);

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
