#version 450
// The depth_peeling method's first pass: every transparent fragment nearer than the opaque
// layer widens its pixel's depth range (MAX blend), so that the passes after it know the
// nearest and farthest layer left, and is counted (summed), so that the host knows how many
// passes the deepest pixel needs.

#define ORDER_DEPTH
#include "mesh_fragment.glsl"
#include "depth_peeling.glsl"

layout(early_fragment_tests) in;

layout(location = 0) out vec2 o_range;
layout(location = 1) out float o_count;

void main() {
    float depth = fragmentOrderDepth();
    o_range = vec2(-depth, depth);
    o_count = 1.0;
}
