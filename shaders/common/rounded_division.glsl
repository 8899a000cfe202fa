// Quotients as the CPU reference rounds them. Vulkan lets a division be 2.5 ulp off (CPU
// drivers divide exactly; GPUs use a reciprocal estimate), and a depth, a snapped vertex or
// an order key one ulp away from the reference's can cover, order or blend differently.
// With ROUNDED_DIVISION (the GPU profile) every such quotient is corrected to the nearest
// float, ties to even, by comparing it with the exact quotient in 64-bit integers.
#ifndef TRANSLUCID_ROUNDED_DIVISION_GLSL
#define TRANSLUCID_ROUNDED_DIVISION_GLSL

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

#include "interface_specialization.glsl"

bool normalBits(uint magnitude) {
    return magnitude >= 0x00800000u && magnitude < 0x7F800000u;
}

// The 24-bit significand of a normal float's magnitude bits.
uint significandOf(uint magnitude) {
    return (magnitude & 0x007FFFFFu) | 0x00800000u;
}

// Where a correction step leaves q: the quotient, or moved one ulp towards it, or given up
// (the estimate stands).
const uint QUOTIENT_FOUND = 0u;
const uint QUOTIENT_MOVED = 1u;
const uint QUOTIENT_UNSURE = 2u;

// One step of roundedQuotient: q (magnitude bits) checked against the midpoints to its
// neighbours and moved one ulp towards a / b, where a and b have significands ma and mb and
// exponents that differ by `exponents`.
uint quotientStep(uint64_t ma, uint64_t mb, int exponents, inout uint q) {
    if (!normalBits(q)) {
        return QUOTIENT_UNSURE;
    }
    uint mq = significandOf(q);
    // With a = ma 2^(ea-150), b = mb 2^(eb-150) and q = mq 2^(eq-150), the midpoints between
    // q and its neighbours, times 4b, are mb (4 mq + 2) above and mb (4 mq - 2) below (- 1
    // when q is a power of two: the ulp below it is half as wide); 4a is ma 2^shift on the
    // same scale.
    int shift = exponents - int(q >> 23) + 152;
    if (shift < 0 || shift > 39) {
        return QUOTIENT_UNSURE;
    }
    uint64_t scaled = ma << shift;
    uint64_t above = mb * uint64_t(4u * mq + 2u);
    uint64_t below = mb * uint64_t(4u * mq - (mq == 0x00800000u ? 1u : 2u));
    bool odd = (mq & 1u) != 0u;
    if (scaled > above || (scaled == above && odd)) {
        q += 1u;
        return QUOTIENT_MOVED;
    }
    if (scaled < below || (scaled == below && odd)) {
        q -= 1u;
        return QUOTIENT_MOVED;
    }
    return QUOTIENT_FOUND;
}

// a / b rounded to nearest, ties to even, from `estimate`, a quotient a few ulps off. Exact
// for normal a, b and quotient; a zero a gives a signed zero, anything else (zeros,
// subnormals, infinities, NaN, an estimate far off) keeps the estimate.
float roundedQuotient(float a, float b, float estimate) {
    uint ua = floatBitsToUint(a);
    uint ub = floatBitsToUint(b);
    uint sign = (ua ^ ub) & 0x80000000u;
    ua &= 0x7FFFFFFFu;
    ub &= 0x7FFFFFFFu;
    if (ua == 0u && normalBits(ub)) {
        return uintBitsToFloat(sign);
    }
    if (!normalBits(ua) || !normalBits(ub)) {
        return estimate;
    }
    uint64_t ma = uint64_t(significandOf(ua));
    uint64_t mb = uint64_t(significandOf(ub));
    int exponents = int(ua >> 23) - int(ub >> 23);
    uint q = floatBitsToUint(estimate) & 0x7FFFFFFFu;
    // A conforming estimate needs at most 3 steps; the fourth confirms. Written out, not a
    // loop: the rasters count their loops' iterations against CPU drivers' loop limit, and
    // a division inside a walk would add uncounted ones.
    uint state = quotientStep(ma, mb, exponents, q);
    if (state == QUOTIENT_MOVED) {
        state = quotientStep(ma, mb, exponents, q);
    }
    if (state == QUOTIENT_MOVED) {
        state = quotientStep(ma, mb, exponents, q);
    }
    if (state == QUOTIENT_MOVED) {
        state = quotientStep(ma, mb, exponents, q);
    }
    return state == QUOTIENT_FOUND ? uintBitsToFloat(sign | q) : estimate;
}

// a / b as the reference computes it (Rust's `/`, correctly rounded) where ROUNDED_DIVISION
// is on, and the device's division elsewhere.
float quotient(float a, float b) {
    float estimate = a / b;
    return ROUNDED_DIVISION ? roundedQuotient(a, b, estimate) : estimate;
}

#endif
