// The body of the wavelet resolve pass; shaders/wavelet/resolve_rank<N>.frag set the rank.
#ifndef TRANSLUCID_WAVELET_RESOLVE_GLSL
#define TRANSLUCID_WAVELET_RESOLVE_GLSL
// Pass 3, full screen: dims the opaque layer by the transmittance behind every transparent
// fragment (MULTIPLY blend into the frame colour) and writes the wavelet depth buffer: the
// opaque depth, or nearer, the depth at which every channel is absorbed. The shading pass
// tests against it, so hidden fragments are rejected before they are shaded.

#include "interface_scene.glsl"
#define WAVELET_READ_SET 1
#include "wavelet_read.glsl"

// Set 0 is the scene's (only its frame constants are read here); the read set is the
// resolve's, with the opaque depth.
#include "interface_scene_set.glsl"
#include "interface_wavelet_resolve.glsl"

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

    gl_FragDepth = min(depth, waveletHiddenDepth(cells, b, uvec2(pixel), u_frame.depthMapping));
}

#endif
