#version 450
// Test only: corrects a table of division estimates (rounded_division.glsl) so that a host
// test can compare each with Rust's correctly rounded `/`.

#include "rounded_division.glsl"

layout(local_size_x = 64) in;

struct DivisionCase {
    float a;
    float b;
    float estimate;
    float pad;
};

layout(set = 0, binding = 0, std430) readonly buffer CaseBlock { DivisionCase g_cases[]; };
layout(set = 0, binding = 1, std430) writeonly buffer ResultBlock { float g_results[]; };

layout(push_constant) uniform PushBlock { uint count; } u_push;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < u_push.count) {
        DivisionCase c = g_cases[i];
        g_results[i] = roundedQuotient(c.a, c.b, c.estimate);
    }
}
