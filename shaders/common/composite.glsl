// The composite pass's interface (bins/composite.vert and .frag): one quad per block the
// rasters may have written, blending their transparent layer onto the opaque colour where
// it is (the frame target, or the engine's colour image).
#ifndef TRANSLUCID_COMPOSITE_GLSL
#define TRANSLUCID_COMPOSITE_GLSL

#include "bin_triangle.glsl"
#include "transparent_layer.glsl"

// The blocks with a non-empty bin, in block order (block_scan.comp): the composite's instances.
layout(set = 0, binding = 0, std430) readonly buffer RasterBinBlock { uint g_rasterBins[]; };
layout(set = 0, binding = 1, rg32ui) uniform readonly uimage2D u_transparentLayer;
layout(set = 0, binding = 2, r32ui) uniform readonly uimage2D u_transparentLayerStamps;

layout(push_constant) uniform CompositePush {
    uint binsX;   // blocks across
    uint stamp;   // the submission whose pixels are blended
    vec2 extent;  // the frame's size in pixels
} u_push;

#endif
