#version 450
#define WAVELET_RANK 2
#include "wavelet_shade.glsl"
