// Descriptor sets of the mesh pipelines (opaque layer and blend). Set 0: frame constants,
// draws and materials. Set 1: the draw's base-colour texture, bound per draw (lavapipe, like
// many Vulkan 1.2 devices, cannot index sampler arrays dynamically). Push constant: the draw
// index.
#ifndef TRANSLUCID_SCENE_BINDINGS_GLSL
#define TRANSLUCID_SCENE_BINDINGS_GLSL

#include "interface_scene_set.glsl"
#include "interface_base_texture.glsl"

layout(push_constant) uniform PushBlock { uint drawIndex; } u_push;

#endif
