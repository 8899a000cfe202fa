#version 450
// mesh.vert for the pipelines that order fragments as the reference does (linked_list,
// depth_peeling): also hands ordered.geom each vertex's snapped position and depths.

#define ORDER_DEPTH
#include "mesh_vertex.glsl"
