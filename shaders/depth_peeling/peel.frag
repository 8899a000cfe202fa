#version 450
// One pass of dual depth peeling: the fragments at the nearest depth the previous pass left
// go into the front layer, those at the farthest into the back layer, and the rest widen the
// range for the next pass. A fragment outside the previous range was peeled before and adds
// nothing. Nothing is discarded: a neutral output (the range's clear value, no radiance,
// full transmittance) leaves every blend unchanged, and shading runs in uniform control flow,
// so texture derivatives stay defined.
//
// Blends: range MAX; each layer is one image per colour channel, (radiance, 0, 0,
// transmittance), composited front to back in the order the fragments arrive (UNDER). The
// driver blends in submission order, so fragments at one depth in a pixel (coplanar
// surfaces) cover one another as the reference orders them: the first drawn nearer.

#define ORDER_DEPTH
#include "mesh_fragment.glsl"
#include "shading.glsl"
#include "depth_peeling.glsl"

layout(early_fragment_tests) in;

// The range the previous pass left (u_previous).
#include "interface_depth_peeling_peel.glsl"

layout(location = 0) out vec2 o_range;
layout(location = 1) out vec4 o_frontRed;
layout(location = 2) out vec4 o_frontGreen;
layout(location = 3) out vec4 o_frontBlue;
layout(location = 4) out vec4 o_backRed;
layout(location = 5) out vec4 o_backGreen;
layout(location = 6) out vec4 o_backBlue;

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
    // Neutral where the fragment is not in the layer: no radiance, full transmittance.
    vec3 frontL = front ? radiance : vec3(0.0);
    vec3 frontT = front ? transmittance : vec3(1.0);
    vec3 backL = back ? radiance : vec3(0.0);
    vec3 backT = back ? transmittance : vec3(1.0);
    o_frontRed = vec4(frontL.r, 0.0, 0.0, frontT.r);
    o_frontGreen = vec4(frontL.g, 0.0, 0.0, frontT.g);
    o_frontBlue = vec4(frontL.b, 0.0, 0.0, frontT.b);
    o_backRed = vec4(backL.r, 0.0, 0.0, backT.r);
    o_backGreen = vec4(backL.g, 0.0, 0.0, backT.g);
    o_backBlue = vec4(backL.b, 0.0, 0.0, backT.b);
}
