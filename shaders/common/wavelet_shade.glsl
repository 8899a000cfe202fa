// The body of the wavelet shade pass; shaders/wavelet/shade_rank<N>.frag set the rank.
#ifndef TRANSLUCID_WAVELET_SHADE_GLSL
#define TRANSLUCID_WAVELET_SHADE_GLSL
// Pass 4, shading: every visible fragment adds its radiance times the transmittance in front
// of it (its own share removed) to the frame colour, by an ADD blend. Depth-tested against the
// wavelet depth buffer, so fragments behind full absorption never run this shader.

#include "wavelet_fragment.glsl"
#include "shading.glsl"
#define WAVELET_READ_SET 2
#include "wavelet_read.glsl"

layout(location = 0) out vec4 o_radiance;

void main() {
    DrawInfo d = g_draws[u_push.drawIndex];
    Material m = g_materials[d.materialIndex];
    vec3 radiance;
    vec3 transmittance;
    shadeTransparent(m, u_frame, v_colour, sampleBaseTextureAnalytic(m), fragmentNormal(d), radiance,
                     transmittance);
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec3 cells[WAVELET_MAX_COUNT];
    waveletLoadCells(pixel, cells);
    float v = waveletNormalizedDepth(waveletFragmentDepth(),
                                     waveletBounds(pixel));
    float p = waveletCellPosition(v, uvec2(pixel));
    vec3 inFront = waveletAbsorbanceAt(cells, p, waveletAbsorbance(transmittance));
    o_radiance = vec4(radiance * waveletTransmittance(inFront), 0.0);
}

#endif
