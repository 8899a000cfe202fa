#version 450
// The depth_peeling method's last step, one invocation per pixel: the front layers over the
// back layers over the frame's colour.

#include "colour.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

// composite.comp's, whose pass and last this ignores.
layout(push_constant) uniform Push {
    uint pass;
    uint last;
    uint width;
    uint height;
} u_push;

#include "interface_depth_peeling.glsl"

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(u_push.width) || pixel.y >= int(u_push.height)) {
        return;
    }
    vec4 colour = imageLoad(u_colour, pixel);
    vec3 behind = imageLoad(u_back, pixel).rgb + imageLoad(u_backT, pixel).rgb * colour.rgb;
    vec3 result = imageLoad(u_front, pixel).rgb + imageLoad(u_frontT, pixel).rgb * behind;
    imageStore(u_colour, pixel, vec4(storedColour(result), colour.a));
}
