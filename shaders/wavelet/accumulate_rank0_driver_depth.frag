#version 450
#define WAVELET_RANK 0
#include "wavelet_accumulate.glsl"
