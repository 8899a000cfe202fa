// The body of the wavelet bounds pass; shaders/wavelet/bounds*.frag pick the order depth.
#ifndef TRANSLUCID_WAVELET_BOUNDS_GLSL
#define TRANSLUCID_WAVELET_BOUNDS_GLSL
// Pass 1, depth bounds: each pixel's nearest and farthest transparent order depth, kept by a
// MAX blend as (-depth, depth).

#include "wavelet_fragment.glsl"

layout(location = 0) out vec2 o_bounds;

void main() {
    float viewDepth = waveletFragmentDepth();
    o_bounds = vec2(-viewDepth, viewDepth);
}

#endif
