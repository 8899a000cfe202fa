#version 450
#define WAVELET_RANK 3
#include "wavelet_accumulate.glsl"
