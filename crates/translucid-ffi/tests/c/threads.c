/*
 * Two threads calling into one context at once, which the API does not allow: the call that
 * finds the other inside is refused with TRANSLUCID_RESULT_ERROR_CONTEXT_BUSY and a message
 * naming the rule, does nothing, and the context stays whole. Then, with the calls taken in
 * turn, both threads' objects draw as they should.
 */
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include "red_quad.h"
#include "translucid.h"

/* Frames rendered by the first thread while the second one races it. */
#define FRAMES 40
#define SIDE 32

static int g_failed = 0;

static translucid_frame_info frame_info(translucid_draw *draw) {
    translucid_frame_info info;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
    info.method = TRANSLUCID_METHOD_EXACT;
    info.width = SIDE;
    info.height = SIDE;
    info.camera.view[0] = info.camera.view[5] = info.camera.view[10] = info.camera.view[15] = 1;
    info.camera.fov_y = 1.2f;
    info.camera.z_near = 0.1f;
    info.camera.z_far = 10.0f;
    info.draws = draw;
    info.draw_count = 1;
    return info;
}

/* What one thread saw. */
typedef struct racer {
    translucid_context *ctx;
    translucid_draw draw;
    int refused, done, wrong;
    /* Set by the first thread when its frames are rendered: the second one stops. */
    volatile int *stop;
} racer;

/* A refusal must name the rule, on the refused thread. */
static void check_refusal(racer *r) {
    const char *message = translucid_context_get_last_error(r->ctx);
    r->refused++;
    if (strstr(message, "another thread is in a call on this context") == NULL) {
        printf("FAIL: a refusal's message does not name the rule: %s\n", message);
        r->wrong++;
    }
}

/* Renders frames (long calls), counting refusals and anything else that is not success. */
static void *render_frames(void *arg) {
    racer *r = arg;
    translucid_frame_info info = frame_info(&r->draw);
    int k;
    for (k = 0; k < FRAMES; k++) {
        translucid_frame frame;
        translucid_result got = translucid_frame_render(r->ctx, &info, &frame);
        if (got == TRANSLUCID_RESULT_ERROR_CONTEXT_BUSY) {
            check_refusal(r);
            continue;
        }
        if (got != TRANSLUCID_RESULT_SUCCESS) {
            printf("FAIL: render returned %s: %s\n", translucid_result_string(got),
                   translucid_context_get_last_error(r->ctx));
            r->wrong++;
            continue;
        }
        r->done++;
        /* Retried until the other thread lets it in: a handle is never leaked. */
        while ((got = translucid_frame_destroy(r->ctx, frame)) ==
               TRANSLUCID_RESULT_ERROR_CONTEXT_BUSY) {
            check_refusal(r);
        }
        if (got != TRANSLUCID_RESULT_SUCCESS) r->wrong++;
    }
    *r->stop = 1;
    return NULL;
}

/* Creates and destroys materials (short calls) until the frames are done. */
static void *churn_materials(void *arg) {
    racer *r = arg;
    translucid_material_create_info info = material_info();
    while (!*r->stop) {
        translucid_material material;
        translucid_result got = translucid_material_create(r->ctx, &info, &material);
        if (got == TRANSLUCID_RESULT_ERROR_CONTEXT_BUSY) {
            check_refusal(r);
            continue;
        }
        if (got != TRANSLUCID_RESULT_SUCCESS) {
            r->wrong++;
            continue;
        }
        r->done++;
        while ((got = translucid_material_destroy(r->ctx, material)) ==
               TRANSLUCID_RESULT_ERROR_CONTEXT_BUSY) {
            check_refusal(r);
        }
        if (got != TRANSLUCID_RESULT_SUCCESS) r->wrong++;
    }
    return NULL;
}

int main(void) {
    translucid_context_create_info info;
    translucid_context *ctx = NULL;
    translucid_mesh_create_info mesh = mesh_info();
    translucid_material_create_info material = material_info();
    translucid_draw draw;
    translucid_frame frame;
    translucid_frame_info frame_of;
    racer renderer, churner;
    volatile int stop = 0;
    pthread_t threads[2];
    uint8_t pixels[SIDE * SIDE * 4];

    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_CONTEXT_CREATE_INFO;
    info.header_version = TRANSLUCID_HEADER_VERSION;
    if (translucid_context_create(&info, &ctx) < 0) {
        printf("FAIL: cannot create a context: %s\n", translucid_context_get_last_error(NULL));
        return 1;
    }
    memset(&draw, 0, sizeof draw);
    if (translucid_mesh_create(ctx, &mesh, &draw.mesh) < 0 ||
        translucid_material_create(ctx, &material, &draw.material) < 0) {
        printf("FAIL: %s\n", translucid_context_get_last_error(ctx));
        return 1;
    }
    draw.layer = TRANSLUCID_LAYER_TRANSPARENT;
    draw.transform[0] = draw.transform[5] = draw.transform[10] = draw.transform[15] = 1;
    draw.tint[0] = draw.tint[1] = draw.tint[2] = draw.tint[3] = 1;

    memset(&renderer, 0, sizeof renderer);
    renderer.ctx = ctx;
    renderer.draw = draw;
    renderer.stop = &stop;
    churner = renderer;
    pthread_create(&threads[0], NULL, render_frames, &renderer);
    pthread_create(&threads[1], NULL, churn_materials, &churner);
    pthread_join(threads[0], NULL);
    pthread_join(threads[1], NULL);
    printf("threads: %d frames and %d refusals on one thread, %d materials and %d refusals on "
           "the other\n",
           renderer.done, renderer.refused, churner.done, churner.refused);
    if (renderer.wrong || churner.wrong) g_failed++;
    /* Two cores or one, the threads overlapped: some call found the other inside. */
    if (renderer.refused + churner.refused == 0) {
        printf("FAIL: no call was refused, yet the threads overlapped for %d frames\n", FRAMES);
        g_failed++;
    }

    /* The context is whole: a frame draws the red quad over the background. */
    frame_of = frame_info(&draw);
    if (translucid_frame_render(ctx, &frame_of, &frame) < 0 ||
        translucid_frame_read(ctx, frame, TRANSLUCID_PIXEL_FORMAT_RGBA8_SRGB, pixels,
                              sizeof pixels) < 0) {
        printf("FAIL: after the race: %s\n", translucid_context_get_last_error(ctx));
        g_failed++;
    } else {
        const uint8_t *centre = pixels + ((SIDE / 2) * SIDE + SIDE / 2) * 4;
        if (centre[0] <= centre[1] || centre[0] <= centre[2]) {
            printf("FAIL: the centre is not the red quad: %u %u %u\n", centre[0], centre[1],
                   centre[2]);
            g_failed++;
        }
        if (translucid_frame_destroy(ctx, frame) < 0) g_failed++;
    }
    translucid_context_destroy(ctx);
    printf("threads: %s\n", g_failed == 0 ? "passed" : "FAILED");
    return g_failed == 0 ? 0 : 1;
}
