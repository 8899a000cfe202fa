#version 450
// ordered.vert without the eye vector and the normal (ordered_unlit.geom).

#define ORDER_DEPTH
#define UNLIT
#include "mesh_vertex.glsl"
