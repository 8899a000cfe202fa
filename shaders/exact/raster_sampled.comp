#version 450
// The exact bin raster, sampling textures in hardware (docs/gpu.md).
#define HARDWARE_SAMPLING
#include "exact_raster.glsl"
