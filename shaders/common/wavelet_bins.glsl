// The body of the wavelet bin raster; shaders/wavelet/bins_rank<N>.comp set the rank.
#ifndef TRANSLUCID_WAVELET_BINS_GLSL
#define TRANSLUCID_WAVELET_BINS_GLSL
// The wavelet method on the bins (shaders/bins/, which exact's raster reads too), with each
// pixel's coefficients in registers instead of full-screen images. It runs per band, as
// exact's raster does, one invocation per pixel and tiles (a subgroup each) that walk their
// tile's list in step (raster.comp says why a subgroup must see one tile; "row" below is the
// tile). Three walks over the list:
// 1. bounds: the nearest and farthest order depth of the pixel's fragments;
// 2. transmittance: each fragment adds its absorbance's Haar coefficients;
// 3. shading: each fragment in front of full absorption adds its radiance times the
//    transmittance in front of it, its own share removed;
// then what the fragments added, and the transmittance behind every fragment, which dims
// the opaque colour, are written once (writePixel). Rows whose pixels all have at most KEPT fragments keep
// their triangles from walk 1 (in registers), and walks 2 and 3 visit those instead of the
// list: a pixel's own fragments, not every triangle of the row. The loop budget applies on
// every device, and to every row of a scene with any texture (TEXTURES is per scene).
// Coverage, sampling and shading are exact's, so a pixel's fragments are the CPU
// reference's, and the math is wavelet.glsl's, as in the image passes.
// Rows whose walks would pass the driver's loop budget are reported (OVERFLOW_CROWDED_BIN):
// unlike exact's raster, a row's state (its coefficients) is not saved for a continuation.

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_EXT_control_flow_attributes : require

#include "scene_bindings_compute.glsl"
#include "bins_bindings.glsl"
#include "raster.glsl"
#include "bin_lists.glsl"
#include "raster_tile.glsl"
#include "texture_sampler.glsl"
#include "shading.glsl"
#include "bin_fragment.glsl"
#include "wavelet.glsl"

// Fragments a pixel keeps from walk 1 for the short form of walks 2 and 3.
const int KEPT = 8;

// The triangle of list entry e (walkedEntry) is the same for the whole row (not broadcast:
// raster.comp says why). The walks fetch the next step's entry a step ahead, as raster.comp
// does, with the index clamped to the list's last entry.

// The triangle of visit i of walks 2 and 3: kept slot i in the short form, else list entry
// first + i (selects over constant indices: a run-time index would put the slots in memory).
uint visitTriangle(bool shortForm, uint keptTri[KEPT], uint i, uint first, uint last) {
    uint kept = keptTri[0];
    [[unroll]] for (int k = 1; k < KEPT; k++) {
        kept = uint(k) == i ? keptTri[k] : kept;
    }
    return shortForm ? kept : walkedEntry(first + i, last);
}

void main() {
    // Loads first, outside all control flow (raster.comp says why).
    FrameInfo frame = u_frame;
    uint block = g_rasterBins[g_counters.bandFirst + linearWorkGroup()];
    // As raster.comp: groupRows() rows of a block per workgroup, a bin a tile.
    uint row = gl_WorkGroupID.y * groupRows() + laneRow();
    uint tile = row >> TILE_SHIFT;
    uint bin = (block * TILES_PER_BLOCK + tile) * SLABS;
    uint first = binStart(block, tile, bin);
    uint end = g_binEnds[bin + SLABS - 1u];
    uint lastEntry = max(end, 1u) - 1u;
    uint x = (block % u_push.binsX) * BIN_SIZE + laneColumn();
    uint y = (block / u_push.binsX) * BIN_SIZE + row;
    if (x >= u_push.width || y >= u_push.height) {
        return;
    }
    // Loop iterations per entry: walk 1, and walks 2 and 3 with their shading (the software
    // sampler's mip loops), counted generously.
    uint perEntry = 1u + 2u * (TEXTURES ? 41u : 1u);
    if (end - first > (LOOP_BUDGET - 16u) / perEntry) {
        if (subgroupElect()) {
            atomicOr(g_counters.overflow, OVERFLOW_CROWDED_BIN);
        }
        return;
    }
    float opaqueDepth = opaqueDepthAt(ivec2(x, y));
    uvec2 pixel = uvec2(x, y);

    // Walk 1: bounds, and the triangles of the last KEPT fragments (all of them where there
    // are at most KEPT; newest in slot 0).
    float nearest = uintBitsToFloat(0x7F800000u);
    float farthest = 0.0;
    uint fragments = 0u;
    uint keptTri[KEPT];
    [[unroll]] for (int k = 0; k < KEPT; k++) {
        keptTri[k] = 0u;
    }
    uint nextTri = walkedEntry(first, lastEntry);
    // Do-whiles throughout: raster.comp says why.
    uint e = first;
    if (e < end) do {
        uint ti = nextTri;
        nextTri = walkedEntry(e + 1u, lastEntry);
        RasterSample s;
        bool take = coverSample(loadWalkedTriangle(ti), x, y, s) && s.zNdc < opaqueDepth;
        nearest = take ? min(nearest, s.viewDepth) : nearest;
        farthest = take ? max(farthest, s.viewDepth) : farthest;
        fragments += take ? 1u : 0u;
        [[unroll]] for (int k = KEPT - 1; k > 0; k--) {
            keptTri[k] = take ? keptTri[k - 1] : keptTri[k];
        }
        keptTri[0] = take ? ti : keptTri[0];
    } while (++e < end);
    if (subgroupAll(fragments == 0u)) {
        return;
    }
    vec2 bounds = vec2(nearest, farthest);
    // Walks 2 and 3 visit the row's list, or, when every pixel of the row kept all its
    // fragments, each pixel's kept triangles (each covered once). One loop serves both, so
    // that a row runs each walk's body once at least, not twice (a loop's body always runs).
    bool shortForm = subgroupAll(fragments <= uint(KEPT));
    uint visits = shortForm ? fragments : end - first;

    // Walk 2: transmittance, as coefficients.
    vec3 c[WAVELET_MAX_COUNT];
    [[unroll]] for (int i = 0; i < WAVELET_MAX_COUNT; i++) {
        c[i] = vec3(0.0);
    }
    nextTri = visitTriangle(shortForm, keptTri, 0u, first, lastEntry);
    uint i = 0u;
    if (i < visits) do {
        uint ti = nextTri;
        nextTri = visitTriangle(shortForm, keptTri, i + 1u, first, lastEntry);
        BinTriangle t = loadTriangle(ti);
        RasterSample s;
        bool take = coverSample(t, x, y, s) && s.zNdc < opaqueDepth;
        vec3 a = vec3(0.0);
        if (take) {
            vec3 l;
            vec3 tr;
            shadeFragment(t, x, y, s, frame, l, tr);
            a = waveletAbsorbance(tr);
        }
        float p = waveletCellPosition(waveletNormalizedDepth(s.viewDepth, bounds), pixel);
        waveletAccumulate(c, take ? p : 0.0, a);
    } while (++i < visits);
    vec3 cells[WAVELET_MAX_COUNT];
    waveletSynthesize(c, cells);

    // What reaches the opaque layer behind every fragment, and the depth from which nothing
    // is visible.
    vec3 throughAll = waveletTransmittance(waveletAbsorbanceBehindAll(cells));
    float cut = waveletHiddenDepth(cells, bounds, pixel, u_frame.depthMapping);

    // Walk 3: shading. The fragments' share is summed apart from the opaque colour, so that
    // the sum of quantized addends stays exact.
    vec3 lit = vec3(0.0);
    nextTri = visitTriangle(shortForm, keptTri, 0u, first, lastEntry);
    i = 0u;
    if (i < visits) do {
        uint ti = nextTri;
        nextTri = visitTriangle(shortForm, keptTri, i + 1u, first, lastEntry);
        BinTriangle t = loadTriangle(ti);
        RasterSample s;
        bool take = coverSample(t, x, y, s) && s.zNdc < opaqueDepth && s.zNdc < cut;
        if (take) {
            vec3 l;
            vec3 tr;
            shadeFragment(t, x, y, s, frame, l, tr);
            float p = waveletCellPosition(waveletNormalizedDepth(s.viewDepth, bounds), pixel);
            vec3 inFront = waveletAbsorbanceAt(cells, p, waveletAbsorbance(tr));
            lit += waveletQuantize(l * waveletTransmittance(inFront));
        }
    } while (++i < visits);
    if (fragments > 0u) {
        writePixel(ivec2(x, y), lit, throughAll);
    }
    // Statistics: one atomic per subgroup, in the workgroup's slot (interface_bins.glsl); there
    // are no passes to count.
    uint subgroupFragments = subgroupAdd(fragments);
    if (subgroupElect()) {
        atomicAdd(g_counters.statistics[(gl_WorkGroupID.x % STATISTICS_SLOTS) * 16u],
                  subgroupFragments);
    }
}

#endif
