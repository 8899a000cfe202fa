#version 450
// The reference's triangle setup for fragment stages that shade transmittance alone (wavelet's
// accumulate pass), handing on no eye vector or normal: common/ordered_geometry.glsl.

#define UNLIT
#include "ordered_geometry.glsl"
