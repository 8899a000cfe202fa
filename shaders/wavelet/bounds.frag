#version 450
// Pass 1, depth bounds: each pixel's nearest and farthest transparent view depth, kept by a
// MAX blend as (-view depth, view depth).

layout(location = 0) out vec2 o_bounds;

void main() {
    float viewDepth = 1.0 / gl_FragCoord.w;
    o_bounds = vec2(-viewDepth, viewDepth);
}
