#version 450
// The first draw of a peeling pass: the range and the six layer channels as the pass starts,
// an empty range and empty layers (no radiance, full transmittance). Drawn rather than
// cleared on load, so that a pass the gate skips skips its clears too.

#include "depth_peeling.glsl"

layout(location = 0) out vec2 o_range;
layout(location = 1) out vec4 o_frontRed;
layout(location = 2) out vec4 o_frontGreen;
layout(location = 3) out vec4 o_frontBlue;
layout(location = 4) out vec4 o_backRed;
layout(location = 5) out vec4 o_backGreen;
layout(location = 6) out vec4 o_backBlue;

void main() {
    const vec4 empty = vec4(0.0, 0.0, 0.0, 1.0);
    o_range = NO_RANGE;
    o_frontRed = empty;
    o_frontGreen = empty;
    o_frontBlue = empty;
    o_backRed = empty;
    o_backGreen = empty;
    o_backBlue = empty;
}
