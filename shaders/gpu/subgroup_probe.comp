#version 450
// How many lanes a subgroup really holds in a workgroup of RASTER_GROUP_SIZE invocations
// held to whole subgroups (gpu::subgroup_probe): a driver may report a subgroup size its
// compute shaders do not reach (lavapipe at LP_NATIVE_VECTOR_WIDTH 1024 reports 32 and runs
// 16), and the bin rasters' tiles must be what a subgroup really holds.

#extension GL_KHR_shader_subgroup_ballot : require

#include "interface_specialization.glsl"

layout(local_size_x_id = RASTER_GROUP_SIZE_ID) in;

layout(set = 0, binding = 0, std430) buffer ProbeBlock { uint g_fewestLanes; };

void main() {
    uint lanes = subgroupBallotBitCount(subgroupBallot(true));
    if (subgroupElect()) {
        atomicMin(g_fewestLanes, lanes);
    }
}
