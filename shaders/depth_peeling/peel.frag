#version 450
// One pass of dual depth peeling: the fragments at the nearest depth the previous pass left
// go into the front layer, those at the farthest into the back layer, and the rest widen the
// range for the next pass. A fragment outside the previous range was peeled before and adds
// nothing. Nothing is discarded: a neutral output (the range's clear value, no radiance,
// full transmittance) leaves every blend unchanged, and shading runs in uniform control flow,
// so texture derivatives stay defined.
//
// Blends: range MAX; radiance summed; transmittance multiplied. Fragments at one depth in a
// pixel (coplanar surfaces) are one layer, summed without covering one another.

#define ORDER_DEPTH
#include "mesh_fragment.glsl"
#include "shading.glsl"
#include "depth_peeling.glsl"

layout(early_fragment_tests) in;

// The range the previous pass left.
layout(set = 2, binding = 0) uniform sampler2D u_previous;

layout(location = 0) out vec2 o_range;
layout(location = 1) out vec4 o_frontRadiance;
layout(location = 2) out vec4 o_frontTransmittance;
layout(location = 3) out vec4 o_backRadiance;
layout(location = 4) out vec4 o_backTransmittance;

void main() {
    DrawInfo d = g_draws[u_push.drawIndex];
    Material m = g_materials[d.materialIndex];
    vec3 radiance;
    vec3 transmittance;
    shadeTransparent(m, u_frame, v_colour, sampleBaseTexture(m), fragmentNormal(d), radiance,
                     transmittance);

    float depth = fragmentOrderDepth();
    vec2 previous = texelFetch(u_previous, ivec2(gl_FragCoord.xy), 0).xy;
    float near = -previous.x;
    float far = previous.y;
    bool front = depth == near;
    bool back = !front && depth == far;
    bool left = depth > near && depth < far;

    o_range = left ? vec2(-depth, depth) : NO_RANGE;
    o_frontRadiance = vec4(front ? radiance : vec3(0.0), 0.0);
    o_frontTransmittance = vec4(front ? transmittance : vec3(1.0), 1.0);
    o_backRadiance = vec4(back ? radiance : vec3(0.0), 0.0);
    o_backTransmittance = vec4(back ? transmittance : vec3(1.0), 1.0);
}
