#version 450
#define WAVELET_RANK 3
#define HARDWARE_SAMPLING
#include "wavelet_bins.glsl"
