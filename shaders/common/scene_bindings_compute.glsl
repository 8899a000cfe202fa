// Set 0 of the compute stages that read the scene: frame constants, draws and materials
// (the same buffers the mesh pipelines bind; the push constant block is the stage's own).
#ifndef TRANSLUCID_SCENE_BINDINGS_COMPUTE_GLSL
#define TRANSLUCID_SCENE_BINDINGS_COMPUTE_GLSL

#include "interface_scene_set.glsl"

#endif
