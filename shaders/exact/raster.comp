#version 450
// The exact bin raster, sampling textures in software: bit for bit the CPU reference.
#include "exact_raster.glsl"
