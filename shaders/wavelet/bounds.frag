#version 450
// Pass 1, depth bounds: each pixel's nearest and farthest transparent order depth, kept by a
// MAX blend as (-depth, depth). The reference's order depth (ordered stages); bounds_driver_depth
// takes the driver's where the device has no geometry stage.

#define ORDER_DEPTH
#include "wavelet_bounds.glsl"
