/*
 * The C API fuzzer: random sequences of calls over create, render, read and destroy, with
 * random arguments, on standalone contexts (or an engine's device, below). Built with
 * AddressSanitizer and UBSan (see the
 * README, "Fuzzing"), so that memory errors on either side of the API end the run.
 *
 *   fuzz_calls [--seed S] [--first N] [--cases N | --seconds T] [--calls K] [--threads N]
 *              [--host-device]
 *
 * Case N of seed S is built from (S, N) alone: fresh contexts, K calls, everything
 * destroyed. Most calls carry one deliberate fault (a NULL pointer, a bad structure type,
 * an out-of-range enum or size, a non-finite value, a stale, foreign or never-issued
 * handle) and must return that fault's documented code; some are sound and must succeed;
 * some have several fields scrambled at once and may return any documented code. Every
 * call must leave a message when it fails, leave its out-parameter alone, and never panic.
 * A broken contract prints the case and exits 1; `--first N --cases 1` replays case N.
 *
 * With `--threads N`, N threads run cases at once (thread t takes cases first + t,
 * first + t + N, ...), each on contexts of its own, as an engine with a context per thread
 * would: what one thread does must not reach another's contexts, errors or objects. A case
 * replays alone with the same result, since each is built from (S, N) alone.
 *
 * With `--host-device`, every context is made on an engine's device (fuzz_host.c: one
 * device with every method's features, shared by the threads), and frames are recorded
 * into the engine's command buffer over colour and depth images of random formats, sizes
 * and layouts, submitted, waited for and completed: each must complete (or ask to be
 * recorded again), and a float colour image must come back finite. Validation errors end
 * the run.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "fuzz_host.h"
#include "translucid.h"

/* Whether contexts are made on the engine's device (--host-device). */
static int g_host_mode;

/* Seconds a case may take before SIGALRM ends the run as a hang. */
#define CASE_TIMEOUT 120
#define MAX_OBJECTS 12
#define MAX_VERTICES 48
#define MAX_SIDE 40

/* ---- random numbers: splitmix64, one stream per (seed, case) ---- */

/* Per thread: each case runs on one thread, from its own stream. */
static _Thread_local uint64_t g_state;

static uint64_t next_u64(void) {
    uint64_t z = (g_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Uniform in [0, n). */
static uint32_t below(uint32_t n) { return (uint32_t)(next_u64() % n); }
static int chance(uint32_t percent) { return below(100) < percent; }
static float unit(void) { return (float)(next_u64() >> 40) / (float)(1 << 24); }

/* A float that is usually ordinary and sometimes extreme. */
static float any_float(void) {
    switch (below(12)) {
    case 0: return NAN;
    case 1: return INFINITY;
    case 2: return -INFINITY;
    case 3: return 1e30f;
    case 4: return -1.0f;
    case 5: return 0.0f;
    default: return unit() * 4.0f - 2.0f;
    }
}

/* A frame or texture side: often the smallest, where buffers are padded and blocks cut. */
static uint32_t side(void) { return chance(20) ? 1 + below(3) : 1 + below(MAX_SIDE); }

static uint32_t any_u32(void) {
    switch (below(6)) {
    case 0: return 0;
    case 1: return 0xFFFFFFFFu;
    case 2: return 1u << below(32);
    default: return below(70000);
    }
}

/* ---- the contract every call keeps ---- */

static _Thread_local uint64_t g_seed, g_case;
static _Thread_local unsigned long g_calls;

static void broken(const char *call, int line, const char *what, translucid_result got,
                   const translucid_context *ctx) {
    const char *message = translucid_context_get_last_error(ctx);
    fprintf(stderr,
            "CONTRACT BROKEN in case %llu of seed %llu (call %lu, line %d): %s\n  %s\n"
            "  returned %s (%d); last error: %s\n  replay: fuzz_calls --seed %llu --first %llu "
            "--cases 1\n",
            (unsigned long long)g_case, (unsigned long long)g_seed, g_calls, line, call, what,
            translucid_result_string(got), (int)got, message ? message : "(NULL)",
            (unsigned long long)g_seed, (unsigned long long)g_case);
    /* Not exit(): the contexts still alive are no leak worth a report. */
    _exit(1);
}

static int known_code(translucid_result code) {
    return strcmp(translucid_result_string(code), "unknown result code") != 0;
}

/* Any sound answer: a documented code, never a panic, a message when it failed. */
static void check_sound(translucid_result got, const translucid_context *ctx, const char *call,
                        int line) {
    g_calls++;
    if (!known_code(got)) {
        broken(call, line, "an undocumented result code", got, ctx);
    }
    if (got == TRANSLUCID_RESULT_ERROR_PANIC || got == TRANSLUCID_RESULT_ERROR_CONTEXT_POISONED) {
        broken(call, line, "the library panicked", got, ctx);
    }
    const char *message = translucid_context_get_last_error(ctx);
    if (message == NULL) {
        broken(call, line, "last_error returned NULL", got, ctx);
    }
    if (got < 0 && message[0] == '\0') {
        broken(call, line, "failed without a message", got, ctx);
    }
}

/* `want` exactly, or (want == ANY) any sound answer. */
#define ANY 0x7FFFFFFF
static void check(translucid_result got, int want, const translucid_context *ctx,
                  const char *call, int line) {
    check_sound(got, ctx, call, line);
    if (want != ANY && got != want) {
        char what[128];
        snprintf(what, sizeof what, "expected %s (%d)", translucid_result_string(want), want);
        broken(call, line, what, got, ctx);
    }
}
#define CHECK(ctx, call, want) check((call), (want), (ctx), #call, __LINE__)

/* An out-parameter a failed call must not touch. */
#define UNTOUCHED 0x5EED5EED5EED5EEDull
/* The first method value no version defines yet. */
#define METHOD_END (TRANSLUCID_METHOD_DEPTH_PEELING + 1)

static void check_out(translucid_result got, uint64_t out, const translucid_context *ctx,
                      const char *call, int line) {
    if (got >= 0 && (out == UNTOUCHED || out == 0)) {
        broken(call, line, "succeeded without writing its handle", got, ctx);
    }
    if (got < 0 && out != UNTOUCHED) {
        broken(call, line, "failed but wrote its out-parameter", got, ctx);
    }
}

/* ---- objects a case has made: live or destroyed ---- */

typedef struct {
    uint64_t id;
    int live;
    /* Meshes: their vertex count. */
    uint32_t vertices;
} object;

typedef struct {
    object items[MAX_OBJECTS];
    int count;
} objects;

/* The object remembered, or NULL when the list is full. */
static object *remember(objects *list, uint64_t id) {
    if (list->count >= MAX_OBJECTS) {
        return NULL;
    }
    object *o = &list->items[list->count++];
    o->id = id;
    o->live = 1;
    o->vertices = 0;
    return o;
}

/* A random remembered object (NULL if none). */
static object *pick(objects *list) {
    return list->count ? &list->items[below((uint32_t)list->count)] : NULL;
}

/* A random live object (NULL if none). */
static object *pick_live(objects *list) {
    int live = 0;
    for (int i = 0; i < list->count; i++) {
        live += list->items[i].live;
    }
    if (live == 0) {
        return NULL;
    }
    int n = (int)below((uint32_t)live);
    for (int i = 0; i < list->count; i++) {
        if (list->items[i].live && n-- == 0) {
            return &list->items[i];
        }
    }
    return NULL;
}

typedef struct {
    translucid_context *ctx;
    /* A second context, for foreign handles (made on first use). */
    translucid_context *other;
    uint64_t other_mesh, other_texture, other_material;
    objects meshes, textures, materials, frames;
    uint32_t methods[8];
    size_t method_count;
    /* The largest frame index of a frame made so far. */
    uint64_t frame_index;
} state;

/* Handle faults: which handle a call gets instead of a live one, and what it must answer. */
enum handle_fault { HANDLE_LIVE, HANDLE_STALE, HANDLE_FOREIGN, HANDLE_NEVER, HANDLE_NULL };

static translucid_context *other_context(state *s);

/* A handle of `list` with fault `fault` (HANDLE_LIVE when `list` has a live one; the fault
 * is changed to what could be made), and the code a call given only it must return. */
static uint64_t handle_for(objects *list, uint64_t foreign, enum handle_fault *fault,
                           int *want) {
    object *o;
    switch (*fault) {
    case HANDLE_STALE:
        for (int i = 0; i < list->count; i++) {
            if (!list->items[i].live) {
                *want = TRANSLUCID_RESULT_ERROR_STALE_HANDLE;
                return list->items[i].id;
            }
        }
        break;
    case HANDLE_FOREIGN:
        if (foreign != 0) {
            *want = TRANSLUCID_RESULT_ERROR_FOREIGN_HANDLE;
            return foreign;
        }
        break;
    case HANDLE_NEVER:
        /* Slot index 2^24 - 1 of this kind is never issued in a case this short. */
        o = pick(list);
        if (o) {
            *want = TRANSLUCID_RESULT_ERROR_INVALID_HANDLE;
            return o->id | 0xFFFFFFull;
        }
        break;
    case HANDLE_NULL:
        *want = TRANSLUCID_RESULT_ERROR_INVALID_HANDLE;
        return 0;
    case HANDLE_LIVE:
        break;
    }
    o = pick_live(list);
    *fault = HANDLE_LIVE;
    *want = o ? TRANSLUCID_RESULT_SUCCESS : TRANSLUCID_RESULT_ERROR_INVALID_HANDLE;
    return o ? o->id : 0;
}

static enum handle_fault any_handle_fault(void) {
    return chance(60) ? HANDLE_LIVE : (enum handle_fault)(1 + below(4));
}

/* ---- the calls ---- */

static _Thread_local float g_positions[MAX_VERTICES * 3], g_normals[MAX_VERTICES * 3];
static _Thread_local float g_colours[MAX_VERTICES * 4], g_uvs[MAX_VERTICES * 2];
static _Thread_local uint32_t g_indices[MAX_VERTICES * 3];
static _Thread_local uint8_t g_texels[MAX_SIDE * MAX_SIDE * 4];

static void mesh_create(state *s) {
    translucid_mesh_create_info info;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_MESH_CREATE_INFO;
    info.primitive = below(2);
    info.vertex_count = 3 + below(MAX_VERTICES - 2);
    uint32_t per = info.primitive == TRANSLUCID_PRIMITIVE_QUADS ? 4 : 3;
    info.index_count = per * (1 + below(MAX_VERTICES * 3 / per - 1));
    for (uint32_t i = 0; i < info.vertex_count * 3; i++) {
        g_positions[i] = unit() * 2.0f - 1.0f;
        g_normals[i] = unit() - 0.5f;
    }
    for (uint32_t i = 0; i < info.vertex_count; i++) {
        g_positions[i * 3 + 2] -= 3.0f;
    }
    for (uint32_t i = 0; i < info.vertex_count * 4; i++) {
        g_colours[i] = unit();
    }
    for (uint32_t i = 0; i < info.vertex_count * 2; i++) {
        g_uvs[i] = unit() * 3.0f - 1.0f;
    }
    for (uint32_t i = 0; i < info.index_count; i++) {
        g_indices[i] = below(info.vertex_count);
    }
    info.positions = g_positions;
    info.indices = g_indices;
    info.normals = chance(50) ? g_normals : NULL;
    info.colours = chance(50) ? g_colours : NULL;
    info.uvs = chance(50) ? g_uvs : NULL;
    info.name = chance(50) ? "fuzzed mesh" : NULL;

    int want = TRANSLUCID_RESULT_SUCCESS;
    translucid_context *ctx = s->ctx;
    translucid_mesh mesh = {UNTOUCHED};
    translucid_mesh *out = &mesh;
    const translucid_mesh_create_info *pinfo = &info;
    switch (below(12)) {
    case 0: pinfo = NULL; want = TRANSLUCID_RESULT_ERROR_NULL_POINTER; break;
    case 1: out = NULL; want = TRANSLUCID_RESULT_ERROR_NULL_POINTER; break;
    case 2: info.s_type = any_u32() | 0x100; want = TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE; break;
    case 3: info.primitive = 2 + below(1000); want = TRANSLUCID_RESULT_ERROR_INVALID_ENUM; break;
    case 4: info.positions = NULL; want = TRANSLUCID_RESULT_ERROR_NULL_POINTER; break;
    case 5: g_positions[below(info.vertex_count * 3)] = chance(50) ? NAN : INFINITY;
            want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT; break;
    case 6: g_indices[below(info.index_count)] = info.vertex_count + below(5);
            want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT; break;
    case 7: info.index_count = chance(50) ? 0 : info.index_count - 1;
            want = TRANSLUCID_RESULT_ERROR_INVALID_SIZE; break;
    case 8: /* Scrambled: several fields at once, any sound answer. */
        info.primitive = chance(70) ? info.primitive : any_u32();
        info.vertex_count = chance(70) ? info.vertex_count : below(info.vertex_count + 1);
        info.index_count = chance(70) ? info.index_count : below(info.index_count + 1);
        if (chance(30)) g_positions[below(info.vertex_count * 3 + 1)] = any_float();
        if (chance(30)) g_indices[below(info.index_count + 1)] = any_u32();
        if (chance(30) && info.colours) g_colours[below(info.vertex_count * 4 + 1)] = any_float();
        if (chance(30) && info.uvs) g_uvs[below(info.vertex_count * 2 + 1)] = any_float();
        want = ANY;
        break;
    default: break;
    }
    translucid_result got = translucid_mesh_create(ctx, pinfo, out);
    check(got, want, ctx, "translucid_mesh_create", __LINE__);
    check_out(got, out ? mesh.id : UNTOUCHED, ctx, "translucid_mesh_create", __LINE__);
    if (got == TRANSLUCID_RESULT_SUCCESS && out) {
        object *o = remember(&s->meshes, mesh.id);
        if (o != NULL) {
            o->vertices = info.vertex_count;
        }
    }
}

/* A range of a mesh's vertices moved, or a bad range, pointer, value or handle. */
static void mesh_update(state *s) {
    object *o = pick_live(&s->meshes);
    if (o == NULL) {
        return;
    }
    uint32_t first = below(o->vertices), count = 1 + below(o->vertices - first);
    for (uint32_t i = 0; i < count * 3; i++) {
        g_positions[i] = unit() * 2.0f - 1.0f - (i % 3 == 2 ? 3.0f : 0.0f);
    }
    const float *positions = g_positions;
    translucid_mesh mesh = {o->id};
    int want = TRANSLUCID_RESULT_SUCCESS;
    switch (below(8)) {
    case 0: count = 0; want = TRANSLUCID_RESULT_ERROR_INVALID_SIZE; break;
    case 1: first = o->vertices - count + 1 + below(5); want = TRANSLUCID_RESULT_ERROR_INVALID_SIZE;
            break;
    case 2: positions = NULL; want = TRANSLUCID_RESULT_ERROR_NULL_POINTER; break;
    case 3: g_positions[below(count * 3)] = chance(50) ? NAN : -INFINITY;
            want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT; break;
    case 4: {
        enum handle_fault fault = any_handle_fault();
        if (fault == HANDLE_FOREIGN) {
            other_context(s);
        }
        mesh.id = handle_for(&s->meshes, s->other_mesh, &fault, &want);
        /* Without such a handle to hand, another live mesh stands in, whose vertex count the
         * range may not fit. */
        if (want == TRANSLUCID_RESULT_SUCCESS) {
            want = ANY;
        }
        break;
    }
    case 5: /* Scrambled. */
        first = chance(50) ? first : any_u32();
        count = chance(50) ? count : any_u32() % (MAX_VERTICES + 2);
        want = ANY;
        break;
    default: break;
    }
    translucid_result got = translucid_mesh_update(s->ctx, mesh, first, count, positions);
    check(got, want, s->ctx, "translucid_mesh_update", __LINE__);
}

static void texture_create(state *s) {
    translucid_texture_create_info info;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_TEXTURE_CREATE_INFO;
    info.width = side();
    info.height = side();
    info.flags = below(2) ? TRANSLUCID_TEXTURE_SRGB : 0;
    for (uint32_t i = 0; i < info.width * info.height * 4; i++) {
        g_texels[i] = (uint8_t)next_u64();
    }
    info.texels = g_texels;
    translucid_sampler_info sampler;
    memset(&sampler, 0, sizeof sampler);
    sampler.s_type = TRANSLUCID_STRUCTURE_TYPE_SAMPLER_INFO;
    sampler.wrap_s = below(3);
    sampler.wrap_t = below(3);
    sampler.mag_filter = below(2);
    sampler.min_filter = below(2);
    sampler.mipmap_mode = below(3);
    if (chance(50)) {
        info.next = &sampler;
    }

    int want = TRANSLUCID_RESULT_SUCCESS;
    translucid_texture texture = {UNTOUCHED};
    translucid_texture *out = &texture;
    switch (below(11)) {
    case 0: out = NULL; want = TRANSLUCID_RESULT_ERROR_NULL_POINTER; break;
    case 1: info.texels = NULL; want = TRANSLUCID_RESULT_ERROR_NULL_POINTER; break;
    case 2: info.s_type = TRANSLUCID_STRUCTURE_TYPE_MESH_CREATE_INFO;
            want = TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE; break;
    case 3: if (chance(50)) info.width = 0; else info.height = 0;
            want = TRANSLUCID_RESULT_ERROR_INVALID_SIZE; break;
    case 4: info.width = TRANSLUCID_MAX_TEXTURE_SIZE + 1 + below(1u << 20); info.height = 1;
            want = TRANSLUCID_RESULT_ERROR_INVALID_SIZE; break;
    case 5: info.flags |= 2u << below(30); want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT; break;
    case 6: info.next = &sampler; sampler.wrap_s = 3 + below(100);
            want = TRANSLUCID_RESULT_ERROR_INVALID_ENUM; break;
    case 7: info.next = &sampler; sampler.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
            want = TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE; break;
    case 8: /* Scrambled sampler. */
        info.next = &sampler;
        sampler.wrap_s = chance(50) ? sampler.wrap_s : any_u32();
        sampler.wrap_t = chance(50) ? sampler.wrap_t : any_u32();
        sampler.mag_filter = chance(50) ? sampler.mag_filter : any_u32();
        sampler.min_filter = chance(50) ? sampler.min_filter : any_u32();
        sampler.mipmap_mode = chance(50) ? sampler.mipmap_mode : any_u32();
        want = ANY;
        break;
    default: break;
    }
    translucid_result got = translucid_texture_create(s->ctx, &info, out);
    check(got, want, s->ctx, "translucid_texture_create", __LINE__);
    check_out(got, out ? texture.id : UNTOUCHED, s->ctx, "translucid_texture_create", __LINE__);
    if (got == TRANSLUCID_RESULT_SUCCESS && out) {
        remember(&s->textures, texture.id);
    }
}

static void material_create(state *s) {
    translucid_material_create_info info;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_MATERIAL_CREATE_INFO;
    for (int i = 0; i < 4; i++) {
        info.base_colour[i] = unit();
    }
    info.transmission = chance(50) ? unit() : 0.0f;
    for (int i = 0; i < 3; i++) {
        info.transmission_tint[i] = unit();
    }
    info.reflectance = unit();
    info.alpha_cutoff = chance(20) ? unit() : 0.0f;
    info.flags = below(4);
    info.name = chance(50) ? "fuzzed material" : NULL;

    int want = TRANSLUCID_RESULT_SUCCESS;
    if (chance(40)) {
        enum handle_fault fault = any_handle_fault();
        if (fault == HANDLE_NULL) {
            fault = HANDLE_LIVE; /* a NULL texture is "untextured", not a fault */
        }
        if (fault == HANDLE_FOREIGN) {
            other_context(s);
        }
        info.texture.id = handle_for(&s->textures, s->other_texture, &fault, &want);
        if (info.texture.id == 0) {
            want = TRANSLUCID_RESULT_SUCCESS; /* no texture made yet: untextured */
        }
    }
    translucid_material material = {UNTOUCHED};
    translucid_material *out = &material;
    int fault_free = want == TRANSLUCID_RESULT_SUCCESS;
    switch (fault_free ? below(9) : 8) {
    case 0: out = NULL; want = TRANSLUCID_RESULT_ERROR_NULL_POINTER; break;
    case 1: info.s_type = 0; want = TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE; break;
    case 2: { /* colour is finite and non-negative, alpha in [0, 1] */
        uint32_t k = below(4);
        info.base_colour[k] = chance(50) ? NAN : k == 3 ? 1.5f : -0.5f;
        want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT;
        break;
    }
    case 3: info.transmission = chance(50) ? -0.5f : INFINITY;
            want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT; break;
    case 4: info.flags |= 4u << below(29); want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT; break;
    case 5: /* Scrambled. */
        info.base_colour[below(4)] = any_float();
        info.transmission_tint[below(3)] = any_float();
        info.reflectance = chance(50) ? info.reflectance : any_float();
        info.alpha_cutoff = chance(50) ? info.alpha_cutoff : any_float();
        want = ANY;
        break;
    default: break;
    }
    translucid_result got = translucid_material_create(s->ctx, &info, out);
    check(got, want, s->ctx, "translucid_material_create", __LINE__);
    check_out(got, out ? material.id : UNTOUCHED, s->ctx, "translucid_material_create",
              __LINE__);
    if (got == TRANSLUCID_RESULT_SUCCESS && out) {
        remember(&s->materials, material.id);
    }
}

/* Destroys a random object of a random kind: a live one succeeds, then its handle is
 * stale; the others give their handle fault's code. */
static void destroy(state *s) {
    uint32_t kind = below(4);
    objects *lists[4] = {&s->meshes, &s->textures, &s->materials, &s->frames};
    objects *list = lists[kind];
    enum handle_fault fault = any_handle_fault();
    if (fault == HANDLE_FOREIGN) {
        other_context(s);
    }
    uint64_t foreign[4] = {s->other_mesh, s->other_texture, s->other_material, 0};
    int want;
    uint64_t id = handle_for(list, foreign[kind], &fault, &want);
    translucid_result got;
    switch (kind) {
    case 0: got = translucid_mesh_destroy(s->ctx, (translucid_mesh){id}); break;
    case 1: got = translucid_texture_destroy(s->ctx, (translucid_texture){id}); break;
    case 2: got = translucid_material_destroy(s->ctx, (translucid_material){id}); break;
    default:
        if (chance(80)) {
            got = translucid_frame_destroy(s->ctx, (translucid_frame){id});
        } else {
            /* Only frames in flight can be abandoned, and standalone frames never are. */
            got = translucid_frame_abandon(s->ctx, (translucid_frame){id});
            if (want == TRANSLUCID_RESULT_SUCCESS) {
                want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT;
            }
        }
        break;
    }
    check(got, want, s->ctx, "translucid_*_destroy", __LINE__);
    if (got == TRANSLUCID_RESULT_SUCCESS) {
        for (int i = 0; i < list->count; i++) {
            if (list->items[i].id == id) {
                list->items[i].live = 0;
            }
        }
    }
}

/* The largest colour value translucid takes and gives: the largest finite half float. */
#define MAX_COLOUR 65504.0f

/* A colour channel within translucid's range, often at its ends. */
static float hdr_channel(void) {
    switch (below(4)) {
    case 0: return MAX_COLOUR;
    case 1: return 0.0f;
    case 2: return unit() * MAX_COLOUR;
    default: return unit();
    }
}

/* A value just past what a colour channel may be. */
static float bad_channel(void) {
    switch (below(4)) {
    case 0: return 65520.0f; /* rounds to infinity as a half */
    case 1: return 1.7e5f;
    case 2: return -1.0f;
    default: return NAN;
    }
}

static _Thread_local float g_opaque_colour[MAX_SIDE * MAX_SIDE * 4];
static _Thread_local float g_opaque_depth[MAX_SIDE * MAX_SIDE];
static _Thread_local translucid_exact_settings g_exact;
static _Thread_local translucid_wavelet_settings g_wavelet;

static void frame_render(state *s) {
    translucid_draw draws[6];
    uint32_t draw_count = below(7);
    int want = TRANSLUCID_RESULT_SUCCESS;
    for (uint32_t i = 0; i < draw_count; i++) {
        translucid_draw *d = &draws[i];
        memset(d, 0, sizeof *d);
        enum handle_fault fault = chance(85) ? HANDLE_LIVE : any_handle_fault();
        if (fault == HANDLE_FOREIGN) {
            other_context(s);
        }
        int w1 = TRANSLUCID_RESULT_SUCCESS, w2 = TRANSLUCID_RESULT_SUCCESS;
        d->mesh.id = handle_for(&s->meshes, s->other_mesh, &fault, &w1);
        fault = chance(85) ? HANDLE_LIVE : any_handle_fault();
        if (fault == HANDLE_FOREIGN) {
            other_context(s);
        }
        d->material.id = handle_for(&s->materials, s->other_material, &fault, &w2);
        /* With several bad handles, which is reported first is not specified. */
        int w = w1 != TRANSLUCID_RESULT_SUCCESS ? w1 : w2;
        if (w != TRANSLUCID_RESULT_SUCCESS) {
            want = want == TRANSLUCID_RESULT_SUCCESS ? w : ANY;
        }
        float scale = 0.3f + unit();
        d->transform[0] = d->transform[5] = d->transform[10] = scale;
        d->transform[15] = 1.0f;
        d->transform[12] = unit() - 0.5f;
        /* On the engine's device opaque geometry is the engine's to draw. */
        d->layer = chance(80) || g_host_mode ? TRANSLUCID_LAYER_TRANSPARENT
                                              : TRANSLUCID_LAYER_OPAQUE;
        if (chance(30)) {
            for (int c = 0; c < 4; c++) d->tint[c] = unit() * 1.5f;
        }
    }
    /* A material whose texture was destroyed cannot be drawn; which materials use which
     * textures is not kept here. */
    int textures_destroyed = 0;
    for (int i = 0; i < s->textures.count; i++) {
        textures_destroyed |= !s->textures.items[i].live;
    }
    if (draw_count > 0 && textures_destroyed) {
        want = ANY;
    }
    translucid_frame_info info;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
    info.method = s->methods[below((uint32_t)s->method_count)];
    info.width = side();
    info.height = side();
    info.camera.view[0] = info.camera.view[5] = info.camera.view[10] = info.camera.view[15] = 1;
    info.camera.fov_y = 0.5f + unit();
    info.camera.z_near = 0.1f;
    info.camera.z_far = 50.0f;
    info.draws = draw_count ? draws : NULL;
    info.draw_count = draw_count;
    info.background[0] = unit();
    translucid_light light = {{0.3f, -1.0f, -0.2f}, {1, 1, 1}, {0.1f, 0.1f, 0.1f}};
    info.light = chance(50) ? &light : NULL;
    translucid_opaque_layer opaque;
    memset(&opaque, 0, sizeof opaque);
    opaque.s_type = TRANSLUCID_STRUCTURE_TYPE_OPAQUE_LAYER;
    opaque.colour_format = TRANSLUCID_PIXEL_FORMAT_RGBA32F_LINEAR;
    opaque.colour = g_opaque_colour;
    opaque.depth = g_opaque_depth;
    g_exact.s_type = TRANSLUCID_STRUCTURE_TYPE_EXACT_SETTINGS;
    g_exact.next = NULL;
    g_exact.threshold = chance(20) ? unit() * 0.2f : 0.0f;
    g_wavelet.s_type = TRANSLUCID_STRUCTURE_TYPE_WAVELET_SETTINGS;
    g_wavelet.next = NULL;
    g_wavelet.coefficients = 0;
    g_wavelet.noise = 0.0f;
    g_wavelet.storage = TRANSLUCID_WAVELET_STORAGE_BINS;
    info.next = chance(80) ? (const void *)&g_exact : NULL;
    if (chance(50)) g_exact.next = &g_wavelet;
    if (chance(30)) {
        /* The engine's own matrix: reversed-Z with an infinite far plane, and a jitter. */
        float f = 1.0f / tanf(0.4f);
        info.camera.projection[0] = f * (float)info.height / (float)info.width;
        info.camera.projection[5] = -f;
        info.camera.projection[11] = -1.0f;
        info.camera.projection[14] = 0.1f;
        info.camera.jitter[0] = unit() - 0.5f;
        info.camera.jitter[1] = unit() - 0.5f;
    }
    if (chance(30)) {
        info.frame_index = s->frame_index + below(3);
    }

    translucid_frame frame = {UNTOUCHED};
    translucid_frame *out = &frame;
    if (want == TRANSLUCID_RESULT_SUCCESS) {
        uint32_t pick = below(18);
        switch (pick) {
        case 0: out = NULL; want = TRANSLUCID_RESULT_ERROR_NULL_POINTER; break;
        case 1: info.method = METHOD_END + below(1000); want = TRANSLUCID_RESULT_ERROR_INVALID_ENUM; break;
        case 2: if (chance(50)) info.width = 0; else info.height = 1u << (16 + below(16));
                want = TRANSLUCID_RESULT_ERROR_INVALID_SIZE; break;
        case 3: info.camera.view[below(16)] = NAN; want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT;
                break;
        case 4: /* Near and far are read without a projection matrix only. */
                memset(info.camera.projection, 0, sizeof info.camera.projection);
                info.camera.z_near = chance(50) ? 0.0f : info.camera.z_far * 2.0f;
                want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT; break;
        case 5: if (draw_count > 0) {
                    info.draws = NULL;
                    want = TRANSLUCID_RESULT_ERROR_NULL_POINTER;
                }
                break;
        case 6: if (draw_count > 0) {
                    draws[below(draw_count)].layer = 2 + below(100);
                    want = TRANSLUCID_RESULT_ERROR_INVALID_ENUM;
                }
                break;
        case 7: if (draw_count > 0) {
                    draws[below(draw_count)].transform[below(16)] = INFINITY;
                    want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT;
                }
                break;
        case 9: if (draw_count > 0) {
                    draws[below(draw_count)].tint[below(4)] = chance(50) ? -0.5f : NAN;
                    want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT;
                }
                break;
        case 10: if (s->frame_index > 1) {
                    info.frame_index = 1 + below((uint32_t)(s->frame_index - 1));
                    want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT;
                }
                break;
        case 11: info.camera.jitter[below(2)] = chance(50) ? NAN : INFINITY;
                want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT;
                break;
        case 12: { /* Extreme but allowed: HDR colours at their limit, a world far out. */
                for (int c = 0; c < 3; c++) {
                    light.colour[c] = hdr_channel();
                    light.ambient[c] = hdr_channel();
                    info.background[c] = hdr_channel();
                }
                info.light = &light;
                static const float offsets[] = {1e4f, 1e5f, 1e7f, 1e19f};
                float offset = offsets[below(4)] * (chance(50) ? 1.0f : -1.0f);
                int axis = (int)below(3);
                info.camera.view[12 + axis] = -offset;
                for (uint32_t i = 0; i < draw_count; i++) {
                    draws[i].transform[12 + axis] += offset;
                    if (chance(50)) {
                        for (int c = 0; c < 4; c++) draws[i].tint[c] = hdr_channel();
                    }
                }
                break;
            }
        case 13: /* The engine's opaque layer, HDR up to the limit. */
        case 14: { /* ... with one value out of its range. */
                size_t pixels = (size_t)info.width * info.height;
                if (g_host_mode) {
                    /* There the opaque layer is the engine's images: a layer in the frame
                     * info, or an opaque draw, is refused. */
                    if (pick == 13 || draw_count == 0) {
                        info.opaque_layer = &opaque;
                    } else {
                        draws[below(draw_count)].layer = TRANSLUCID_LAYER_OPAQUE;
                    }
                    want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT;
                    break;
                }
                if (pixels > MAX_SIDE * MAX_SIDE) {
                    break;
                }
                for (size_t i = 0; i < pixels; i++) {
                    for (int c = 0; c < 4; c++) g_opaque_colour[4 * i + (size_t)c] = hdr_channel();
                    g_opaque_depth[i] = chance(30) ? 1.0f : unit();
                }
                for (uint32_t i = 0; i < draw_count; i++) {
                    draws[i].layer = TRANSLUCID_LAYER_TRANSPARENT;
                }
                info.opaque_layer = &opaque;
                if (pick == 14) {
                    size_t at = below((uint32_t)pixels);
                    if (chance(70)) {
                        g_opaque_colour[4 * at + below(3)] = bad_channel();
                    } else {
                        g_opaque_depth[at] = chance(50) ? 1.5f : NAN;
                    }
                    want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT;
                }
                break;
            }
        case 15: /* A light past the colour limit. */
                info.light = &light;
                if (chance(50)) {
                    light.colour[below(3)] = bad_channel();
                } else {
                    light.ambient[below(3)] = bad_channel();
                }
                want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT;
                break;
        case 8: /* Scrambled. */
            info.camera.fov_y = chance(50) ? info.camera.fov_y : any_float();
            info.camera.z_far = chance(50) ? info.camera.z_far : any_float();
            g_exact.threshold = chance(50) ? g_exact.threshold : any_float();
            g_wavelet.coefficients = chance(50) ? 0 : any_u32();
            g_wavelet.storage = chance(50) ? 0 : any_u32();
            g_wavelet.noise = chance(50) ? 0.0f : any_float();
            if (chance(20)) g_wavelet.s_type = any_u32(); /* a link of no known type */
            if (chance(10)) g_wavelet.next = &g_exact;    /* a loop: refused */
            info.background[below(3)] = any_float();
            info.camera.projection[below(16)] = any_float();
            if (draw_count > 0 && chance(50)) {
                draws[below(draw_count)].transform[below(16)] = any_float();
            }
            want = ANY;
            break;
        default: break;
        }
    }
    const char *call = g_host_mode ? "translucid_frame_record" : "translucid_frame_render";
    fuzz_host_outcome outcome = {TRANSLUCID_RESULT_SUCCESS, 1};
    translucid_result got = g_host_mode ? fuzz_host_frame(s->ctx, &info, out, below, &outcome)
                                        : translucid_frame_render(s->ctx, &info, out);
    check(got, want, s->ctx, call, __LINE__);
    check_out(got, out ? frame.id : UNTOUCHED, s->ctx, call, __LINE__);
    if (got != TRANSLUCID_RESULT_SUCCESS || !out) {
        return;
    }
    remember(&s->frames, frame.id);
    if (info.frame_index > s->frame_index) {
        s->frame_index = info.frame_index;
    }
    if (g_host_mode) {
        /* A recorded frame completes once its submission has finished; FRAME_DEGRADED asks
         * for it to be recorded again. Its pixels are the engine's colour image. */
        if (outcome.completed != TRANSLUCID_RESULT_SUCCESS &&
            outcome.completed != TRANSLUCID_RESULT_FRAME_DEGRADED) {
            broken("translucid_frame_complete", __LINE__, "a submitted frame did not complete",
                   outcome.completed, s->ctx);
        }
        if (!outcome.finite) {
            broken("translucid_frame_record", __LINE__, "a composited pixel is not finite", got,
                   s->ctx);
        }
        return;
    }
    /* A rendered frame reads back whole, with finite pixels. */
    size_t pixels = (size_t)info.width * info.height;
    float *linear = malloc(pixels * 16);
    CHECK(s->ctx, translucid_frame_read(s->ctx, frame, TRANSLUCID_PIXEL_FORMAT_RGBA32F_LINEAR,
                                        linear, pixels * 16),
          TRANSLUCID_RESULT_SUCCESS);
    for (size_t i = 0; i < pixels * 4; i++) {
        if (!isfinite(linear[i])) {
            broken("translucid_frame_read", __LINE__, "a rendered pixel is not finite", 0, s->ctx);
        }
    }
    free(linear);
}

/* Reads, statistics and PNGs of random frames, into buffers of random sizes. */
static void frame_use(state *s) {
    /* No foreign frames are made: that fault falls back to a live frame. */
    enum handle_fault fault = any_handle_fault();
    int want;
    translucid_frame frame = {handle_for(&s->frames, 0, &fault, &want)};
    switch (below(3)) {
    case 0: {
        uint32_t format = chance(90) ? below(2) : 2 + below(100);
        size_t size = below(MAX_SIDE * MAX_SIDE * 16 + 1);
        void *pixels = malloc(size ? size : 1);
        translucid_result got = translucid_frame_read(s->ctx, frame, format, pixels, size);
        /* The right size is the frame's, which is not kept here. */
        check(got, want == TRANSLUCID_RESULT_SUCCESS || format > 1 ? ANY : want, s->ctx,
              "translucid_frame_read", __LINE__);
        if (g_host_mode && got >= 0) {
            broken("translucid_frame_read", __LINE__, "read pixels of a host-device frame", got,
                   s->ctx);
        }
        if (format > 1 && want == TRANSLUCID_RESULT_SUCCESS && got >= 0) {
            broken("translucid_frame_read", __LINE__, "an undefined format succeeded", got,
                   s->ctx);
        }
        free(pixels);
        break;
    }
    case 1: {
        translucid_frame_statistics stats;
        memset(&stats, 0, sizeof stats);
        stats.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_STATISTICS;
        if (want == TRANSLUCID_RESULT_SUCCESS && chance(20)) {
            stats.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
            want = TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE;
        }
        translucid_result got = translucid_frame_get_statistics(s->ctx, frame, &stats);
        check(got, want, s->ctx, "translucid_frame_get_statistics", __LINE__);
        if (got == TRANSLUCID_RESULT_SUCCESS &&
            (stats.stage_count > TRANSLUCID_MAX_STAGES ||
             memchr(stats.stages[0].name, 0, TRANSLUCID_STAGE_NAME_SIZE) == NULL)) {
            broken("translucid_frame_get_statistics", __LINE__, "statistics out of range", got,
                   s->ctx);
        }
        break;
    }
    default: {
        char path[96];
        snprintf(path, sizeof path, "/tmp/translucid-fuzz-%ld/frame.png", (long)getpid());
        translucid_result got = translucid_frame_write_png(s->ctx, frame, path);
        /* A host-device frame's pixels are the engine's: it has none to write. */
        check(got, g_host_mode && want == TRANSLUCID_RESULT_SUCCESS ? ANY : want, s->ctx,
              "translucid_frame_write_png", __LINE__);
        if (g_host_mode && got >= 0) {
            broken("translucid_frame_write_png", __LINE__, "wrote a host-device frame", got,
                   s->ctx);
        }
        remove(path);
        break;
    }
    }
}

/* Calls that need no objects, and calls a standalone context does not offer. */
static void misc(state *s) {
    switch (below(8)) {
    case 0: {
        uint32_t methods[8];
        size_t count = 0;
        size_t capacity = below(9);
        translucid_result got =
            translucid_method_get_available(capacity ? methods : NULL, capacity, &count);
        check(got, count > capacity ? TRANSLUCID_RESULT_INCOMPLETE : TRANSLUCID_RESULT_SUCCESS,
              NULL, "translucid_method_get_available", __LINE__);
        break;
    }
    case 1: {
        uint32_t method = any_u32();
        const char *name = translucid_method_name(method);
        if ((method < METHOD_END) != (name != NULL)) {
            broken("translucid_method_name", __LINE__, "a name for no method, or none for one",
                   0, NULL);
        }
        (void)strlen(translucid_result_string((int32_t)any_u32()));
        (void)strlen(translucid_version_string());
        (void)strlen(translucid_context_get_device_name(s->ctx));
        break;
    }
    case 2: {
        translucid_host_requirements requirements;
        memset(&requirements, 0, sizeof requirements);
        requirements.s_type = chance(50) ? TRANSLUCID_STRUCTURE_TYPE_HOST_REQUIREMENTS
                                         : any_u32();
        translucid_result got = translucid_host_get_requirements(&requirements);
        check(got,
              requirements.s_type == TRANSLUCID_STRUCTURE_TYPE_HOST_REQUIREMENTS
                  ? TRANSLUCID_RESULT_SUCCESS
                  : TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE,
              NULL, "translucid_host_get_requirements", __LINE__);
        for (uint32_t i = 0; got == 0 && i < requirements.extension_count; i++) {
            (void)strlen(requirements.extensions[i]);
        }
        break;
    }
    case 3: {
        /* Recording is host-device only; in that mode, empty targets are refused. */
        translucid_frame frame = {UNTOUCHED};
        translucid_frame_info info;
        memset(&info, 0, sizeof info);
        info.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
        translucid_host_frame_targets targets;
        memset(&targets, 0, sizeof targets);
        targets.s_type = TRANSLUCID_STRUCTURE_TYPE_HOST_FRAME_TARGETS;
        translucid_result got = translucid_frame_record(s->ctx, &info, &targets, &frame);
        check(got, ANY, s->ctx, "translucid_frame_record", __LINE__);
        if (got >= 0 || frame.id != UNTOUCHED) {
            broken("translucid_frame_record", __LINE__,
                   "recorded without targets or on a standalone context, or wrote its "
                   "out-parameter", got, s->ctx);
        }
        break;
    }
    case 4: {
        object *o = pick(&s->frames);
        translucid_result got =
            translucid_frame_complete(s->ctx, (translucid_frame){o ? o->id : any_u32()});
        check(got, ANY, s->ctx, "translucid_frame_complete", __LINE__);
        /* Host-device frames were completed when made; completing one again is not
         * specified here. */
        if (got >= 0 && !g_host_mode) {
            broken("translucid_frame_complete", __LINE__, "a standalone frame completed", got,
                   s->ctx);
        }
        break;
    }
    case 5: {
        /* A prepare that cannot be done (building pipelines is left to the tests). */
        translucid_frame_info frame;
        memset(&frame, 0, sizeof frame);
        frame.s_type = TRANSLUCID_STRUCTURE_TYPE_FRAME_INFO;
        frame.width = frame.height = 8;
        translucid_prepare_info info;
        memset(&info, 0, sizeof info);
        info.s_type = TRANSLUCID_STRUCTURE_TYPE_PREPARE_INFO;
        info.frame = &frame;
        const translucid_prepare_info *pinfo = &info;
        uint64_t built = UNTOUCHED;
        int want;
        switch (below(5)) {
        case 0: pinfo = NULL; want = TRANSLUCID_RESULT_ERROR_NULL_POINTER; break;
        case 1: info.s_type = any_u32() | 0x100; want = TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE;
                break;
        case 2: info.content = TRANSLUCID_CONTENT_ALL + 1 + below(1u << 20);
                want = TRANSLUCID_RESULT_ERROR_INVALID_ARGUMENT; break;
        case 3: info.frame = NULL; want = TRANSLUCID_RESULT_ERROR_NULL_POINTER; break;
        default: frame.method = METHOD_END + below(1000); want = TRANSLUCID_RESULT_ERROR_INVALID_ENUM;
                 break;
        }
        translucid_result got = translucid_context_prepare(s->ctx, pinfo, &built);
        check(got, want, s->ctx, "translucid_context_prepare", __LINE__);
        if (built != UNTOUCHED) {
            broken("translucid_context_prepare", __LINE__, "wrote its out-parameter", got, s->ctx);
        }
        break;
    }
    case 6: {
        /* The memory a context holds, asked rightly or not; then a trim. */
        translucid_memory_statistics memory;
        memset(&memory, 0, sizeof memory);
        memory.s_type = TRANSLUCID_STRUCTURE_TYPE_MEMORY_STATISTICS;
        int want = TRANSLUCID_RESULT_SUCCESS;
        translucid_memory_statistics *out = &memory;
        switch (below(3)) {
        case 0: out = NULL; want = TRANSLUCID_RESULT_ERROR_NULL_POINTER; break;
        case 1: memory.s_type = any_u32() | 0x100; want = TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE;
                break;
        default: break;
        }
        translucid_result got = translucid_context_get_memory_statistics(s->ctx, out);
        check(got, want, s->ctx, "translucid_context_get_memory_statistics", __LINE__);
        if (got == TRANSLUCID_RESULT_SUCCESS &&
            memory.total_bytes != memory.device_local_bytes + memory.per_frame_bytes +
                                      memory.staging_bytes + memory.readback_bytes) {
            broken("translucid_context_get_memory_statistics", __LINE__,
                   "a total that is not the sum of its kinds", got, s->ctx);
        }
        uint64_t freed = 0;
        got = translucid_context_trim(s->ctx, chance(50) ? &freed : NULL);
        check(got, TRANSLUCID_RESULT_SUCCESS, s->ctx, "translucid_context_trim", __LINE__);
        break;
    }
    default: {
        /* A context that cannot be made: the out-parameter stays as it was. */
        translucid_context_create_info info;
        memset(&info, 0, sizeof info);
        info.s_type = TRANSLUCID_STRUCTURE_TYPE_CONTEXT_CREATE_INFO;
        info.header_version = TRANSLUCID_HEADER_VERSION;
        int want;
        switch (below(3)) {
        case 0: info.s_type = any_u32() | 0x200; want = TRANSLUCID_RESULT_ERROR_INVALID_STRUCTURE_TYPE;
                break;
        case 1: info.header_version = TRANSLUCID_HEADER_VERSION + (1u << 22);
                want = TRANSLUCID_RESULT_ERROR_HEADER_VERSION_MISMATCH; break;
        default: info.mode = 2 + below(1000); want = TRANSLUCID_RESULT_ERROR_INVALID_ENUM; break;
        }
        translucid_context *ctx = (translucid_context *)(uintptr_t)UNTOUCHED;
        translucid_result got = translucid_context_create(&info, &ctx);
        check(got, want, NULL, "translucid_context_create", __LINE__);
        if (ctx != (translucid_context *)(uintptr_t)UNTOUCHED) {
            broken("translucid_context_create", __LINE__, "wrote its out-parameter", got, NULL);
        }
        break;
    }
    }
}

/* ---- cases ---- */

static translucid_context *new_context(void) {
    translucid_context_create_info info;
    memset(&info, 0, sizeof info);
    info.s_type = TRANSLUCID_STRUCTURE_TYPE_CONTEXT_CREATE_INFO;
    info.header_version = TRANSLUCID_HEADER_VERSION;
    if (g_host_mode) {
        info.mode = TRANSLUCID_CONTEXT_MODE_HOST_DEVICE;
        info.next = fuzz_host_device_info();
    }
    translucid_context *ctx = NULL;
    translucid_result got = translucid_context_create(&info, &ctx);
    if (got != TRANSLUCID_RESULT_SUCCESS) {
        fprintf(stderr, "fuzz_calls: no context (%s): %s\n", translucid_result_string(got),
                translucid_context_get_last_error(NULL));
        exit(2);
    }
    return ctx;
}

/* The second context, with one object of each kind to pass as foreign handles. */
static translucid_context *other_context(state *s) {
    if (s->other) {
        return s->other;
    }
    s->other = new_context();
    static const float positions[] = {0, 0, -2, 1, 0, -2, 0, 1, -2};
    static const uint32_t indices[] = {0, 1, 2};
    translucid_mesh_create_info mesh;
    memset(&mesh, 0, sizeof mesh);
    mesh.s_type = TRANSLUCID_STRUCTURE_TYPE_MESH_CREATE_INFO;
    mesh.vertex_count = 3;
    mesh.positions = positions;
    mesh.index_count = 3;
    mesh.indices = indices;
    static const uint8_t texel[4] = {255, 0, 0, 255};
    translucid_texture_create_info texture;
    memset(&texture, 0, sizeof texture);
    texture.s_type = TRANSLUCID_STRUCTURE_TYPE_TEXTURE_CREATE_INFO;
    texture.width = texture.height = 1;
    texture.texels = texel;
    translucid_material_create_info material;
    memset(&material, 0, sizeof material);
    material.s_type = TRANSLUCID_STRUCTURE_TYPE_MATERIAL_CREATE_INFO;
    material.base_colour[3] = 0.5f;
    translucid_mesh m;
    translucid_texture t;
    translucid_material mt;
    CHECK(s->other, translucid_mesh_create(s->other, &mesh, &m), TRANSLUCID_RESULT_SUCCESS);
    CHECK(s->other, translucid_texture_create(s->other, &texture, &t), TRANSLUCID_RESULT_SUCCESS);
    CHECK(s->other, translucid_material_create(s->other, &material, &mt),
          TRANSLUCID_RESULT_SUCCESS);
    s->other_mesh = m.id;
    s->other_texture = t.id;
    s->other_material = mt.id;
    return s->other;
}

static void run_case(uint64_t seed, uint64_t number, unsigned calls) {
    g_seed = seed;
    g_case = number;
    g_state = seed ^ (number * 0xD1B54A32D192ED03ull);
    (void)next_u64();
    state s;
    memset(&s, 0, sizeof s);
    s.ctx = new_context();
    CHECK(NULL, translucid_method_get_available(s.methods, 8, &s.method_count),
          TRANSLUCID_RESULT_SUCCESS);
    for (unsigned i = 0; i < calls; i++) {
        uint32_t op = below(100);
        if (op < 18) {
            mesh_create(&s);
        } else if (op < 28) {
            texture_create(&s);
        } else if (op < 45) {
            material_create(&s);
        } else if (op < 55) {
            destroy(&s);
        } else if (op < 60) {
            mesh_update(&s);
        } else if (op < 78) {
            frame_render(&s);
        } else if (op < 90) {
            frame_use(&s);
        } else {
            misc(&s);
        }
    }
    translucid_context_destroy(s.ctx);
    translucid_context_destroy(s.other);
}

static uint64_t number_arg(int argc, char **argv, int *i) {
    if (*i + 1 >= argc) {
        fprintf(stderr, "fuzz_calls: %s needs a value\n", argv[*i]);
        exit(2);
    }
    return strtoull(argv[++*i], NULL, 0);
}

#define MAX_THREADS 16

/* What the threads share: the run's plan, and per thread the case it is in and since when
 * (for the watchdog, since one alarm cannot time several threads). */
typedef struct {
    uint64_t seed, first, cases, seconds;
    unsigned calls, threads;
    time_t start;
    pthread_mutex_t lock;
    unsigned long calls_made;
    uint64_t cases_run;
    uint64_t current[MAX_THREADS];
    time_t since[MAX_THREADS];
    int running[MAX_THREADS];
} run;

static int more_cases(const run *r, uint64_t n) {
    return r->cases ? n < r->first + r->cases
                    : (uint64_t)(time(NULL) - r->start) < r->seconds;
}

typedef struct {
    run *run;
    unsigned index;
} worker;

static void *work(void *arg) {
    worker *w = arg;
    run *r = w->run;
    uint64_t done = 0;
    for (uint64_t n = r->first + w->index; more_cases(r, n); n += r->threads) {
        pthread_mutex_lock(&r->lock);
        r->current[w->index] = n;
        r->since[w->index] = time(NULL);
        pthread_mutex_unlock(&r->lock);
        fprintf(stderr, "case %llu\n", (unsigned long long)n);
        run_case(r->seed, n, r->calls);
        done++;
    }
    fuzz_host_thread_end();
    pthread_mutex_lock(&r->lock);
    r->calls_made += g_calls;
    r->cases_run += done;
    r->running[w->index] = 0;
    pthread_mutex_unlock(&r->lock);
    return NULL;
}

/* Runs the cases on r->threads threads; a case past CASE_TIMEOUT ends the run as a hang. */
static void run_threads(run *r) {
    pthread_t threads[MAX_THREADS];
    worker workers[MAX_THREADS];
    for (unsigned t = 0; t < r->threads; t++) {
        workers[t].run = r;
        workers[t].index = t;
        r->running[t] = 1;
        r->since[t] = time(NULL);
        if (pthread_create(&threads[t], NULL, work, &workers[t]) != 0) {
            fprintf(stderr, "fuzz_calls: no thread %u\n", t);
            exit(2);
        }
    }
    for (;;) {
        int any = 0;
        pthread_mutex_lock(&r->lock);
        for (unsigned t = 0; t < r->threads; t++) {
            if (r->running[t] && time(NULL) - r->since[t] > CASE_TIMEOUT) {
                fprintf(stderr, "HANG: case %llu of seed %llu ran past %d s on thread %u\n",
                        (unsigned long long)r->current[t], (unsigned long long)r->seed,
                        CASE_TIMEOUT, t);
                _exit(1);
            }
            any |= r->running[t];
        }
        pthread_mutex_unlock(&r->lock);
        if (!any) {
            break;
        }
        sleep(1);
    }
    for (unsigned t = 0; t < r->threads; t++) {
        pthread_join(threads[t], NULL);
    }
}

int main(int argc, char **argv) {
    static run r;
    r.seed = (uint64_t)time(NULL);
    r.calls = 60;
    r.threads = 1;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--seed") == 0) {
            r.seed = number_arg(argc, argv, &i);
        } else if (strcmp(argv[i], "--first") == 0) {
            r.first = number_arg(argc, argv, &i);
        } else if (strcmp(argv[i], "--cases") == 0) {
            r.cases = number_arg(argc, argv, &i);
        } else if (strcmp(argv[i], "--seconds") == 0) {
            r.seconds = number_arg(argc, argv, &i);
        } else if (strcmp(argv[i], "--calls") == 0) {
            r.calls = (unsigned)number_arg(argc, argv, &i);
        } else if (strcmp(argv[i], "--threads") == 0) {
            r.threads = (unsigned)number_arg(argc, argv, &i);
        } else if (strcmp(argv[i], "--host-device") == 0) {
            g_host_mode = 1;
        } else {
            fprintf(stderr,
                    "usage: fuzz_calls [--seed S] [--first N] [--cases N | --seconds T] "
                    "[--calls K] [--threads N] [--host-device]\n");
            return 2;
        }
    }
    if (r.threads < 1 || r.threads > MAX_THREADS) {
        fprintf(stderr, "fuzz_calls: --threads takes 1 to %d\n", MAX_THREADS);
        return 2;
    }
    if (r.cases == 0 && r.seconds == 0) {
        r.cases = 1;
    }
    fprintf(stderr,
            "fuzzing the C API: seed %llu, cases from %llu, %u calls each, %u thread%s%s\n",
            (unsigned long long)r.seed, (unsigned long long)r.first, r.calls, r.threads,
            r.threads == 1 ? "" : "s", g_host_mode ? ", on an engine's device" : "");
    if (g_host_mode) {
        fuzz_host_start();
    }
    pthread_mutex_init(&r.lock, NULL);
    r.start = time(NULL);
    if (r.threads == 1) {
        uint64_t n = r.first;
        for (; more_cases(&r, n); n++) {
            /* A hang ends the run by SIGALRM, with the case printed. */
            fprintf(stderr, "case %llu\n", (unsigned long long)n);
            alarm(CASE_TIMEOUT);
            run_case(r.seed, n, r.calls);
            alarm(0);
        }
        r.cases_run = n - r.first;
        r.calls_made = g_calls;
        fuzz_host_thread_end();
    } else {
        run_threads(&r);
    }
    if (g_host_mode) {
        int errors = fuzz_host_stop();
        if (errors > 0) {
            fprintf(stderr, "fuzz_calls: %d validation errors (above)\n", errors);
            return 1;
        }
    }
    printf("fuzz_calls: %llu cases, %lu calls, %lld s, seed %llu, %u thread%s%s: every call "
           "kept the contract\n",
           (unsigned long long)r.cases_run, r.calls_made, (long long)(time(NULL) - r.start),
           (unsigned long long)r.seed, r.threads, r.threads == 1 ? "" : "s",
           g_host_mode ? ", host device" : "");
    return 0;
}
