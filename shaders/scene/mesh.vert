#version 450
// Transforms a scene vertex for the opaque layer and the mesh pipelines of the methods.

#include "mesh_vertex.glsl"
