// What the wavelet passes that draw the scene (bounds, accumulate, shade) know of a fragment:
// the mesh pipelines' inputs and its order depth.
#ifndef TRANSLUCID_WAVELET_FRAGMENT_GLSL
#define TRANSLUCID_WAVELET_FRAGMENT_GLSL

#include "mesh_fragment.glsl"
#include "wavelet_constants.glsl"

// The fragment's order depth (raster::order_depth). With ORDER_DEPTH (the pipelines with
// scene/ordered.geom), the reference's own, from the triangle's fixed-point setup at the pixel
// centre, so that every pass places the fragment where the CPU model does. The driver's
// depth differs from it in the last bits: where a pixel's fragments meet at one depth (at a
// shared vertex, or coplanar) the reference's depth range is 0 and the driver's is not, and
// the model's one cell becomes the driver's whole range (spheres under an orthographic camera:
// a pole 3.2/255 off). Without ORDER_DEPTH (devices without a geometry stage), the driver's.
float waveletFragmentDepth() {
#ifdef ORDER_DEPTH
    return fragmentOrderDepth();
#else
    return WAVELET_FRAGMENT_DEPTH(u_frame.depthMapping);
#endif
}

#endif
