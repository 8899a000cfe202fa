#version 450
// bounds.frag with the driver's depth, for devices without a geometry stage.

#include "wavelet_bounds.glsl"
