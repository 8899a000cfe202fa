// What every wavelet pass shares: its specialization constants (WAVELET_* in
// interface_specialization.glsl; nothing that changes with the camera: that is in the
// frame's FrameInfo), and the order depth of a graphics pass's fragment.
#ifndef TRANSLUCID_WAVELET_CONSTANTS_GLSL
#define TRANSLUCID_WAVELET_CONSTANTS_GLSL

#include "interface_specialization.glsl"

// The order depth of a graphics pass's fragment (raster::order_depth), for fragment shaders,
// given the frame's FrameInfo.depthMapping: z_ndc + 1 under an orthographic camera, else clip w.
#define WAVELET_FRAGMENT_DEPTH(mapping) \
    ((mapping).w != 0.0 ? gl_FragCoord.z + 1.0 : 1.0 / gl_FragCoord.w)

#endif
