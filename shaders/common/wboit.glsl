// Weighted blended OIT (McGuire and Bavoil 2013), per colour channel; mirrors
// crates/translucid/src/methods/wboit/model.rs.
#ifndef TRANSLUCID_WBOIT_GLSL
#define TRANSLUCID_WBOIT_GLSL

// The weight of a fragment with per-channel opacity `alpha` at device depth `z` (0 near, 1
// far): the paper's equation (10), alpha * max(1e-2, 3e3 * (1 - z)^3), with the largest
// channel's opacity as alpha. Depth-scale free, unlike its view-distance variants.
float wboitWeight(vec3 alpha, float z) {
    float a = max(alpha.r, max(alpha.g, alpha.b));
    float near = 1.0 - z;
    return a * max(1e-2, 3e3 * near * near * near);
}

// Below this summed weighted opacity a channel has no transparent contribution.
#define WBOIT_MIN_OPACITY 1e-5
// Transmittance clamp before the logarithm: a fully absorbing layer passes 1e-5.
#define WBOIT_MIN_TRANSMITTANCE 1e-5

#endif
