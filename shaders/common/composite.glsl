// The composite pass's interface (bins/composite.vert and .frag): one quad per block the
// rasters may have written, blending their transparent layer onto the opaque colour where
// it is (the frame target, or the engine's colour image).
#ifndef TRANSLUCID_COMPOSITE_GLSL
#define TRANSLUCID_COMPOSITE_GLSL

#include "bin_triangle.glsl"
#include "transparent_layer.glsl"

#include "interface_composite.glsl"

layout(push_constant) uniform CompositePushBlock { CompositePush u_push; };

#endif
