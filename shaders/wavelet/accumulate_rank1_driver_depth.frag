#version 450
#define WAVELET_RANK 1
#include "wavelet_accumulate.glsl"
