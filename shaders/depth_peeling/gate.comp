#version 450
// After the composite of a pass: when that pass left no pixel anything to peel, zeroes the
// indirect commands of the passes recorded after it (their draws, clears and composites, and
// this gate), so that they cost their render passes and nothing else.

layout(local_size_x = 64) in;

layout(push_constant) uniform Push {
    uint pass;   // the pass whose composite just ran
    uint draws;  // transparent draws in g_gate.draws
} u_push;

#include "interface_depth_peeling_gate.glsl"

void main() {
    if (g_flags.fragmentsLeft[u_push.pass] != 0u) {
        return;
    }
    uint draw = gl_GlobalInvocationID.x;
    if (draw == 0u) {
        g_gate.composite[0] = 0u;
        g_gate.clearDraw[1] = 0u;
        g_gate.gate[0] = 0u;
    }
    if (draw < u_push.draws) {
        g_gate.draws[draw * GATE_DRAW_WORDS + GATE_INSTANCE_COUNT] = 0u;
    }
}
