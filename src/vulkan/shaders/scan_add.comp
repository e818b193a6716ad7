#version 450
// Exclusive prefix sum, back-propagation: adds the scanned total of the preceding blocks.
#include "common.glsl"
#define FRNN_SCAN_BLOCK 1024
layout(local_size_x = 256) in;

layout(std430, binding = 0) buffer data_block { uint data[]; };
layout(std430, binding = 1) readonly buffer sums_block { uint sums[]; };
layout(push_constant) uniform push_block { uint count; } pc;

void main() {
    const uint i = frnn_thread_index();
    if (i >= pc.count) return;
    data[i] = frnn_sat_add(data[i], sums[i / FRNN_SCAN_BLOCK]);
}
