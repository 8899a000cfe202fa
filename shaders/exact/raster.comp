#version 450
// Bin raster: one workgroup per 16x16 bin, one invocation per pixel, no shared memory and no
// barriers (both are slow on CPU drivers such as lavapipe; see DESIGN.md).
//
// Each pixel selects, in one pass over its bin's triangles, the SELECT_SIZE nearest fragments
// behind the last one it composited, keeping them sorted in registers with a fully unrolled
// insertion (constant indices only); shades and composites them front to back; and repeats
// until no fragment is left or transmittance is under the threshold. All invocations walk
// the bin's list in step, so triangle records are read once per subgroup, not per pixel.
// (Shading inside the walk, with shaded colours in the selection, measured 1.5-9x slower on
// lavapipe: the larger selection spills registers.) Order is exact by construction:
// fragments are ranked by (view depth, draw, quad, triangle) like the CPU reference, so no
// pixel is ever left out of order and no fallback is needed.

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_EXT_control_flow_attributes : require

#include "scene_bindings_compute.glsl"
#include "exact_bindings.glsl"
#include "raster.glsl"
#include "texture_sampler.glsl"
#include "shading.glsl"

// Fragments selected per pass. Larger means fewer passes over the bin for deep pixels but
// more live registers per invocation; on lavapipe 4 measured as fast as 8 on spheres and
// faster on layers (8 deep), so the register file wins.
#ifndef SELECT_SIZE
#define SELECT_SIZE 4
#endif

layout(local_size_x = BIN_SIZE, local_size_y = BIN_SIZE) in;

// What the scene needs, fixed when the pipeline is made. CPU drivers such as lavapipe run
// both sides of a divergent `if` under a mask, so code a scene cannot reach still costs on
// every fragment there; constants compile it away. The host sets them from the scene and
// falls back to the full shader if setup ever reports a triangle the constants excluded.
layout(constant_id = 0) const bool HOMOGENEOUS_PATH = true;  // near-plane / guard-band triangles
layout(constant_id = 1) const bool TEXTURES = true;          // some material has a texture
layout(constant_id = 2) const bool VERTEX_NORMALS = true;    // some draw has vertex normals
layout(constant_id = 3) const bool FACE_NORMALS = true;      // some draw has none

bool sampleTriangle(ExactTriangle t, uint x, uint y, out RasterSample s) {
    if (!HOMOGENEOUS_PATH || t.edgeB.w < 0) {
        return sampleFixed(t, x, y, s);
    }
    return sampleHomogeneous(loadHomogeneous(t.edgeB.w), x, y, s);
}

// d(barycentric)/dx and /dy at the pixel, as Triangle::barycentric_gradients computes them.
void barycentricGradients(ExactTriangle t, uint x, uint y, out vec3 gx, out vec3 gy) {
    dvec3 q;
    dvec3 dqx;
    dvec3 dqy;
    if (!HOMOGENEOUS_PATH || t.edgeB.w < 0) {
        [[unroll]] for (int k = 0; k < 3; k++) {
            int64_t e = edgeAt(int64_t(t.edgeA[k]), int64_t(t.edgeB[k]), t.edgeC[k], x, y);
            precise float lambda = float(e) * t.zNdc.w;
            precise float qk = lambda * t.invW[k];
            precise float dx = float(t.edgeA[k]) * 256.0 * t.zNdc.w * t.invW[k];
            precise float dy = float(t.edgeB[k]) * 256.0 * t.zNdc.w * t.invW[k];
            q[k] = double(qk);
            dqx[k] = double(dx);
            dqy[k] = double(dy);
        }
    } else {
        ExactHomogeneous h = loadHomogeneous(t.edgeB.w);
        precise dvec3 qq = dvec3(lineAt(h.line0, x, y), lineAt(h.line1, x, y), lineAt(h.line2, x, y)) *
                           h.zInvDet.w;
        q = qq;
        precise dvec3 ax = dvec3(h.line0.x, h.line1.x, h.line2.x) * h.zInvDet.w;
        precise dvec3 ay = dvec3(h.line0.y, h.line1.y, h.line2.y) * h.zInvDet.w;
        dqx = ax;
        dqy = ay;
    }
    precise double sum = (q.x + q.y) + q.z;
    if (sum == 0.0) {
        gx = vec3(0.0);
        gy = vec3(0.0);
        return;
    }
    precise dvec3 b = q / sum;
    precise double dsx = (dqx.x + dqx.y) + dqx.z;
    precise double dsy = (dqy.x + dqy.y) + dqy.z;
    precise dvec3 rx = (dqx - b * dsx) / sum;
    precise dvec3 ry = (dqy - b * dsy) / sum;
    gx = vec3(rx);
    gy = vec3(ry);
}

// Shades the fragment of triangle t (with attributes a) at pixel (x, y).
void shadeFragment(ExactTriangle t, ExactAttributes a, uint x, uint y, RasterSample s,
                   FrameInfo frame, out vec3 radiance, out vec3 transmittance) {
    Material m = loadMaterial(a.materialIndex);
    vec3 b = s.barycentric;

    precise vec4 colour = (a.colour0 * b.x + a.colour1 * b.y) + a.colour2 * b.z;

    vec3 normal;
    if (FACE_NORMALS && (!VERTEX_NORMALS || (a.flags & ATTRIBUTES_FACE_NORMAL) != 0u)) {
        normal = a.normal0.xyz;
    } else {
        precise vec3 n = (a.normal0.xyz * b.x + a.normal1.xyz * b.y) + a.normal2.xyz * b.z;
        normal = n;
    }

    vec4 texel = vec4(1.0);
    if (TEXTURES && m.textureIndex >= 0) {
        ExactTexture tex = loadTextureInfo(m.textureIndex);
        // Meshes without UVs read (0, 0) everywhere: level 0 at the origin, like the reference.
        if ((a.flags & ATTRIBUTES_HAS_UVS) == 0u) {
            texel = sampleTexture(tex, vec2(0.0), 0.0);
        } else {
            vec2 uv0 = a.uv01.xy;
            vec2 uv1 = a.uv01.zw;
            vec2 uv2 = a.uv2;
            vec3 gx;
            vec3 gy;
            barycentricGradients(t, x, y, gx, gy);
            vec2 size = vec2(tex.width, tex.height);
            precise vec2 ux = ((uv0 * gx.x + uv1 * gx.y) + uv2 * gx.z) * size;
            precise vec2 uy = ((uv0 * gy.x + uv1 * gy.y) + uv2 * gy.z) * size;
            float rho = max(length(ux), length(uy));
            precise vec2 uv = (uv0 * b.x + uv1 * b.y) + uv2 * b.z;
            texel = sampleTexture(tex, uv, log2(rho));
        }
    }
    shadeTransparent(m, frame, colour, texel, normal, radiance, transmittance);
}

// (depth, order) < (depth2, order2)
bool keyLess(uint d, uint o, uint d2, uint o2) {
    return d < d2 || (d == d2 && o < o2);
}

void main() {
    // Uniform loads first, outside all control flow: CPU drivers load them once for the
    // subgroup there, but once per lane after a branch (an early return counts).
    FrameInfo frame = u_frame;
    uint bin = gl_WorkGroupID.y * u_push.binsX + gl_WorkGroupID.x;
    uint first = g_binOffsets[bin];
    uint end = first + g_binCounts[bin];
    uint x = gl_WorkGroupID.x * BIN_SIZE + gl_LocalInvocationID.x;
    uint y = gl_WorkGroupID.y * BIN_SIZE + gl_LocalInvocationID.y;
    if (x >= u_push.width || y >= u_push.height) {
        return;
    }
    // Every invocation walks the same bin list in step, so each record is fetched once per
    // subgroup (any subgroup size: only "first active lane" is assumed).
    float opaqueDepth = texelFetch(u_opaqueDepth, ivec2(x, y), 0).r;

    vec3 radiance = vec3(0.0);
    vec3 transmittance = vec3(1.0);
    // Fragments up to and including (doneDepth, doneOrder) are composited.
    uint doneDepth = 0u;
    uint doneOrder = 0u;
    bool started = false;
    uint passes = 0u;
    uint fragments = 0u;

    while (true) {
        uint selDepth[SELECT_SIZE];
        uint selOrder[SELECT_SIZE];
        uint selTri[SELECT_SIZE];
        [[unroll]] for (int k = 0; k < SELECT_SIZE; k++) {
            selDepth[k] = 0xFFFFFFFFu;
            selOrder[k] = 0xFFFFFFFFu;
            selTri[k] = 0u;
        }
        uint found = 0u;
        for (uint e = first; e < end; e++) {
            uint ti = subgroupBroadcastFirst(texelFetch(u_binEntryTexels, int(e)).r);
            ivec4 r = loadTriangleBounds(ti);
            bool inBox = int(x) >= r.x && int(x) < r.z && int(y) >= r.y && int(y) < r.w;
            // A uniform test skips the triangle for real when no pixel of the subgroup is in
            // its box; a per-pixel `continue` alone would not on CPU drivers (masking).
            if (!subgroupAny(inBox)) {
                continue;
            }
            ExactTriangle t = loadTriangle(ti);
            RasterSample s;
            bool take;
            if (HOMOGENEOUS_PATH && t.edgeB.w >= 0) {
                take = inBox && sampleHomogeneous(loadHomogeneous(t.edgeB.w), x, y, s);
            } else {
                i64vec3 edges;
                bool covered = inBox && coversFixed(t, x, y, edges);
                if (!subgroupAny(covered)) {
                    continue;
                }
                take = covered && interpolateFixed(t, edges, s);
            }
            uint d = floatBitsToUint(s.viewDepth);
            uint o = t.ids.w;
            take = take && s.zNdc < opaqueDepth && (!started || keyLess(doneDepth, doneOrder, d, o));
            found += take ? 1u : 0u;
            bool insert = take && keyLess(d, o, selDepth[SELECT_SIZE - 1], selOrder[SELECT_SIZE - 1]);
            if (!subgroupAny(insert)) {
                continue;
            }
            // Insert, dropping the last: each slot takes its left neighbour, the new key, or
            // keeps its own, walking right to left (left neighbours are still unchanged).
            [[unroll]] for (int k = SELECT_SIZE - 1; k > 0; k--) {
                bool shift = insert && keyLess(d, o, selDepth[k - 1], selOrder[k - 1]);
                bool here = insert && !shift && keyLess(d, o, selDepth[k], selOrder[k]);
                selDepth[k] = shift ? selDepth[k - 1] : (here ? d : selDepth[k]);
                selOrder[k] = shift ? selOrder[k - 1] : (here ? o : selOrder[k]);
                selTri[k] = shift ? selTri[k - 1] : (here ? ti : selTri[k]);
            }
            if (insert && keyLess(d, o, selDepth[0], selOrder[0])) {
                selDepth[0] = d;
                selOrder[0] = o;
                selTri[0] = ti;
            }
        }
        passes++;
        uint count = min(found, uint(SELECT_SIZE));
        for (uint i = 0u; i < count; i++) {
            // Always shade slot 0, then shift the selection left: constant indices only.
            ExactTriangle t = loadTriangle(selTri[0]);
            RasterSample s;
            sampleTriangle(t, x, y, s);
            vec3 l;
            vec3 tr;
            shadeFragment(t, loadAttributes(selTri[0]), x, y, s, frame, l, tr);
            radiance += transmittance * l;
            transmittance *= tr;
            doneDepth = selDepth[0];
            doneOrder = selOrder[0];
            [[unroll]] for (int k = 0; k < SELECT_SIZE - 1; k++) {
                selDepth[k] = selDepth[k + 1];
                selOrder[k] = selOrder[k + 1];
                selTri[k] = selTri[k + 1];
            }
        }
        fragments += count;
        started = true;
        bool opaqueEnough = u_push.threshold > 0.0 && all(lessThan(transmittance, vec3(u_push.threshold)));
        if (found <= uint(SELECT_SIZE) || opaqueEnough) {
            break;
        }
    }
    if (fragments > 0u) {
        vec3 behind = imageLoad(u_colour, ivec2(x, y)).rgb;
        precise vec3 result = radiance + transmittance * behind;
        imageStore(u_colour, ivec2(x, y), vec4(result, 1.0));
    }
    // Statistics: one atomic per subgroup, not per pixel.
    uint subgroupFragments = subgroupAdd(fragments);
    uint subgroupPasses = subgroupMax(passes);
    if (subgroupElect()) {
        atomicAdd(g_counters.fragmentCount, subgroupFragments);
        atomicMax(g_counters.passCount, subgroupPasses);
    }
}
