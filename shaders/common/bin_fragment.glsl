// A pixel's fragment in the compute rasterizers (the exact raster, the wavelet bin raster):
// coverage and sampling of a triangle record at a pixel, and its shading, as the CPU
// reference does them. Needs scene_bindings_compute.glsl, bins_bindings.glsl, raster.glsl,
// texture_sampler.glsl and shading.glsl first.
#ifndef TRANSLUCID_BIN_FRAGMENT_GLSL
#define TRANSLUCID_BIN_FRAGMENT_GLSL

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_control_flow_attributes : require

#include "quad_attributes.glsl"

// What the scene needs, fixed when the pipeline is made. CPU drivers such as lavapipe run
// both sides of a divergent `if` under a mask, so code a scene cannot reach still costs on
// every fragment there; constants compile it away. The host sets them from the scene and
// falls back to the full shader if setup ever reports a triangle the constants excluded.
#include "interface_specialization.glsl"
#include "rounded_division.glsl"

// A triangle's attributes at its three corners, as shading interpolates them.
struct ShadingAttributes {
    vec4 colour0;           // vertex colours
    vec4 colour1;
    vec4 colour2;
    vec3 normal0;           // world-space vertex normals, or the face normal alone
    vec3 normal1;           // (TRIANGLE_FACE_NORMAL)
    vec3 normal2;
    vec2 uv0;
    vec2 uv1;
    vec2 uv2;
};

// What shading reads of triangle t's attributes, from its quad's record: only the texels the
// scene's constants let it use. A texel fetch is a call to the driver's sampling code on CPU
// drivers, which the compiler keeps even when nothing reads its result. The second triangle
// of a quad takes corners 0, 2 and 3; selects pick them, an array would be indexed at run
// time.
ShadingAttributes loadShadingAttributes(BinTriangle t) {
    uint quad = t.order >> 1;
    bool second = (t.order & 1u) != 0u;
    ShadingAttributes a;
    a.colour0 = vec4(1.0);
    a.colour1 = vec4(1.0);
    a.colour2 = vec4(1.0);
    if (VERTEX_COLOURS) {
        // Flat colours are interpolated all the same, so that the sum is the reference's.
        int at = colourTexel(quad);
        a.colour0 = uintBitsToFloat(texelFetch(u_attributeTexels, at));
        a.colour1 = a.colour0;
        a.colour2 = a.colour0;
        if (!FLAT_COLOURS) {
            a.colour1 = uintBitsToFloat(texelFetch(u_attributeTexels, at + (second ? 2 : 1)));
            a.colour2 = uintBitsToFloat(texelFetch(u_attributeTexels, at + (second ? 3 : 2)));
        }
    }
    a.normal0 = vec3(0.0);
    a.normal1 = vec3(0.0);
    a.normal2 = vec3(0.0);
    if (VERTEX_NORMALS) {
        // Corners 0 to 3: n.xyz, (n.w, m.xy), (m.zw, r.x), r.yzw; a face normal per triangle
        // in n.xyz and m.xyz.
        int at = normalTexel(quad);
        vec4 n = uintBitsToFloat(texelFetch(u_attributeTexels, at));
        vec4 m = uintBitsToFloat(texelFetch(u_attributeTexels, at + 1));
        vec4 r = uintBitsToFloat(texelFetch(u_attributeTexels, at + 2));
        vec3 corner2 = vec3(m.zw, r.x);
        bool face = FACE_NORMALS && (t.attributeFlags & TRIANGLE_FACE_NORMAL) != 0u;
        a.normal0 = face && second ? m.xyz : n.xyz;
        a.normal1 = second ? corner2 : vec3(n.w, m.xy);
        a.normal2 = second ? r.yzw : corner2;
    } else if (FACE_NORMALS) {
        int at = normalTexel(quad) + (second ? 1 : 0);
        a.normal0 = uintBitsToFloat(texelFetch(u_attributeTexels, at).xyz);
    }
    a.uv0 = vec2(0.0);
    a.uv1 = vec2(0.0);
    a.uv2 = vec2(0.0);
    if (TEXTURES) {
        int at = uvTexel(quad);
        vec4 uv01 = uintBitsToFloat(texelFetch(u_attributeTexels, at));
        vec4 uv23 = uintBitsToFloat(texelFetch(u_attributeTexels, at + 1));
        a.uv0 = uv01.xy;
        a.uv1 = second ? uv23.xy : uv01.zw;
        a.uv2 = second ? uv23.zw : uv23.xy;
    }
    return a;
}

// What shading reads of material i: only the texels the scene's constants let it use, as
// loadShadingAttributes. Without transmission a material's tint and reflectance do not
// matter (the reference's terms with them are exact zeros), nor its flags and texture
// without lighting and textures.
Material loadShadingMaterial(uint i) {
    int base = int(i) * 3;
    Material m;
    m.baseColour = uintBitsToFloat(texelFetch(u_materialTexels, base));
    m.tintTransmission = vec4(1.0, 1.0, 1.0, 0.0);
    m.reflectance = 0.0;
    m.alphaCutoff = -1.0;
    m.textureIndex = -1;
    m.flags = 0u;
    if (TRANSMISSION) {
        m.tintTransmission = uintBitsToFloat(texelFetch(u_materialTexels, base + 1));
    }
    if (TRANSMISSION || TEXTURES || VERTEX_NORMALS || FACE_NORMALS) {
        uvec4 last = texelFetch(u_materialTexels, base + 2);
        m.reflectance = uintBitsToFloat(last.x);
        m.alphaCutoff = uintBitsToFloat(last.y);
        m.textureIndex = int(last.z);
        m.flags = last.w;
    }
    return m;
}

// Triangle record i as shading needs it, for a fragment the walk already found: coverage and
// the depth test are done, so it skips the depths texel (without it the sample's depth is
// meaningless and unused).
BinTriangle loadShadingTriangle(uint i) {
    int base = int(i) * TRIANGLE_TEXELS;
    return unpackTriangle(i, texelFetch(u_triangleTexels, base),
                          texelFetch(u_triangleTexels, base + 1), uvec4(0u),
                          texelFetch(u_triangleTexels, base + 3));
}

// The depth fragments are ordered by (raster::order_depth): clip w, or under an orthographic
// camera, whose w is constant, z_ndc + 1 (positive, and never 0, which keys keep for "none").
float orderDepth(RasterSample s) {
    return ordersByZ() ? s.zNdc + 1.0 : s.viewDepth;
}

// Whether triangle t covers pixel (x, y), and the sample, its viewDepth the order depth. The
// edges decide on both paths (bounds only ever hold every covered sample; raster.rs), so t
// may come without bounds.
bool coverSample(BinTriangle t, uint x, uint y, out RasterSample s) {
    // One exit: glslang turns early returns in inlined functions into extra flags.
    bool take;
    if (HOMOGENEOUS_PATH && t.edgeB.w >= 0) {
        take = sampleHomogeneous(loadHomogeneous(t.edgeB.w), x, y, s);
    } else {
        i64vec3 edges;
        bool covered = coversFixed(t, x, y, edges);
        take = covered && interpolateFixed(t, edges, s);
    }
    s.viewDepth = orderDepth(s);
    return take;
}

bool sampleTriangle(BinTriangle t, uint x, uint y, out RasterSample s) {
    if (!HOMOGENEOUS_PATH || t.edgeB.w < 0) {
        return sampleFixed(t, x, y, s);
    }
    return sampleHomogeneous(loadHomogeneous(t.edgeB.w), x, y, s);
}

// d(barycentric)/dx and /dy at the pixel, as Triangle::barycentric_gradients computes them.
void barycentricGradients(BinTriangle t, uint x, uint y, out vec3 gx, out vec3 gy) {
    vec3 q;
    vec3 dqx;
    vec3 dqy;
    if (!HOMOGENEOUS_PATH || t.edgeB.w < 0) {
        [[unroll]] for (int k = 0; k < 3; k++) {
            int64_t e = edgeAt(t.edgeA[k], t.edgeB[k], t.edgeC[k], x, y);
            precise float lambda = float(e) * t.zNdc.w;
            precise float qk = lambda * t.invW[k];
            precise float dx = float(t.edgeA[k]) * 256.0 * t.zNdc.w * t.invW[k];
            precise float dy = float(t.edgeB[k]) * 256.0 * t.zNdc.w * t.invW[k];
            q[k] = qk;
            dqx[k] = dx;
            dqy[k] = dy;
        }
    } else {
        BinHomogeneous h = loadHomogeneous(t.edgeB.w);
        precise vec3 qq = vec3(lineAt(h.line0, x, y), lineAt(h.line1, x, y), lineAt(h.line2, x, y)) *
                          h.zInvDet.w;
        q = qq;
        precise vec3 ax = vec3(h.line0.x, h.line1.x, h.line2.x) * h.zInvDet.w;
        precise vec3 ay = vec3(h.line0.y, h.line1.y, h.line2.y) * h.zInvDet.w;
        dqx = ax;
        dqy = ay;
    }
    precise float sum = (q.x + q.y) + q.z;
    if (sum == 0.0) {
        gx = vec3(0.0);
        gy = vec3(0.0);
        return;
    }
    precise vec3 b = vec3(quotient(q.x, sum), quotient(q.y, sum), quotient(q.z, sum));
    precise float dsx = (dqx.x + dqx.y) + dqx.z;
    precise float dsy = (dqy.x + dqy.y) + dqy.z;
    precise vec3 nx = dqx - b * dsx;
    precise vec3 ny = dqy - b * dsy;
    precise vec3 rx = vec3(quotient(nx.x, sum), quotient(nx.y, sum), quotient(nx.z, sum));
    precise vec3 ry = vec3(quotient(ny.x, sum), quotient(ny.y, sum), quotient(ny.z, sum));
    gx = rx;
    gy = ry;
}

// Shades the fragment of triangle t at pixel (x, y).
void shadeFragment(BinTriangle t, uint x, uint y, RasterSample s, FrameInfo frame,
                   out vec3 radiance, out vec3 transmittance) {
    Material m = loadShadingMaterial(t.materialIndex);
    ShadingAttributes a = loadShadingAttributes(t);
    // Normals are only for lighting: a scene with no lit draw needs neither, and clearing
    // the flag compiles the lighting away (an `if` runs both sides on CPU drivers).
    if (!VERTEX_NORMALS && !FACE_NORMALS) {
        m.flags &= ~MATERIAL_LIT;
    }
    vec3 b = s.barycentric;

    // White vertices give the reference's sum of barycentrics exactly (1 * b is b).
    precise vec4 colour = VERTEX_COLOURS ? (a.colour0 * b.x + a.colour1 * b.y) + a.colour2 * b.z
                                         : vec4((b.x + b.y) + b.z);

    vec3 normal;
    if (FACE_NORMALS && (!VERTEX_NORMALS || (t.attributeFlags & TRIANGLE_FACE_NORMAL) != 0u)) {
        normal = a.normal0.xyz;
    } else {
        precise vec3 n = (a.normal0.xyz * b.x + a.normal1.xyz * b.y) + a.normal2.xyz * b.z;
        normal = n;
    }

    vec4 texel = vec4(1.0);
    if (TEXTURES && m.textureIndex >= 0) {
        BinTexture tex = loadTextureInfo(m.textureIndex);
        // Meshes without UVs read (0, 0) everywhere: level 0 at the origin, like the reference.
        if ((t.attributeFlags & TRIANGLE_HAS_UVS) == 0u) {
            texel = sampleBaseTexture(m.textureIndex, tex, vec2(0.0), 0.0);
        } else {
            vec2 uv0 = a.uv0;
            vec2 uv1 = a.uv1;
            vec2 uv2 = a.uv2;
            vec3 gx;
            vec3 gy;
            barycentricGradients(t, x, y, gx, gy);
            vec2 size = vec2(tex.width, tex.height);
            precise vec2 ux = ((uv0 * gx.x + uv1 * gx.y) + uv2 * gx.z) * size;
            precise vec2 uy = ((uv0 * gy.x + uv1 * gy.y) + uv2 * gy.z) * size;
            float rho = max(length(ux), length(uy));
            precise vec2 uv = (uv0 * b.x + uv1 * b.y) + uv2 * b.z;
            texel = sampleBaseTexture(m.textureIndex, tex, uv, log2(rho));
        }
    }
    shadeTransparent(m, frame, colour, texel, normal, radiance, transmittance);
}

#endif
