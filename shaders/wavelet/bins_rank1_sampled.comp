#version 450
#define WAVELET_RANK 1
#define HARDWARE_SAMPLING
#include "wavelet_bins.glsl"
