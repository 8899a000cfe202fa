#version 450
#define WAVELET_RANK 0
#define ORDER_DEPTH
#include "wavelet_shade.glsl"
