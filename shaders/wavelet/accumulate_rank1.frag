#version 450
#define WAVELET_RANK 1
#define ORDER_DEPTH
#include "wavelet_accumulate.glsl"
