#version 450
#define WAVELET_RANK 3
#define ORDER_DEPTH
#include "wavelet_shade.glsl"
