#version 450
// Pass 1, depth bounds: each pixel's nearest and farthest transparent order depth, kept by a
// MAX blend as (-depth, depth).

#include "scene_bindings.glsl"
#include "wavelet_constants.glsl"

layout(location = 0) out vec2 o_bounds;

void main() {
    float viewDepth = WAVELET_FRAGMENT_DEPTH(u_frame.depthMapping);
    o_bounds = vec2(-viewDepth, viewDepth);
}
