// What the bin stages and the rasters that read them share: their descriptor set
// (interface_bins_set.glsl, from crates/translucid/src/interface/bins.rs), push constants,
// and the loaders and helpers over them.
#ifndef TRANSLUCID_BINS_BINDINGS_GLSL
#define TRANSLUCID_BINS_BINDINGS_GLSL

#extension GL_EXT_control_flow_attributes : require

#include "interface_scene.glsl"
#include "interface_specialization.glsl"
#include "bin_triangle.glsl"
#include "transparent_layer.glsl"

#include "interface_bins_set.glsl"

layout(push_constant) uniform BinPushBlock { BinPush u_push; };

// Opaque depth as translucid's depth grows, away from the eye, at a pixel of the frame, and
// over the four texels around `corner` (a point between texels, in the frame's pixels, with
// `texelSize` the depth image's); the frame starts at the push constants' corner of the
// depth image.
ivec2 opaqueDepthOrigin() {
    return ivec2(u_push.opaqueDepthX, u_push.opaqueDepthY);
}

float opaqueDepthAt(ivec2 pixel) {
    float d = texelFetch(u_opaqueDepth, pixel + opaqueDepthOrigin(), 0).r;
    return u_push.opaqueDepthReversed != 0u ? 1.0 - d : d;
}

vec4 opaqueDepthGather(vec2 corner, vec2 texelSize) {
    vec4 d = textureGather(u_opaqueDepth, (corner + vec2(opaqueDepthOrigin())) * texelSize, 0);
    return u_push.opaqueDepthReversed != 0u ? 1.0 - d : d;
}

// A pixel's transparent layer, everything in front of the opaque layer: composited onto the
// frame target's colour; or, in place, left for this submission's composite.
void writePixel(ivec2 pixel, vec3 radiance, vec3 transmittance) {
    if (u_push.stamp != 0u) {
        LayerTexel texel = packTransparentLayer(radiance, transmittance, u_push.stamp);
        imageStore(u_transparentLayer, pixel, uvec4(texel.first, 0u, 0u));
        imageStore(u_transparentLayerStamps, pixel, uvec4(texel.second));
    } else {
        vec3 behind = imageLoad(u_colour, pixel).rgb;
        precise vec3 result = radiance + transmittance * behind;
        imageStore(u_colour, pixel, vec4(storedColour(result), 1.0));
    }
}

// Dispatches over triangles (setup and binning, BINNING_GROUP_SIZE invocations a workgroup
// in x) and over a band's blocks (the rasters) may need more workgroups than a device allows
// in x (65535): they go on in z, u_push.groupsX to a row. A workgroup's and a triangle
// dispatch's invocation's place in the whole, and the (x, z) counts of `groups` workgroups
// (split_groups in bins/mod.rs). The last row of a triangle dispatch may hold workgroups past
// the items, which their bounds checks skip; a band fills whole rows (planBand). (Not
// gl_WorkGroupSize: these come before the shaders declare their size.)
uint linearWorkGroup() {
    return gl_WorkGroupID.z * gl_NumWorkGroups.x + gl_WorkGroupID.x;
}

uint linearInvocation() {
    return linearWorkGroup() * BINNING_GROUP_SIZE + gl_LocalInvocationID.x;
}

uvec2 splitGroups(uint groups) {
    return uvec2(min(groups, u_push.groupsX), (groups + u_push.groupsX - 1u) / u_push.groupsX);
}

uvec4 loadQuad(uint i) {
    return texelFetch(u_quadTexels, int(i));
}

// The mat4 whose columns are texels first .. first + 3 of `texels`.
mat4 fetchMat4(usamplerBuffer texels, int first) {
    return mat4(uintBitsToFloat(texelFetch(texels, first)),
                uintBitsToFloat(texelFetch(texels, first + 1)),
                uintBitsToFloat(texelFetch(texels, first + 2)),
                uintBitsToFloat(texelFetch(texels, first + 3)));
}

BinDraw loadBinDraw(uint i) {
    int base = int(i) * 5;
    BinDraw d;
    d.mvp = fetchMat4(u_binDrawTexels, base);
    uvec4 rest = texelFetch(u_binDrawTexels, base + 4);
    d.drawIndex = rest.x;
    d.firstItem = rest.y;
    d.quadCount = rest.z;
    d.firstQuad = rest.w;
    return d;
}

DrawInfo loadDrawInfo(uint i) {
    int base = int(i) * 10;
    DrawInfo d;
    d.model = fetchMat4(u_drawTexels, base);
    d.normalMatrix = fetchMat4(u_drawTexels, base + 4);
    uvec4 rest = texelFetch(u_drawTexels, base + 8);
    d.materialIndex = rest.x;
    d.flags = rest.y;
    d.firstQuad = rest.z;
    d.quadCount = rest.w;
    d.tint = uintBitsToFloat(texelFetch(u_drawTexels, base + 9));
    return d;
}

// Texels of a triangle record (BinTriangleRecord) in u_triangleTexels.
#define TRIANGLE_TEXELS 4

// The fixed-point edges of snapped vertices v, negated when they wind the other way: edge k
// runs from vertex k + 1 to vertex k + 2. Setup and the record loaders both build them here.
void unpackEdges(ivec2 v[3], bool negated, out BinTriangle t) {
    int s = negated ? -1 : 1;
    int ties = 0;
    [[unroll]] for (int k = 0; k < 3; k++) {
        ivec2 p = v[(k + 1) % 3];
        ivec2 q = v[(k + 2) % 3];
        int a = s * (p.y - q.y);
        int b = s * (q.x - p.x);
        t.edgeA[k] = a;
        t.edgeB[k] = b;
        int64_t c = int64_t(p.x) * int64_t(q.y) - int64_t(p.y) * int64_t(q.x);
        t.edgeC[k] = negated ? -c : c;
        ties |= (a > 0 || (a == 0 && b > 0)) ? (1 << k) : 0;
    }
    t.edgeA.w = ties;
    t.edgeC.w = 0l;
}

// Record i from its texels t0 to t3. What a caller does not use of it compiles away.
BinTriangle unpackTriangle(uint i, uvec4 t0, uvec4 t1, uvec4 t2, uvec4 t3) {
    BinTriangle t;
    ivec2 v[3] = ivec2[3](ivec2(t0.xy), ivec2(t0.zw), ivec2(t1.xy));
    unpackEdges(v, (t1.z & TRIANGLE_NEGATED) != 0u, t);
    t.edgeB.w = (t1.z & TRIANGLE_HOMOGENEOUS) != 0u ? int(t0.x) : -1;
    t.order = i;
    t.materialIndex = t1.z >> TRIANGLE_MATERIAL_SHIFT;
    t.attributeFlags = t1.z & (TRIANGLE_FACE_NORMAL | TRIANGLE_HAS_UVS);
    t.zNdc = vec4(uintBitsToFloat(t2.xyz), uintBitsToFloat(t3.w));
    t.invW = vec4(uintBitsToFloat(t3.xyz), 0.0);
    t.bounds = ivec4(t1.w & 0xFFFFu, t1.w >> 16u, t2.w & 0xFFFFu, t2.w >> 16u);
    return t;
}

// Triangle record i.
BinTriangle loadTriangle(uint i) {
    int base = int(i) * TRIANGLE_TEXELS;
    return unpackTriangle(i, texelFetch(u_triangleTexels, base),
                          texelFetch(u_triangleTexels, base + 1),
                          texelFetch(u_triangleTexels, base + 2),
                          texelFetch(u_triangleTexels, base + 3));
}

// Triangle record i, read from the storage buffer setup wrote it to (only where the records
// fit one storage binding: STORAGE_WALK).
BinTriangle loadStoredTriangle(uint i) {
    BinTriangleRecord r = g_triangles[i];
    return unpackTriangle(i, uvec4(r.vertices01),
                          uvec4(uvec2(r.vertex2), r.flags, r.boundsMin),
                          uvec4(floatBitsToUint(r.zNdc), r.boundsEnd),
                          uvec4(floatBitsToUint(r.invW), floatBitsToUint(r.invArea)));
}

// The record of a triangle a walk visits, the same in every lane of its tile: loaded as
// STORAGE_WALK says (features.rs, storage_walk).
BinTriangle loadWalkedTriangle(uint i) {
    return STORAGE_WALK ? loadStoredTriangle(i) : loadTriangle(i);
}

// List entry e, clamped to `last` (so that a look-ahead never reads past the list).
uint walkedEntry(uint e, uint last) {
    return STORAGE_WALK ? g_binEntries[min(e, last)]
                        : texelFetch(u_binEntryTexels, int(min(e, last))).r;
}

BinHomogeneous loadHomogeneous(int i) {
    int base = i * 8;
    BinHomogeneous h;
    h.line0 = uintBitsToFloat(texelFetch(u_homogeneousTexels, base));
    h.line1 = uintBitsToFloat(texelFetch(u_homogeneousTexels, base + 1));
    h.line2 = uintBitsToFloat(texelFetch(u_homogeneousTexels, base + 2));
    h.zInvDet = uintBitsToFloat(texelFetch(u_homogeneousTexels, base + 3));
    uvec4 c01 = texelFetch(u_homogeneousTexels, base + 4);
    uvec4 c2 = texelFetch(u_homogeneousTexels, base + 5);
    h.fixedC = i64vec4(int64_t(packUint2x32(c01.xy)), int64_t(packUint2x32(c01.zw)),
                       int64_t(packUint2x32(c2.xy)), int64_t(packUint2x32(c2.zw)));
    h.fixedA = ivec4(texelFetch(u_homogeneousTexels, base + 6));
    h.fixedB = ivec4(texelFetch(u_homogeneousTexels, base + 7));
    return h;
}

Material loadMaterial(uint i) {
    int base = int(i) * 3;
    uvec4 last = texelFetch(u_materialTexels, base + 2);
    Material m;
    m.baseColour = uintBitsToFloat(texelFetch(u_materialTexels, base));
    m.tintTransmission = uintBitsToFloat(texelFetch(u_materialTexels, base + 1));
    m.reflectance = uintBitsToFloat(last.x);
    m.alphaCutoff = uintBitsToFloat(last.y);
    m.textureIndex = int(last.z);
    m.flags = last.w;
    return m;
}

BinTexture loadTextureInfo(int i) {
    uvec4 a = texelFetch(u_textureInfoTexels, i * 2);
    uvec4 b = texelFetch(u_textureInfoTexels, i * 2 + 1);
    BinTexture t;
    t.firstTexel = a.x;
    t.width = a.y;
    t.height = a.z;
    t.levels = a.w;
    t.srgb = b.x;
    t.samplerBits = b.y;
    t.pad[0] = 0u;
    t.pad[1] = 0u;
    return t;
}

#endif
