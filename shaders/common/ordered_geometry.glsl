// The body of scene/ordered*.geom, between ordered.vert and the fragment stages of linked_list,
// depth_peeling and wavelet's coefficient images: sets each triangle up as the CPU reference
// does (raster.rs, fixed-point path), so that its fragments can find the reference's order
// depth (mesh_fragment.glsl) instead of the driver's, whose rounding differs. Surfaces at
// nearly one depth (coplanar, or mirror images meeting) are then ordered as the reference
// orders them. The triangle passes through unchanged. With ORDER_ONLY it hands on the order
// setup alone, for fragment stages that read nothing else (no output left unread); with
// UNLIT, everything but the eye vector and the normal, for those that shade transmittance
// alone.
#ifndef TRANSLUCID_ORDERED_GEOMETRY_GLSL
#define TRANSLUCID_ORDERED_GEOMETRY_GLSL

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

#ifndef ORDER_ONLY
#ifndef UNLIT
layout(location = 0) in vec3 v_fromEye[];
layout(location = 1) in vec3 v_normal[];
#endif
layout(location = 2) in vec2 v_uv[];
layout(location = 3) in vec4 v_colour[];
#endif
layout(location = 4) flat in ivec3 v_snapped[];
layout(location = 5) in vec2 v_depth[];

#ifndef ORDER_ONLY
#ifndef UNLIT
layout(location = 0) out vec3 o_fromEye;
layout(location = 1) out vec3 o_normal;
#endif
layout(location = 2) out vec2 o_uv;
layout(location = 3) out vec4 o_colour;
#endif
#include "order_setup.glsl"
#include "rounded_division.glsl"

void main() {
    ivec2 p0 = v_snapped[0].xy;
    ivec2 p1 = v_snapped[1].xy;
    ivec2 p2 = v_snapped[2].xy;
    // The doubled signed area, in 64 bits as setup.comp has it.
    int64_t area2 = (int64_t(p0.x) * p1.y - int64_t(p1.x) * p0.y) +
                    (int64_t(p1.x) * p2.y - int64_t(p2.x) * p1.y) +
                    (int64_t(p2.x) * p0.y - int64_t(p0.x) * p2.y);
    bool fixedPath = v_snapped[0].z != 0 && v_snapped[1].z != 0 && v_snapped[2].z != 0 &&
                     area2 != 0;
    precise float invArea = quotient(1.0, float(abs(area2)));
    for (int i = 0; i < 3; i++) {
        gl_Position = gl_in[i].gl_Position;
        gl_PrimitiveID = gl_PrimitiveIDIn;
#ifndef ORDER_ONLY
#ifndef UNLIT
        o_fromEye = v_fromEye[i];
        o_normal = v_normal[i];
#endif
        o_uv = v_uv[i];
        o_colour = v_colour[i];
#endif
        t_corners = ivec4(p0, p1);
        t_lastCorner = ivec3(p2, fixedPath ? (area2 > 0 ? 1 : -1) : 0);
        t_zNdc = vec4(v_depth[0].x, v_depth[1].x, v_depth[2].x, invArea);
        t_invW = vec3(v_depth[0].y, v_depth[1].y, v_depth[2].y);
        EmitVertex();
    }
    EndPrimitive();
}

#endif
