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

// The fragment's depth in the reference's order (raster::order_depth): view depth (clip w)
// under a perspective, device depth plus one under an orthographic projection.
float fragmentOrderDepth() {
    return u_frame.depthMapping.w > 0.5 ? gl_FragCoord.z + 1.0 : 1.0 / gl_FragCoord.w;
}

#endif
