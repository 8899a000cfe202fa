// Specialization constants of every wavelet pass (nothing that changes with the camera: that
// is in the frame's FrameInfo). Host mirror: SpecConstants in
// crates/translucid/src/methods/wavelet/layout.rs (a test compares the two). They start at
// WAVELET_CONSTANT_ID: 0 in the graphics passes; the bin raster (wavelet_bins.glsl) puts them
// after the exact raster's own.
#ifndef TRANSLUCID_WAVELET_CONSTANTS_GLSL
#define TRANSLUCID_WAVELET_CONSTANTS_GLSL

#ifndef WAVELET_CONSTANT_ID
#define WAVELET_CONSTANT_ID 0
#endif
layout(constant_id = WAVELET_CONSTANT_ID + 0) const int WAVELET_FIRST_TEXEL = 0;  // accumulation: first texel written
layout(constant_id = WAVELET_CONSTANT_ID + 1) const float WAVELET_NOISE = 0.0;    // depth noise strength, in cells
layout(constant_id = WAVELET_CONSTANT_ID + 2) const float WAVELET_ABSORBED = 7.6; // absorbance treated as opaque
// The order depth of a graphics pass's fragment (raster::order_depth), for fragment shaders,
// given the frame's FrameInfo.depthMapping: z_ndc + 1 under an orthographic camera, else clip w.
#define WAVELET_FRAGMENT_DEPTH(mapping) \
    ((mapping).w != 0.0 ? gl_FragCoord.z + 1.0 : 1.0 / gl_FragCoord.w)

#endif
