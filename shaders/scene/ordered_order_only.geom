#version 450
// The reference's triangle setup alone, for fragment stages that read only the order depth
// (depth_peeling's first pass, wavelet's bounds): common/ordered_geometry.glsl.

#define ORDER_ONLY
#include "ordered_geometry.glsl"
