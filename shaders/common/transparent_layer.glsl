// The transparent layer a bin raster leaves on an engine's device for the composite pass
// (bins/composite.*): per pixel, the radiance and transmittance of everything in front of
// the opaque layer, and the stamp of the submission that wrote it. The composite blends it
// onto the engine's colour where it is, so that no full-screen copy goes in or out: out =
// radiance + transmittance x colour. Pixels whose stamp is not the submission's were not
// written by it (no fragment, a skipped block, a row left unfinished) and keep their colour.
#ifndef TRANSLUCID_TRANSPARENT_LAYER_GLSL
#define TRANSLUCID_TRANSPARENT_LAYER_GLSL

#include "colour.glsl"

// 96 bits a pixel, in two images: radiance as three unsigned 16-bit floats with 5 exponent and 11 mantissa bits
// (radiance is not negative; f16's 10 bits cost a wavelet test a decibel), transmittance as
// three 13-bit unorms (finer than halves near 1, where clear surfaces are), and the stamp in
// 6 bits: first = (r | g << 16, b | tr << 16), second = tg | tb << 13 | stamp << 26. Stamps
// run from 1 to LAST_STAMP (interface_bins.glsl); the layer is cleared when they start again.

const uint EXPONENT_REBIAS = (127u - 15u) << 23;

// Rounded to nearest; under 2^-14 (and NaN) is zero. At most 2^16.
uint packRadiance(float v) {
    return v >= 1.0 / 16384.0 ? (floatBitsToUint(v) - EXPONENT_REBIAS + 0x800u) >> 12 : 0u;
}

float unpackRadiance(uint bits) {
    return bits == 0u ? 0.0 : uintBitsToFloat((bits << 12) + EXPONENT_REBIAS);
}

uint packTransmittance(float t) {
    return uint(round(t * 8191.0));
}

float unpackTransmittance(uint bits) {
    return float(bits) / 8191.0;
}

// The blend must stay finite over any colour an f16 target holds, and the composite cannot
// clamp what the blend unit adds: radiance + transmittance x colour <= MAX_COLOUR for any
// colour <= MAX_COLOUR, after both are rounded (by up to 2^-12 of radiance and 2^-14 of
// transmittance). So radiance stays below LAYER_LIMIT and, where there is some,
// transmittance below 1 - radiance / LAYER_LIMIT - 2^-13: that lowers it only for
// fragments of under 2^-13 coverage, or brighter than any display.
const float LAYER_LIMIT = MAX_COLOUR - 128.0;

struct LayerTexel {
    uvec2 first;
    uint second;
};

LayerTexel packTransparentLayer(vec3 radiance, vec3 transmittance, uint stamp) {
    vec3 l = min(radiance, vec3(LAYER_LIMIT));
    vec3 room = mix(vec3(1.0), 1.0 - l / LAYER_LIMIT - 1.0 / 8192.0, greaterThan(l, vec3(0.0)));
    vec3 t = clamp(transmittance, vec3(0.0), max(room, vec3(0.0)));
    LayerTexel texel;
    texel.first = uvec2(packRadiance(l.r) | packRadiance(l.g) << 16,
                        packRadiance(l.b) | packTransmittance(t.r) << 16);
    texel.second = packTransmittance(t.g) | packTransmittance(t.b) << 13 | stamp << 26;
    return texel;
}

// The stamp a texel holds.
uint transparentLayerStamp(LayerTexel texel) {
    return texel.second >> 26;
}

void unpackTransparentLayer(LayerTexel texel, out vec3 radiance, out vec3 transmittance) {
    radiance = vec3(unpackRadiance(texel.first.x & 0xFFFFu), unpackRadiance(texel.first.x >> 16),
                    unpackRadiance(texel.first.y & 0xFFFFu));
    transmittance = vec3(unpackTransmittance(texel.first.y >> 16),
                         unpackTransmittance(texel.second & 0x1FFFu),
                         unpackTransmittance(texel.second >> 13 & 0x1FFFu));
}

#endif
