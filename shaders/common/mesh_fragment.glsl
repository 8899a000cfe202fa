// Fragment-stage inputs of the mesh pipelines, and the per-fragment values shading needs.
#ifndef TRANSLUCID_MESH_FRAGMENT_GLSL
#define TRANSLUCID_MESH_FRAGMENT_GLSL

#include "scene_bindings.glsl"
#include "shading.glsl"

layout(location = 0) in vec3 v_fromEye;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in vec2 v_uv;
layout(location = 3) in vec4 v_colour;

vec4 sampleBaseTexture(Material m) {
    return m.textureIndex < 0 ? vec4(1.0) : texture(u_baseTexture, v_uv);
}

// The base texture at the level of detail the CPU reference takes (scene/texture.rs, the
// reference's TriangleShader::texel): from the exact screen-space derivatives of the
// perspective-correct UV at the pixel centre, where `texture` takes 2x2 differences of the UV
// itself, which are not its derivative under perspective (ClearCoatTest, TransmissionTest,
// GlassHurricaneCandleHolder and spot_blend at 480x270: up to 6.1/255 on 0.02 % of the pixels
// of a minified texture). uv / w and 1 / w (gl_FragCoord.w) are affine in screen space, so
// their differences across a quad are their exact gradients (helper invocations past the
// triangle's edge extrapolate the same planes), and d(uv) = (d(uv / w) - uv d(1 / w)) * w,
// the reference's quotient rule. A level of detail of 0 or less, or NaN, magnifies, as there.
// The derivatives are taken before the draw-uniform branch.
vec4 sampleBaseTextureAnalytic(Material m) {
    float q = gl_FragCoord.w;
    vec2 uvq = v_uv * q;
    vec2 dx = dFdx(uvq) - v_uv * dFdx(q);
    vec2 dy = dFdy(uvq) - v_uv * dFdy(q);
    if (m.textureIndex < 0) {
        return vec4(1.0);
    }
    vec2 size = vec2(textureSize(u_baseTexture, 0));
    float rho = max(length(dx / q * size), length(dy / q * size));
    float lod = log2(rho);
    return textureLod(u_baseTexture, v_uv, lod > 0.0 ? lod : 0.0);
}

// The interpolated normal, or the geometric face normal when the mesh has none (its sign
// does not matter: lighting is two-sided). The face normal comes from the position relative
// to the eye, whose differences between pixels keep their precision however far from the
// origin the scene is (world positions 10 km out left shading noise).
vec3 fragmentNormal(DrawInfo d) {
    if ((d.flags & DRAW_HAS_NORMALS) != 0u) {
        return v_normal;
    }
    return faceNormal(dFdx(v_fromEye), dFdy(v_fromEye));
}

#ifdef ORDER_DEPTH
#define ORDER_SETUP_IN
#include "order_setup.glsl"
#include "raster_rules.glsl"

// The fragment's depth in the reference's order (raster::order_depth): view depth (clip w)
// under a perspective, device depth plus one under an orthographic projection; computed as
// the reference computes it at this pixel's centre from scene/ordered.geom's setup, bit for
// bit, so that fragments at nearly one depth come out in the reference's order. A triangle
// off the fixed-point path (across the near plane, or past the guard band) takes the
// driver's depth.
float fragmentOrderDepth() {
    bool orthographic = u_frame.depthMapping.w > 0.5;
    int sign = t_lastCorner.z;
    if (sign == 0) {
        return orthographic ? gl_FragCoord.z + 1.0 : 1.0 / gl_FragCoord.w;
    }
    ivec2 v[3] = ivec2[3](t_corners.xy, t_corners.zw, t_lastCorner.xy);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    i64vec3 e;
    for (int k = 0; k < 3; k++) {
        ivec2 p = v[(k + 1) % 3];
        ivec2 q = v[(k + 2) % 3];
        int64_t c = int64_t(p.x) * int64_t(q.y) - int64_t(p.y) * int64_t(q.x);
        e[k] = edgeAt(sign * (p.y - q.y), sign * (q.x - p.x), int64_t(sign) * c, pixel.x, pixel.y);
    }
    RasterSample s = interpolateEdges(e, t_zNdc, t_invW);
    return orthographic ? s.zNdc + 1.0 : s.viewDepth;
}
#endif

#endif
