// The body of the wavelet resolve pass; shaders/wavelet/resolve_rank<N>.frag set the rank.
#ifndef TRANSLUCID_WAVELET_RESOLVE_GLSL
#define TRANSLUCID_WAVELET_RESOLVE_GLSL
// Pass 3, full screen: dims the opaque layer by the transmittance behind every transparent
// fragment (MULTIPLY blend into the frame colour) and writes the wavelet depth buffer: the
// opaque depth, or nearer, the depth at which every channel is absorbed. The shading pass
// tests against it, so hidden fragments are rejected before they are shaded.

#define WAVELET_READ_SET 0
#include "wavelet_read.glsl"

layout(set = 0, binding = 2) uniform sampler2D u_opaqueDepth;

layout(location = 0) out vec4 o_transmittance;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    float depth = texelFetch(u_opaqueDepth, pixel, 0).x;
    vec2 b = waveletBounds(pixel);
    if (b.y < b.x) {
        // No transparent fragment: nothing to dim or hide, no coefficients to read (most of
        // the screen in many scenes). Lavapipe runs both sides of a branch, so it gains
        // nothing there (measured); devices that branch skip the reads.
        o_transmittance = vec4(1.0);
        gl_FragDepth = depth;
        return;
    }
    vec3 cells[WAVELET_MAX_COUNT];
    waveletLoadCells(pixel, cells);
    o_transmittance = vec4(waveletTransmittance(waveletAbsorbanceBehindAll(cells)), 1.0);

    float p = waveletOpaquePosition(cells, WAVELET_ABSORBED);
    if (p >= 0.0) {
        // Noise only moves positions forward, by at most WAVELET_NOISE * noise cells: undo
        // that much so the cut is never in front of the true crossing.
        float last = float(WAVELET_COUNT - 1);
        float slack = clamp(WAVELET_NOISE, 0.0, 0.5 * last) * waveletPixelNoise(uvec2(pixel));
        float v = min((p + slack) / last, 1.0);
        float viewDepth = b.x + v * (b.y - b.x);
        depth = min(depth, DEPTH_A - DEPTH_B / viewDepth);
    }
    gl_FragDepth = depth;
}

#endif
