#version 450
// Composite, full screen: the weighted average colour covers (1 - revealage) of the pixel;
// dual-source blending puts it over the frame colour (dst = L + revealage * dst).

#include "wboit.glsl"

#include "interface_wboit.glsl"

layout(location = 0, index = 0) out vec4 o_radiance;
layout(location = 0, index = 1) out vec4 o_transmittance;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec3 radiance = texelFetch(u_radiance, pixel, 0).rgb;
    vec3 opacity = texelFetch(u_opacity, pixel, 0).rgb;
    vec3 revealage = exp(-texelFetch(u_absorbance, pixel, 0).rgb);
    vec3 average = radiance / max(opacity, vec3(WBOIT_MIN_OPACITY));
    o_radiance = vec4(average * (1.0 - revealage), 0.0);
    o_transmittance = vec4(revealage, 1.0);
}
