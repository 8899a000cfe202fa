#version 450
// An engine's depth image that cannot be copied as it is, sampled into translucid's depth
// target (D32_SFLOAT, 0 near, 1 far): reversed-Z turned around, other formats widened. One
// full-screen triangle, depth written always, no colour.

#include "interface_specialization.glsl"

#include "interface_depth_import.glsl"

layout(push_constant) uniform DepthImportPushBlock { DepthImportPush u_push; };

void main() {
    // The target holds the frame from its own corner; the engine's image from the frame's.
    ivec2 pixel = ivec2(gl_FragCoord.xy) + ivec2(u_push.originX, u_push.originY);
    float depth = texelFetch(u_engineDepth, pixel, 0).x;
    gl_FragDepth = IMPORTED_DEPTH_REVERSED ? 1.0 - depth : depth;
}
