// Haar-wavelet absorbance, mirroring crates/translucid/src/methods/wavelet/math.rs function
// for function (read its module doc first). Coefficients are RGB per index; on the GPU they
// are packed densely, slot 3*i + channel, four slots per texel of the coefficient images.
// The rank is a compile-time define (one SPIR-V per rank, from the thin front files in
// shaders/wavelet/): every loop has a constant trip count and is unrolled by glslc, so every
// array index below is a constant and nothing is a run-time indexed array. (With the rank as
// a specialization constant, lavapipe kept some loops and the passes took 15-25 % longer.)
#ifndef TRANSLUCID_WAVELET_GLSL
#define TRANSLUCID_WAVELET_GLSL

#extension GL_EXT_control_flow_attributes : require

#ifndef WAVELET_RANK
#error "define WAVELET_RANK (0 to 3) before including wavelet.glsl"
#endif

#include "wavelet_constants.glsl"

const int WAVELET_COUNT = 2 << WAVELET_RANK;
const int WAVELET_SLOTS = 3 * WAVELET_COUNT;
// Texels of coefficient images: ceil(3N / 4).
const int WAVELET_TEXELS = (WAVELET_SLOTS + 3) / 4;
// Texels one accumulate draw writes, at most 8 colour attachments: the rank's texels in
// equal parts (rank 3's 12 in two draws of 6), so that no draw writes an output its render
// pass has no attachment for (methods/wavelet/passes.rs, `draw_texels`).
const int WAVELET_DRAW_TEXELS = WAVELET_TEXELS / ((WAVELET_TEXELS + 7) / 8);
#define WAVELET_MAX_TEXELS 12
#define WAVELET_MAX_COUNT 16
#define WAVELET_MAX_RANK 3
#define WAVELET_MIN_TRANSMITTANCE 1e-5

vec3 waveletAbsorbance(vec3 transmittance) {
    return -log(max(transmittance, vec3(WAVELET_MIN_TRANSMITTANCE)));
}

vec3 waveletTransmittance(vec3 absorbance) {
    return exp(-max(absorbance, vec3(0.0)));
}

float waveletNormalizedDepth(float viewDepth, vec2 bounds) {
    float range = bounds.y - bounds.x;
    return range > 0.0 ? clamp((viewDepth - bounds.x) / range, 0.0, 1.0) : 0.0;
}

float waveletPixelNoise(uvec2 pixel) {
    uint h = (pixel.x * 0x8da6b343u) ^ (pixel.y * 0xd8163841u);
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    h *= 0x846ca68bu;
    h ^= h >> 16;
    return float(h >> 8) * (1.0 / 16777216.0);
}

// Cell-space position of normalized depth v, with the pixel's depth noise when it is on.
float waveletCellPosition(float v, uvec2 pixel) {
    v = clamp(v, 0.0, 1.0);
    float last = float(WAVELET_COUNT - 1);
    float p = v * last;
    if (WAVELET_NOISE > 0.0) {
        float tent = 2.0 * min(v, 1.0 - v);
        p -= clamp(WAVELET_NOISE, 0.0, 0.5 * last) * waveletPixelNoise(pixel) * tent;
    }
    return p;
}

// An event of absorbance a at unit position u adds one addend per wavelet level: to the
// level's wavelet waveletLevelCell (of 2^level), waveletLevelAddend.
float waveletLevelCell(int level, float u) {
    float width = float(1 << level);
    return clamp(floor(u * width), 0.0, width - 1.0);
}

vec3 waveletLevelAddend(int level, float u, vec3 a) {
    float f = u * float(1 << level) - waveletLevelCell(level, u);
    float tent = f < 0.5 ? f : 1.0 - f;
    return -a * (exp2(-0.5 * float(level)) * tent);
}

// Addend of coefficient i for an event of absorbance a at cell position p.
vec3 waveletAddend(int i, float p, vec3 a) {
    float u = p / float(WAVELET_COUNT);
    if (i == 0) {
        return a * (1.0 - u);
    }
    int level = findMSB(i);
    return float(i - (1 << level)) == waveletLevelCell(level, u) ? waveletLevelAddend(level, u, a)
                                                                 : vec3(0.0);
}

// Slot s (channel s % 3 of coefficient s / 3) of an event's addends; 0 past the last.
float waveletAddendSlot(int s, float p, vec3 a) {
    if (s >= WAVELET_SLOTS) {
        return 0.0;
    }
    return waveletAddend(s / 3, p, a)[s % 3];
}

vec4 waveletAddendTexel(int t, float p, vec3 a) {
    return vec4(waveletAddendSlot(4 * t, p, a), waveletAddendSlot(4 * t + 1, p, a),
                waveletAddendSlot(4 * t + 2, p, a), waveletAddendSlot(4 * t + 3, p, a));
}

// The bin raster sums in the order of its lists, which atomics choose anew each frame. So
// every addend it sums is first rounded to a multiple of 2^-16: sums under 2^8 are then
// exact in single precision, the same in any order, and frames repeat. (A coefficient is at
// most the pixel's total absorbance, 11.5 a fragment at most: 22 nearly opaque layers; the
// radiance sum is the light that reaches the eye. A quantum of 2^-14, exact to 2^10, cost
// 2.7 dB on polychrome, 89 to 86 dB, invisible but measurable.)
#define WAVELET_QUANTUM 65536.0
vec3 waveletQuantize(vec3 v) {
    return roundEven(v * WAVELET_QUANTUM) * (1.0 / WAVELET_QUANTUM);
}

// Adds an event of absorbance a at cell position p to coefficients kept in registers (the bin
// raster), quantized: constant indices, a select per coefficient. Written out, not as an
// unrolled loop: glslc's optimizer (shaderc 2023.2, SPIRV-Tools 2022.4) crashes unrolling that
// loop inside the walk that shades.
#define WAVELET_ADD(i, level) \
    if (i < WAVELET_COUNT) c[i] += float(i - (1 << level)) == cell[level] ? value[level] : vec3(0.0)
void waveletAccumulate(inout vec3 c[WAVELET_MAX_COUNT], float p, vec3 a) {
    float u = p / float(WAVELET_COUNT);
    float cell[WAVELET_MAX_RANK + 1];
    vec3 value[WAVELET_MAX_RANK + 1];
    [[unroll]] for (int level = 0; level <= WAVELET_MAX_RANK; level++) {
        cell[level] = level <= WAVELET_RANK ? waveletLevelCell(level, u) : 0.0;
        value[level] = level <= WAVELET_RANK ? waveletQuantize(waveletLevelAddend(level, u, a))
                                             : vec3(0.0);
    }
    c[0] += waveletQuantize(a * (1.0 - u));
    WAVELET_ADD(1, 0);
    WAVELET_ADD(2, 1);
    WAVELET_ADD(3, 1);
    WAVELET_ADD(4, 2);
    WAVELET_ADD(5, 2);
    WAVELET_ADD(6, 2);
    WAVELET_ADD(7, 2);
    WAVELET_ADD(8, 3);
    WAVELET_ADD(9, 3);
    WAVELET_ADD(10, 3);
    WAVELET_ADD(11, 3);
    WAVELET_ADD(12, 3);
    WAVELET_ADD(13, 3);
    WAVELET_ADD(14, 3);
    WAVELET_ADD(15, 3);
}
#undef WAVELET_ADD

// Unpacks texels into coefficients (only the first WAVELET_TEXELS are read).
void waveletUnpack(vec4 texels[WAVELET_MAX_TEXELS], out vec3 c[WAVELET_MAX_COUNT]) {
    [[unroll]] for (int i = 0; i < WAVELET_MAX_COUNT; i++) {
        c[i] = vec3(0.0);
    }
    [[unroll]] for (int i = 0; i < WAVELET_COUNT; i++) {
        [[unroll]] for (int ch = 0; ch < 3; ch++) {
            int s = 3 * i + ch;
            c[i][ch] = texels[s / 4][s % 4];
        }
    }
}

// The inverse Haar transform: cell m = c0 + sum over levels of the signed, scaled wavelet
// coefficient covering it (+ in the first half of the wavelet's support).
void waveletSynthesize(vec3 c[WAVELET_MAX_COUNT], out vec3 cells[WAVELET_MAX_COUNT]) {
    [[unroll]] for (int m = 0; m < WAVELET_MAX_COUNT; m++) {
        cells[m] = vec3(0.0);
    }
    [[unroll]] for (int m = 0; m < WAVELET_COUNT; m++) {
        vec3 v = c[0];
        [[unroll]] for (int level = 0; level <= WAVELET_RANK; level++) {
            int shift = WAVELET_RANK - level;
            int k = m >> (shift + 1);
            float sign = ((m >> shift) & 1) == 0 ? 1.0 : -1.0;
            v += (sign * exp2(0.5 * float(level))) * c[(1 << level) + k];
        }
        cells[m] = v;
    }
}

// Absorbance in front of cell position p, minus the share of the fragment's own event of
// absorbance `own` (pass vec3(0) for none). Cell averages sit at the middles of their cells;
// selects over constant indices pick the two around p.
vec3 waveletAbsorbanceAt(vec3 cells[WAVELET_MAX_COUNT], float p, vec3 own) {
    float last = float(WAVELET_COUNT - 1);
    p = clamp(p, 0.0, last);
    float q = p + 0.5;
    float fm = min(floor(q), last);
    float t = q - fm;
    int m = int(fm);
    vec3 before = vec3(0.0);
    vec3 here = vec3(0.0);
    [[unroll]] for (int i = 0; i < WAVELET_COUNT; i++) {
        before = (i == m - 1) ? cells[i] : before;
        here = (i == m) ? cells[i] : here;
    }
    float ownBefore = clamp(fm - p, 0.0, 1.0);
    float ownHere = clamp(fm + 1.0 - p, 0.0, 1.0);
    vec3 share = own * (ownBefore + (ownHere - ownBefore) * t);
    return max(mix(before, here, t) - share, vec3(0.0));
}

vec3 waveletAbsorbanceBehindAll(vec3 cells[WAVELET_MAX_COUNT]) {
    vec3 last = vec3(0.0);
    [[unroll]] for (int i = 0; i < WAVELET_COUNT; i++) {
        last = cells[i];
    }
    return last;
}

// The cell position from which fragments are hidden: the end of the first cell whose average
// reaches `limit` in every channel; negative if none does before the farthest fragment.
float waveletOpaquePosition(vec3 cells[WAVELET_MAX_COUNT], float limit) {
    float cut = -1.0;
    [[unroll]] for (int k = 0; k < WAVELET_COUNT - 1; k++) {
        bool absorbed = all(greaterThanEqual(cells[k], vec3(limit)));
        cut = (cut < 0.0 && absorbed) ? float(k + 1) : cut;
    }
    return cut;
}

// The device depth from which a pixel's fragments are hidden (every channel absorbed in front
// of them), or 2.0, behind everything, where none is. Noise only moves positions forward, by
// at most WAVELET_NOISE cells: that much is undone so the cut is never in front of the true
// crossing. The cut is at least a cell behind the nearest fragment; where the pixel's depth
// range is too thin for that to be a later depth (one fragment, or all at one depth), every
// fragment sits in cell 0 and none is hidden: mapped back to depth, the cut would fall on them.
// `mapping` is the frame's FrameInfo.depthMapping.
float waveletHiddenDepth(vec3 cells[WAVELET_MAX_COUNT], vec2 bounds, uvec2 pixel, vec4 mapping) {
    float p = waveletOpaquePosition(cells, WAVELET_ABSORBED);
    float last = float(WAVELET_COUNT - 1);
    float slack = clamp(WAVELET_NOISE, 0.0, 0.5 * last) * waveletPixelNoise(pixel);
    float v = min((p + slack) / last, 1.0);
    float view = bounds.x + v * (bounds.y - bounds.x);
    if (p < 0.0 || !(view > bounds.x)) {
        return 2.0;
    }
    return mapping.x - mapping.y / view + mapping.z * view;
}

#endif
