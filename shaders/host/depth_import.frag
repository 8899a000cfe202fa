#version 450
// An engine's depth image that cannot be copied as it is, sampled into translucid's depth
// target (D32_SFLOAT, 0 near, 1 far): reversed-Z turned around, other formats widened. One
// full-screen triangle, depth written always, no colour.

#include "interface_specialization.glsl"

#include "interface_depth_import.glsl"

void main() {
    float depth = texelFetch(u_engineDepth, ivec2(gl_FragCoord.xy), 0).x;
    gl_FragDepth = IMPORTED_DEPTH_REVERSED ? 1.0 - depth : depth;
}
