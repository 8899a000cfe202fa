// The mesh pipelines' vertex stage (scene/mesh.vert, scene/ordered.vert). The clip position
// is the CPU reference's, operation for operation (raster_rules.glsl), so that the driver
// rasterizes the triangles the reference does. With ORDER_DEPTH defined it also hands
// scene/ordered.geom what the reference's order depth needs of the vertex.
#ifndef TRANSLUCID_MESH_VERTEX_GLSL
#define TRANSLUCID_MESH_VERTEX_GLSL

#include "scene_bindings.glsl"
#include "raster_rules.glsl"

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec4 a_colour;

layout(location = 0) out vec3 v_fromEye;       // world position minus the eye
layout(location = 1) out vec3 v_normal;
layout(location = 2) out vec2 v_uv;
layout(location = 3) out vec4 v_colour;
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

void main() {
    DrawInfo d = g_draws[u_push.drawIndex];
    vec4 world = d.model * vec4(a_position, 1.0);
    v_fromEye = world.xyz - u_frame.eye.xyz;
    v_normal = mat3(d.normalMatrix) * a_normal;
    v_uv = a_uv;
    v_colour = a_colour * d.tint;
    vec4 clip = clipPosition(modelViewProjection(u_frame.viewProj, d.model), a_position);
    gl_Position = clip;
#ifdef ORDER_DEPTH
    vec3 fb = viewportTransform(clip, u_frame.viewport.xy);
    bool fixedPath = clip.w > 0.0 && clip.z >= 0.0 && inGuardBand(fb.x) && inGuardBand(fb.y);
    v_snapped = fixedPath ? ivec3(int(snapCoord(fb.x)), int(snapCoord(fb.y)), 1) : ivec3(0);
    precise float invW = 1.0 / clip.w;
    v_depth = vec2(fb.z, invW);
#endif
}

#endif
