// Set 0 of the compute stages that read the scene: frame constants, draws and materials
// (the same buffers the mesh pipelines bind; the push constant block is the stage's own).
#ifndef TRANSLUCID_SCENE_BINDINGS_COMPUTE_GLSL
#define TRANSLUCID_SCENE_BINDINGS_COMPUTE_GLSL

#include "interface_scene.glsl"

layout(set = 0, binding = 0, std140) uniform FrameBlock { FrameInfo u_frame; };
layout(set = 0, binding = 1, std430) readonly buffer DrawBlock { DrawInfo g_draws[]; };
layout(set = 0, binding = 2, std430) readonly buffer MaterialBlock { Material g_materials[]; };

#endif
