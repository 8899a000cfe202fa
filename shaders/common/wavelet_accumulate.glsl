// The body of the wavelet accumulate pass; shaders/wavelet/accumulate_rank<N>.frag set the rank.
#ifndef TRANSLUCID_WAVELET_ACCUMULATE_GLSL
#define TRANSLUCID_WAVELET_ACCUMULATE_GLSL
// Pass 2, transmittance: each fragment adds its absorbance -ln T, projected onto the Haar
// basis, into the coefficient images by an ADD blend. One draw of the scene writes
// WAVELET_DRAW_TEXELS texels (colour attachments, 8 at most); rank 3 needs 12, so it draws
// twice, 6 each, starting at WAVELET_FIRST_TEXEL. Every output is written: zero where the
// event adds nothing.

#include "wavelet_fragment.glsl"
#include "shading.glsl"
#include "wavelet.glsl"

#include "interface_wavelet_bounds.glsl"

layout(location = 0) out vec4 o_texels[WAVELET_DRAW_TEXELS];

void main() {
    DrawInfo d = g_draws[u_push.drawIndex];
    Material m = g_materials[d.materialIndex];
    vec3 radiance;
    vec3 transmittance;
    shadeTransparent(m, u_frame, v_colour, sampleBaseTextureAnalytic(m), fragmentNormal(d), radiance,
                     transmittance);
    vec2 b = texelFetch(u_waveletBounds, ivec2(gl_FragCoord.xy), 0).xy;
    float v = waveletNormalizedDepth(waveletFragmentDepth(), vec2(-b.x, b.y));
    float p = waveletCellPosition(v, uvec2(gl_FragCoord.xy));
    vec3 a = waveletAbsorbance(transmittance);
    [[unroll]] for (int k = 0; k < WAVELET_DRAW_TEXELS; k++) {
        o_texels[k] = waveletAddendTexel(WAVELET_FIRST_TEXEL + k, p, a);
    }
}

#endif
