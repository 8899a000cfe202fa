// Reading a pixel's wavelet data: depth bounds and coefficient images, bound at set
// WAVELET_READ_SET (binding 0: bounds, binding 1: the coefficient images; slots past the
// rank's texel count hold any valid image and are never read).
#ifndef TRANSLUCID_WAVELET_READ_GLSL
#define TRANSLUCID_WAVELET_READ_GLSL

#ifndef WAVELET_READ_SET
#error "define WAVELET_READ_SET (the descriptor set of the wavelet images) before including"
#endif

#include "wavelet.glsl"

#include "interface_wavelet_read.glsl"

// (nearest, farthest) view depth of the pixel's transparent fragments. The bounds image holds
// (-nearest, farthest) so that one MAX blend keeps both.
vec2 waveletBounds(ivec2 pixel) {
    vec2 b = texelFetch(u_waveletBounds, pixel, 0).xy;
    return vec2(-b.x, b.y);
}

// Array indices must be constants here (sampler arrays are not dynamically indexable on
// every device), hence one line per texel; the rank's specialization removes the rest.
#define WAVELET_FETCH(t) \
    texels[t] = (t < WAVELET_TEXELS) ? texelFetch(u_waveletCoefficients[t], pixel, 0) : vec4(0.0)

void waveletLoadCells(ivec2 pixel, out vec3 cells[WAVELET_MAX_COUNT]) {
    vec4 texels[WAVELET_MAX_TEXELS];
    WAVELET_FETCH(0);
    WAVELET_FETCH(1);
    WAVELET_FETCH(2);
    WAVELET_FETCH(3);
    WAVELET_FETCH(4);
    WAVELET_FETCH(5);
    WAVELET_FETCH(6);
    WAVELET_FETCH(7);
    WAVELET_FETCH(8);
    WAVELET_FETCH(9);
    WAVELET_FETCH(10);
    WAVELET_FETCH(11);
    vec3 c[WAVELET_MAX_COUNT];
    waveletUnpack(texels, c);
    waveletSynthesize(c, cells);
}

#endif
