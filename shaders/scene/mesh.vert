#version 450
// Transforms a scene vertex for the opaque layer and the blend method.

#include "scene_bindings.glsl"

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec4 a_colour;

layout(location = 0) out vec3 v_fromEye;       // world position minus the eye
layout(location = 1) out vec3 v_normal;
layout(location = 2) out vec2 v_uv;
layout(location = 3) out vec4 v_colour;

void main() {
    DrawInfo d = g_draws[u_push.drawIndex];
    vec4 world = d.model * vec4(a_position, 1.0);
    v_fromEye = world.xyz - u_frame.eye.xyz;
    v_normal = mat3(d.normalMatrix) * a_normal;
    v_uv = a_uv;
    v_colour = a_colour * d.tint;
    gl_Position = u_frame.viewProj * world;
}
