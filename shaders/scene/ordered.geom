#version 450
// The reference's triangle setup for fragment stages that shade (common/ordered_geometry.glsl).

#include "ordered_geometry.glsl"
