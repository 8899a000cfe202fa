#version 450
// Setup: one invocation per transparent quad. Transforms its vertices, sets up its one or two
// triangles under the shared raster rules, culls what can cover nothing (degenerate, back
// facing for single-sided materials, outside the viewport or the depth range, wholly behind
// the opaque layer), and writes the rest to the triangle array for binning, each at its
// order key.

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require

#include "scene_bindings_compute.glsl"
#include "bins_bindings.glsl"
#include "raster.glsl"
#include "bin_lists.glsl"
#include "depth_pyramid.glsl"
#include "quad_attributes.glsl"
#include "shading.glsl"

layout(local_size_x = BINNING_GROUP_SIZE) in;

// Whether the homogeneous (near-plane, guard-band) path is compiled in. Both sides of an `if`
// run on CPU drivers, so the host leaves it out when no mesh can need it; a triangle that
// needs it anyway is only counted, and the host rebuilds this shader and the raster with
// the path and renders the frame again.
#include "interface_specialization.glsl"
// What shading can read of an attribute record is constants 1 to 3, 9 and 10, shared with
// the rasters (quad_attributes.glsl): setup stores only those sections. Its stores are most
// of its time, since a storage-buffer store is a loop over the lanes for every 32-bit
// component.
// Setup without the occlusion cull (and without the depth pyramid it reads), which the host
// records while the cull drops next to nothing: on CPU drivers the pyramid costs about a
// millisecond a frame (methods/bins/mod.rs). The raster depth-tests every fragment anyway.

// The transparent draw holding global quad `item` (draws are sorted by firstItem).
uint findDraw(uint item) {
    uint lo = 0u;
    uint hi = u_push.drawCount - 1u;
    while (lo < hi) {
        uint mid = (lo + hi + 1u) >> 1;
        if (texelFetch(u_binDrawTexels, int(mid) * 5 + 4).y <= item) {
            lo = mid;
        } else {
            hi = mid - 1u;
        }
    }
    return lo;
}

bool inBand(float v) {
    return abs(v) <= GUARD_BAND; // false for NaN
}

int clampPixel(int64_t v, uint size) {
    return int(clamp(v, int64_t(0), int64_t(size)));
}

// Bounds on the homogeneous path: the triangle (its vertices scaled by a power of two, which
// projection ignores) clipped to the near plane (z >= 0), projected, padded by a pixel; the
// whole viewport when a clipped vertex is not clearly in front of the eye. A superset of the
// reference's bounds: coverage itself is decided by the edges, and a projected corner is
// within 2^-21 of its size, less than the pad on screen.
bool homogeneousBounds(vec4 c[3], out ivec4 bounds) {
    vec4 poly[4];
    int n = 0;
    for (int i = 0; i < 3; i++) {
        vec4 a = c[i];
        vec4 b = c[(i + 1) % 3];
        bool aIn = a.z >= 0.0;
        bool bIn = b.z >= 0.0;
        if (aIn) {
            poly[n++] = a;
        }
        if (aIn != bIn) {
            float t = a.z / (a.z - b.z);
            poly[n++] = a + (b - a) * t;
        }
    }
    if (n == 0) {
        return false;
    }
    vec2 lo = vec2(1e30);
    vec2 hi = vec2(-1e30);
    vec2 size = vec2(u_push.width, u_push.height);
    for (int i = 0; i < n; i++) {
        // Nearly on the eye plane (including w > 0 only through rounding): anywhere.
        if (!(poly[i].w > 1.0e-6 * max(abs(poly[i].x), abs(poly[i].y)))) {
            bounds = ivec4(0, 0, u_push.width, u_push.height);
            return true;
        }
        vec2 p = (poly[i].xy / poly[i].w * 0.5 + 0.5) * size;
        lo = min(lo, p);
        hi = max(hi, p);
    }
    vec2 first = clamp(ceil(lo - 0.5) - 1.0, vec2(0.0), size);
    vec2 end = clamp(floor(hi - 0.5) + 2.0, vec2(0.0), size);
    bounds = ivec4(int(first.x), int(first.y), int(end.x), int(end.y));
    return true;
}

vec3 crossF(vec3 p, vec3 q) {
    precise vec3 r = vec3(p.y * q.z - p.z * q.y, p.z * q.x - p.x * q.z, p.x * q.y - p.y * q.x);
    return r;
}

void fixedEdge(i64vec2 p, i64vec2 q, int64_t s, out int64_t a, out int64_t b, out int64_t c) {
    a = s * (p.y - q.y);
    b = s * (q.x - p.x);
    c = s * (p.x * q.y - p.y * q.x);
}

// Sets up one triangle; false when it covers no sample. `front` tells its facing; `vertices`
// and `negated` are what the record keeps of the edges (zero on the homogeneous path).
bool setupTriangle(vec4 c[3], out BinTriangle t, out ivec2 vertices[3], out bool negated,
                   out BinHomogeneous h, out bool homogeneous, out bool front) {
    homogeneous = false;
    front = false;
    negated = false;
    vertices = ivec2[3](ivec2(0), ivec2(0), ivec2(0));
    t.bounds = ivec4(0);
    for (int i = 0; i < 3; i++) {
        if (any(isnan(c[i])) || any(isinf(c[i]))) {
            return false;
        }
    }
    vec2 size = vec2(u_push.width, u_push.height);
    vec3 fb[3];
    i64vec2 p[3];
    bool snapped[3];   // w > 0 and inside the guard band
    bool allFixed = true;
    for (int i = 0; i < 3; i++) {
        fb[i] = viewportTransform(c[i], size);
        snapped[i] = c[i].w > 0.0 && inBand(fb[i].x) && inBand(fb[i].y);
        p[i] = snapped[i] ? i64vec2(snapCoord(fb[i].x), snapCoord(fb[i].y)) : i64vec2(0);
        allFixed = allFixed && snapped[i] && c[i].z >= 0.0;
    }
    if (allFixed) {
        int64_t area2 = (p[0].x * p[1].y - p[1].x * p[0].y) + (p[1].x * p[2].y - p[2].x * p[1].y) +
                        (p[2].x * p[0].y - p[0].x * p[2].y);
        if (area2 == 0) {
            return false;
        }
        int64_t s = area2 > 0 ? int64_t(1) : int64_t(-1);
        negated = s < 0;
        // Inside the guard band, so they fit 32 bits. The edges come from the same function
        // that rebuilds them from the record.
        vertices = ivec2[3](ivec2(p[0]), ivec2(p[1]), ivec2(p[2]));
        unpackEdges(vertices, negated, t);
        t.edgeB.w = -1;
        int64_t minX = min(min(p[0].x, p[1].x), p[2].x);
        int64_t minY = min(min(p[0].y, p[1].y), p[2].y);
        int64_t maxX = max(max(p[0].x, p[1].x), p[2].x);
        int64_t maxY = max(max(p[0].y, p[1].y), p[2].y);
        t.bounds = ivec4(clampPixel((minX - HALF_PIXEL + 255) >> 8, u_push.width),
                         clampPixel((minY - HALF_PIXEL + 255) >> 8, u_push.height),
                         clampPixel(((maxX - HALF_PIXEL) >> 8) + 1, u_push.width),
                         clampPixel(((maxY - HALF_PIXEL) >> 8) + 1, u_push.height));
        precise float invArea = quotient(1.0, float(abs(area2)));
        t.zNdc = vec4(fb[0].z, fb[1].z, fb[2].z, invArea);
        precise vec4 invW = vec4(quotient(1.0, c[0].w), quotient(1.0, c[1].w), quotient(1.0, c[2].w), 0.0);
        t.invW = invW;
        front = area2 < 0;
    } else if (!HOMOGENEOUS_PATH) {
        atomicAdd(g_counters.homogeneousCount, 1u);
        return false;
    } else {
        homogeneous = true;
        // The vertices scaled by 2^-e (raster.rs), so that no product overflows.
        float largest = 0.0;
        for (int i = 0; i < 3; i++) {
            largest = max(largest, max(max(abs(c[i].x), abs(c[i].y)), max(abs(c[i].z), abs(c[i].w))));
        }
        int exponent = exponentOf(largest);
        vec4 scaled[3];
        vec3 v[3];
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < 4; j++) {
                scaled[i][j] = scaleByPowerOfTwo(c[i][j], -exponent);
            }
            precise float x = (scaled[i].x * 0.5 + scaled[i].w * 0.5) * size.x;
            precise float y = (scaled[i].y * 0.5 + scaled[i].w * 0.5) * size.y;
            v[i] = vec3(x, y, scaled[i].w);
        }
        vec3 raw0 = crossF(v[1], v[2]);
        vec3 raw1 = crossF(v[2], v[0]);
        vec3 raw2 = crossF(v[0], v[1]);
        precise float det = (raw0.x * v[0].x + raw0.y * v[0].y) + raw0.z * v[0].z;
        if (det == 0.0 || isnan(det) || isinf(det)) {
            return false;
        }
        float s = det > 0.0 ? 1.0 : -1.0;
        if (!homogeneousBounds(scaled, t.bounds)) {
            return false;
        }
        h.line0 = vec4(raw0 * s, float(exponent));
        h.line1 = vec4(raw1 * s, 0.0);
        h.line2 = vec4(raw2 * s, 0.0);
        precise float invDet = quotient(1.0, abs(det));
        h.zInvDet = vec4(scaled[0].z, scaled[1].z, scaled[2].z, invDet);
        int mask = 0;
        int ties = 0;
        for (int k = 0; k < 3; k++) {
            int j = (k + 1) % 3;
            int l = (k + 2) % 3;
            if (snapped[j] && snapped[l] && p[j] != p[l]) {
                int64_t a, b, cc;
                fixedEdge(p[j], p[l], int64_t(s), a, b, cc);
                h.fixedA[k] = int(a);
                h.fixedB[k] = int(b);
                h.fixedC[k] = cc;
                mask |= 1 << k;
                ties |= ownsTies(a, b) ? (1 << k) : 0;
            } else {
                h.fixedA[k] = 0;
                h.fixedB[k] = 0;
                h.fixedC[k] = 0;
            }
        }
        h.fixedA.w = mask;
        h.fixedB.w = ties;
        h.fixedC.w = 0;
        t.edgeA = ivec4(0);
        t.edgeB = ivec4(0, 0, 0, -1);
        t.edgeC = i64vec4(0);
        t.zNdc = vec4(0.0);
        t.invW = vec4(0.0);
        front = det < 0.0;
    }
    return t.bounds.x < t.bounds.z && t.bounds.y < t.bounds.w;
}

// Whether no fragment of fixed-path triangle t can pass the opaque depth test (nearer than
// the opaque depth). Its fragments' depths are interpolated between its vertices' in float,
// so none is below the nearest vertex's less a few ulps; 2^-16 of it is far more than that.
bool behindOpaque(BinTriangle t) {
    float nearest = min(min(t.zNdc.x, t.zNdc.y), t.zNdc.z);
    return nearest - nearest * (1.0 / 65536.0) >= farthestOpaque(t.bounds);
}

// A corner of a quad as setup reads it: its three vertex texels, fetched once for both of
// the quad's triangles (a texel fetch is a call to the driver's sampling code on CPU
// drivers; fetching per triangle cost setup 7 %).
struct Corner {
    vec3 position;
    vec3 normal;
    vec2 uv;
    vec4 colour;
};

Corner loadCorner(uint v) {
    uvec4 a = texelFetch(u_vertexTexels, int(v) * 3);
    uvec4 b = texelFetch(u_vertexTexels, int(v) * 3 + 1);
    Corner c;
    c.position = uintBitsToFloat(a.xyz);
    c.normal = uintBitsToFloat(uvec3(a.w, b.xy));
    c.uv = uintBitsToFloat(b.zw);
    c.colour = uintBitsToFloat(texelFetch(u_vertexTexels, int(v) * 3 + 2));
    return c;
}

// Setup writes the records as storage buffers (g_triangles, g_attributes), as far as one
// binding reaches, while they fit (faster on lavapipe than texel stores), else through
// u_triangleRecords and u_attributeRecords (RECORDS_AS_TEXELS, set by the host from the
// records' size).

// Record ti (BinTriangleRecord), whose order key is ti: through texels, one per 16 bytes of
// its std430 layout, or field by field.
void storeTriangle(uint ti, BinTriangle t, ivec2 v[3], bool negated) {
    bool homogeneous = t.edgeB.w >= 0;
    uint flags = (negated ? TRIANGLE_NEGATED : 0u) | (homogeneous ? TRIANGLE_HOMOGENEOUS : 0u) |
                 t.attributeFlags | t.materialIndex << TRIANGLE_MATERIAL_SHIFT;
    ivec4 vertices01 = homogeneous ? ivec4(t.edgeB.w, 0, 0, 0) : ivec4(v[0], v[1]);
    uint boundsMin = uint(t.bounds.x) | uint(t.bounds.y) << 16u;
    uint boundsEnd = uint(t.bounds.z) | uint(t.bounds.w) << 16u;
    if (!RECORDS_AS_TEXELS) {
        g_triangles[ti].vertices01 = vertices01;
        g_triangles[ti].vertex2 = v[2];
        g_triangles[ti].flags = flags;
        g_triangles[ti].boundsMin = boundsMin;
        g_triangles[ti].zNdc = t.zNdc.xyz;
        g_triangles[ti].boundsEnd = boundsEnd;
        g_triangles[ti].invW = t.invW.xyz;
        g_triangles[ti].invArea = t.zNdc.w;
        return;
    }
    int base = int(ti) * TRIANGLE_TEXELS;
    imageStore(u_triangleRecords, base, uvec4(vertices01));
    imageStore(u_triangleRecords, base + 1, uvec4(uvec2(v[2]), flags, boundsMin));
    imageStore(u_triangleRecords, base + 2, uvec4(floatBitsToUint(t.zNdc.xyz), boundsEnd));
    imageStore(u_triangleRecords, base + 3,
               uvec4(floatBitsToUint(t.invW.xyz), floatBitsToUint(t.zNdc.w)));
}

// Record ti as a hole: empty bounds (an end of 0), so that binning enters it nowhere. Its
// other fields are never read.
void storeHole(uint ti) {
    if (RECORDS_AS_TEXELS) {
        imageStore(u_triangleRecords, int(ti) * TRIANGLE_TEXELS + 2, uvec4(0u));
    } else {
        g_triangles[ti].boundsEnd = 0u;
    }
}

// Texel `at` of the attribute records.
void storeAttributeTexel(int at, uvec4 texel) {
    if (RECORDS_AS_TEXELS) {
        imageStore(u_attributeRecords, at, texel);
    } else {
        g_attributes[at] = texel;
    }
}

// The attribute record of quad `quad` of `draw`, with corners k0 to k3 (interface_bins.glsl):
// only the sections shading can read under the same constants (quad_attributes.glsl).
// Normals are transformed here exactly as the reference transforms them per fragment. A quad
// of a draw without normals keeps its triangles' face normals instead. (A draw's vertex
// normals go unstored without VERTEX_NORMALS: no lit draw has any, so that draw is unlit.)
void storeAttributes(uint quad, DrawInfo draw, Corner k0, Corner k1, Corner k2, Corner k3) {
    if (VERTEX_COLOURS) {
        int at = colourTexel(quad);
        storeAttributeTexel(at, floatBitsToUint(k0.colour * draw.tint));
        if (!FLAT_COLOURS) {
            storeAttributeTexel(at + 1, floatBitsToUint(k1.colour * draw.tint));
            storeAttributeTexel(at + 2, floatBitsToUint(k2.colour * draw.tint));
            storeAttributeTexel(at + 3, floatBitsToUint(k3.colour * draw.tint));
        }
    }
    bool hasNormals = (draw.flags & DRAW_HAS_NORMALS) != 0u;
    if (VERTEX_NORMALS && hasNormals) {
        mat3 nm = mat3(draw.normalMatrix);
        precise vec3 n0 = nm * k0.normal;
        precise vec3 n1 = nm * k1.normal;
        precise vec3 n2 = nm * k2.normal;
        precise vec3 n3 = nm * k3.normal;
        int at = normalTexel(quad);
        storeAttributeTexel(at, floatBitsToUint(vec4(n0, n1.x)));
        storeAttributeTexel(at + 1, floatBitsToUint(vec4(n1.yz, n2.xy)));
        storeAttributeTexel(at + 2, floatBitsToUint(vec4(n2.z, n3)));
    }
    if (FACE_NORMALS && !hasNormals) {
        vec3 p0 = (draw.model * vec4(k0.position, 1.0)).xyz;
        vec3 p1 = (draw.model * vec4(k1.position, 1.0)).xyz;
        vec3 p2 = (draw.model * vec4(k2.position, 1.0)).xyz;
        vec3 p3 = (draw.model * vec4(k3.position, 1.0)).xyz;
        int at = normalTexel(quad);
        storeAttributeTexel(at, uvec4(floatBitsToUint(faceNormal(p1 - p0, p2 - p0)), 0u));
        storeAttributeTexel(at + 1, uvec4(floatBitsToUint(faceNormal(p2 - p0, p3 - p0)), 0u));
    }
    if (TEXTURES && (draw.flags & DRAW_HAS_UVS) != 0u) {
        int at = uvTexel(quad);
        storeAttributeTexel(at, floatBitsToUint(vec4(k0.uv, k1.uv)));
        storeAttributeTexel(at + 1, floatBitsToUint(vec4(k2.uv, k3.uv)));
    }
}

void main() {
    uint item = linearInvocation();
    if (item >= u_push.itemCount) {
        return;
    }
    uint slot = findDraw(item);
    BinDraw d = loadBinDraw(slot);
    uint quadIndex = item - d.firstItem;
    uvec4 q = loadQuad(d.firstQuad + quadIndex);
    DrawInfo draw = loadDrawInfo(d.drawIndex);
    Material m = loadMaterial(draw.materialIndex);
    bool cullBack = (m.flags & MATERIAL_DOUBLE_SIDED) == 0u;
    // A quad whose last index repeats a corner is a lone triangle (its fourth corner is read
    // and not used). Triangle 0 has corners 0, 1, 2 and triangle 1 corners 0, 2, 3, as in the
    // reference; selects pick them, since an array indexed by `sub` would be indexed at run
    // time.
    Corner k0 = loadCorner(q.x);
    Corner k1 = loadCorner(q.y);
    Corner k2 = loadCorner(q.z);
    Corner k3 = loadCorner(q.w);
    vec4 clip0 = clipPosition(d.mvp, k0.position);
    vec4 clip1 = clipPosition(d.mvp, k1.position);
    vec4 clip2 = clipPosition(d.mvp, k2.position);
    vec4 clip3 = clipPosition(d.mvp, k3.position);
    uint subCount = (q.w != q.z && q.w != q.x) ? 2u : 1u;
    // A do-while, and `if`s rather than `continue`s (bin_count.comp says why).
    uint sub = 0u;
    bool kept = false;
    do {
        bool second = sub != 0u;
        vec4 c[3];
        c[0] = clip0;
        c[1] = second ? clip2 : clip1;
        c[2] = second ? clip3 : clip2;
        BinTriangle t;
        ivec2 v[3];
        bool negated;
        BinHomogeneous h;
        bool homogeneous;
        bool front;
        bool drawn = setupTriangle(c, t, v, negated, h, homogeneous, front) &&
                     !(cullBack && !front);
        bool occluded = !SKIP_OCCLUSION_CULL && drawn && !homogeneous && behindOpaque(t);
        bool visible = drawn && !occluded;
        if (!SKIP_OCCLUSION_CULL) {
            // What the cull is worth, for the host's choice: the blocks the dropped triangles
            // would have been binned into, one atomic per subgroup.
            ivec4 r = binRect(t.bounds);
            uint blocks = uint(r.z - r.x + 1) *
                          uint(((r.w >> BLOCK_TILE_SHIFT) - (r.y >> BLOCK_TILE_SHIFT)) + 1);
            uint dropped = subgroupAdd(occluded ? blocks : 0u);
            if (dropped > 0u && subgroupElect()) {
                atomicAdd(g_counters.occludedBlocks, dropped);
            }
        }
        if (visible && homogeneous) {
            uint hi = atomicAdd(g_counters.homogeneousCount, 1u);
            if (hi >= g_counters.homogeneousCapacity) {
                atomicOr(g_counters.overflow, OVERFLOW_HOMOGENEOUS);
                visible = false;
            } else {
                g_homogeneous[hi] = h;
                t.edgeB.w = int(hi);
            }
        }
        // Every triangle has its record at its order key (interface_bins.glsl), culled ones too,
        // as a hole that binning skips: two records per quad, the capacity.
        uint ti = item * 2u + sub;
        if (visible) {
            t.order = ti;
            t.materialIndex = draw.materialIndex;
            t.attributeFlags =
                ((draw.flags & DRAW_HAS_NORMALS) == 0u ? TRIANGLE_FACE_NORMAL : 0u) |
                ((draw.flags & DRAW_HAS_UVS) != 0u ? TRIANGLE_HAS_UVS : 0u);
            kept = true;
            // Frame-wide counters take one atomic per subgroup: one per triangle made them the
            // most contended words of the frame. Only the visible lanes are active here. The
            // depth range only places slabs (bin_lists.glsl): frames of one slab skip it
            // (the dragon's setup 4-6 % faster).
            uvec2 depth = homogeneous ? uvec2(0xFFFFFFFFu, 0u) : triangleDepthBits(t);
            uint nearest = SLABS > 1u ? subgroupMin(depth.x) : 0u;
            uint farthest = SLABS > 1u ? subgroupMax(depth.y) : 0u;
            uint keptCount = subgroupBallotBitCount(subgroupBallot(true));
            uint slices = subgroupMax(binningSlices(t.bounds));
            uint last = subgroupMax(ti);
            if (subgroupElect()) {
                if (slices > 1u) {
                    atomicMax(g_dispatch[DISPATCH_BINNING * 4u + 1u], slices);
                }
                if (SLABS > 1u) {
                    atomicMin(g_counters.depthLo, nearest);
                    atomicMax(g_counters.depthHi, farthest);
                }
                atomicAdd(g_counters.triangleCount, keptCount);
                uvec2 groups = splitGroups(
                    ((last + 1u) * ROW_LANES + BINNING_GROUP_SIZE - 1u) / BINNING_GROUP_SIZE);
                atomicMax(g_dispatch[DISPATCH_BINNING * 4u], groups.x);
                atomicMax(g_dispatch[DISPATCH_BINNING * 4u + 2u], groups.y);
            }
            storeTriangle(ti, t, v, negated);
        } else {
            storeHole(ti);
        }
    } while (++sub < subCount);
    if (subCount == 1u) {
        storeHole(item * 2u + 1u);
    }
    if (kept) {
        storeAttributes(item, draw, k0, k1, k2, k3);
    }
}
