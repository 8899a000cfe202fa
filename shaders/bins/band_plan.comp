#version 450
// The plan of a band after the first (bin_scan.glsl says where it stands): one invocation.

#include "bin_scan.glsl"

layout(local_size_x = 1) in;

void main() {
    planBand();
}
