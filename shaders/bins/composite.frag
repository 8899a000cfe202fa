#version 450
// Blends a pixel's transparent layer onto the colour with dual-source blending
// (dst = radiance + transmittance x dst), where this submission wrote one; every other pixel
// is left exactly as it is.

#include "composite.glsl"

layout(location = 0, index = 0) out vec4 o_radiance;
layout(location = 0, index = 1) out vec4 o_transmittance;

void main() {
    // The layer holds the frame from its own corner; the colour image from the frame's.
    ivec2 pixel = ivec2(gl_FragCoord.xy) - ivec2(u_push.originX, u_push.originY);
    LayerTexel texel;
    texel.second = imageLoad(u_transparentLayerStamps, pixel).x;
    if (transparentLayerStamp(texel) != u_push.stamp) {
        discard;
    }
    texel.first = imageLoad(u_transparentLayer, pixel).xy;
    vec3 radiance;
    vec3 transmittance;
    unpackTransparentLayer(texel, radiance, transmittance);
    o_radiance = vec4(radiance, 0.0);
    o_transmittance = vec4(transmittance, 1.0);
}
