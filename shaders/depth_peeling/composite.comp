#version 450
// After each peeling pass, one invocation per pixel: the pass's front layer goes under the
// layers peeled from the front so far, its back layer over those peeled from the back; and
// whether the pixel has fragments left is noted for the next pass (which is skipped when no
// pixel has any) and, after the last pass, counted.

#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require

#include "depth_peeling.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(push_constant) uniform Push {
    uint pass;   // 1 for the first peeling pass
    uint last;   // 1 for the last pass recorded
    uint width;
    uint height;
} u_push;

#include "interface_depth_peeling.glsl"

// The pass's front layer's radiance and transmittance, from its three channel images.
void readFront(ivec2 pixel, out vec3 radiance, out vec3 transmittance) {
    vec2 r = texelFetch(u_frontLayer[0], pixel, 0).ra;
    vec2 g = texelFetch(u_frontLayer[1], pixel, 0).ra;
    vec2 b = texelFetch(u_frontLayer[2], pixel, 0).ra;
    radiance = vec3(r.x, g.x, b.x);
    transmittance = vec3(r.y, g.y, b.y);
}

// The same of its back layer.
void readBack(ivec2 pixel, out vec3 radiance, out vec3 transmittance) {
    vec2 r = texelFetch(u_backLayer[0], pixel, 0).ra;
    vec2 g = texelFetch(u_backLayer[1], pixel, 0).ra;
    vec2 b = texelFetch(u_backLayer[2], pixel, 0).ra;
    radiance = vec3(r.x, g.x, b.x);
    transmittance = vec3(r.y, g.y, b.y);
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(u_push.width) || pixel.y >= int(u_push.height)) {
        return;
    }
    vec3 frontL, frontT, backL, backT;
    readFront(pixel, frontL, frontT);
    readBack(pixel, backL, backT);
    if (u_push.pass == 1u) {
        // One atomic a subgroup: one a pixel made a single word the frame's most contended.
        uint most = subgroupMax(uint(texelFetch(u_fragments, pixel, 0).r));
        if (subgroupElect()) {
            atomicMax(g_peeling.mostFragments, most);
        }
    } else {
        vec3 front = imageLoad(u_front, pixel).rgb;
        vec3 frontSoFar = imageLoad(u_frontT, pixel).rgb;
        vec3 back = imageLoad(u_back, pixel).rgb;
        vec3 backSoFar = imageLoad(u_backT, pixel).rgb;
        frontL = front + frontSoFar * frontL;
        frontT = frontSoFar * frontT;
        backL = backL + backT * back;
        backT = backT * backSoFar;
    }
    imageStore(u_front, pixel, vec4(frontL, 0.0));
    imageStore(u_frontT, pixel, vec4(frontT, 0.0));
    imageStore(u_back, pixel, vec4(backL, 0.0));
    imageStore(u_backT, pixel, vec4(backT, 0.0));

    if (rangeHolds(texelFetch(u_range, pixel, 0).xy)) {
        g_peeling.fragmentsLeft[u_push.pass] = 1u;
        if (u_push.last != 0u) {
            atomicAdd(g_peeling.unpeeledPixels, 1u);
        }
    }
}
