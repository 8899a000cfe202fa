// The mesh pipelines' vertex stage (scene/mesh.vert, scene/ordered.vert). The clip position
// is the CPU reference's, operation for operation (raster_rules.glsl), so that the driver
// rasterizes the triangles the reference does. With ORDER_DEPTH defined it also hands
// scene/ordered.geom what the reference's order depth needs of the vertex; with ORDER_ONLY
// too, only that (scene/ordered_order_only.vert); with UNLIT, no eye vector or normal
// (scene/ordered_unlit.vert).
#ifndef TRANSLUCID_MESH_VERTEX_GLSL
#define TRANSLUCID_MESH_VERTEX_GLSL

#include "scene_bindings.glsl"
#include "raster_rules.glsl"

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec4 a_colour;

#ifndef ORDER_ONLY
#ifndef UNLIT
layout(location = 0) out vec3 v_fromEye;       // world position minus the eye
layout(location = 1) out vec3 v_normal;
#endif
layout(location = 2) out vec2 v_uv;
layout(location = 3) out vec4 v_colour;
#endif
#ifdef ORDER_DEPTH
// The snapped framebuffer position (8 sub-pixel bits) and, in z, 1 when the vertex is on the
// fixed-point path (in front of the eye and the near plane, inside the guard band).
layout(location = 4) flat out ivec3 v_snapped;
// z_ndc and 1 / w.
layout(location = 5) out vec2 v_depth;
#endif

bool inGuardBand(float v) {
    return abs(v) <= GUARD_BAND; // false for NaN
}

// A framebuffer coordinate snapped as the reference snaps it (raster::snap, 8 sub-pixel bits),
// as a float: the same float operations as snapCoord, and every value in the guard band a
// multiple of 1/256 that a float holds exactly.
float snappedCoord(float v) {
    precise float s = floor(v * 256.0 + 0.5);
    return s * (1.0 / 256.0);
}

// The clip position the driver is handed: `clip` moved (by less than half a sub-pixel, w and z
// kept) to where its viewport transform lands exactly on the reference's snapped framebuffer
// position. Handed `clip` itself, the driver divides and scales in its own order and snaps the
// result itself: a vertex near a half sub-pixel could snap one sub-pixel away from the
// reference's, and a pixel centre a fraction of a sub-pixel inside an edge in the reference
// lose its fragment (stanford_dragon_100k_blend at 480x270: a fold 0.21 sub-pixels from
// a pixel centre). From the grid point the driver's few roundings move it by a few float ulps
// (a tenth of a sub-pixel at 1920 pixels, 0.03 at 480), which its snap to the nearest
// sub-pixel undoes, so it rasterizes the reference's snapped triangle. Vertices off the
// fixed-point path (behind the eye, outside the guard band) are the driver's to clip and are
// handed as they are.
vec4 snappedClipPosition(vec4 clip, vec2 size) {
    vec3 fb = viewportTransform(clip, size);
    if (!(clip.w > 0.0 && inGuardBand(fb.x) && inGuardBand(fb.y))) {
        return clip;
    }
    vec2 snapped = vec2(snappedCoord(fb.x), snappedCoord(fb.y));
    precise vec2 ndc = snapped / size * 2.0 - 1.0;
    return vec4(ndc * clip.w, clip.z, clip.w);
}

void main() {
    DrawInfo d = g_draws[u_push.drawIndex];
    vec4 world = d.model * vec4(a_position, 1.0);
#ifndef ORDER_ONLY
#ifndef UNLIT
    v_fromEye = world.xyz - u_frame.eye.xyz;
    v_normal = mat3(d.normalMatrix) * a_normal;
#endif
    v_uv = a_uv;
    v_colour = a_colour * d.tint;
#endif
    vec4 clip = clipPosition(modelViewProjection(u_frame.viewProj, d.model), a_position);
    gl_Position = snappedClipPosition(clip, u_frame.viewport.xy);
#ifdef ORDER_DEPTH
    vec3 fb = viewportTransform(clip, u_frame.viewport.xy);
    bool fixedPath = clip.w > 0.0 && clip.z >= 0.0 && inGuardBand(fb.x) && inGuardBand(fb.y);
    v_snapped = fixedPath ? ivec3(int(snapCoord(fb.x)), int(snapCoord(fb.y)), 1) : ivec3(0);
    precise float invW = quotient(1.0, clip.w);
    v_depth = vec2(fb.z, invW);
#endif
}

#endif
