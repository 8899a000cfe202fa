#version 450
// One quad over listed block gl_InstanceIndex (two triangles, no vertex input); the viewport
// clips what passes the frame's edge.

#include "composite.glsl"

const vec2 CORNERS[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(0, 1), vec2(0, 1), vec2(1, 0), vec2(1, 1));

void main() {
    uint block = g_rasterBins[gl_InstanceIndex];
    vec2 origin = vec2(block % u_push.binsX, block / u_push.binsX);
    vec2 pixel = (origin + CORNERS[gl_VertexIndex]) * float(BIN_SIZE);
    gl_Position = vec4(pixel / u_push.extent * 2.0 - 1.0, 0.0, 1.0);
}
