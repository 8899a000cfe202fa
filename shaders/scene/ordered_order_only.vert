#version 450
// ordered.vert handing on nothing but what the order depth needs (ordered_order_only.geom).

#define ORDER_DEPTH
#define ORDER_ONLY
#include "mesh_vertex.glsl"
