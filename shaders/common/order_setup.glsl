// What scene/ordered.geom hands each fragment of a triangle (flat): its setup under the
// reference's fixed-point rules, for mesh_fragment.glsl's order depth. Outputs of the
// geometry stage; inputs of the fragment stage, which defines ORDER_SETUP_IN.
#ifndef TRANSLUCID_ORDER_SETUP_GLSL
#define TRANSLUCID_ORDER_SETUP_GLSL

#ifdef ORDER_SETUP_IN
#define ORDER_SETUP_QUALIFIER flat in
#else
#define ORDER_SETUP_QUALIFIER flat out
#endif

// Snapped corners 0 and 1.
layout(location = 4) ORDER_SETUP_QUALIFIER ivec4 t_corners;
// Snapped corner 2, and in z the sign of the doubled area, or 0 when the triangle is not on
// the fixed-point path (its fragments take the driver's depth).
layout(location = 5) ORDER_SETUP_QUALIFIER ivec3 t_lastCorner;
// The corners' z_ndc, and 1 / |doubled area|.
layout(location = 6) ORDER_SETUP_QUALIFIER vec4 t_zNdc;
// The corners' 1 / w.
layout(location = 7) ORDER_SETUP_QUALIFIER vec3 t_invW;

#endif
