#version 450
#define WAVELET_RANK 2
#define ORDER_DEPTH
#include "wavelet_shade.glsl"
