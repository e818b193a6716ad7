#version 450
// Scatter into slot order: slot start + index inside the slot (from the atomics, so the order
// inside a slot still depends on scheduling; the stable pass fixes it).
#include "common.glsl"
layout(local_size_x = FRNN_GROUP_SIZE) in;

layout(std430, binding = 0) readonly buffer start_block { uint start[]; };
layout(std430, binding = 1) readonly buffer slot_block { uint point_slot[]; };
layout(std430, binding = 2) readonly buffer rank_block { uint point_rank[]; };
layout(std430, binding = 3) writeonly buffer tmp_block { uint tmp[]; };
layout(push_constant) uniform push_block { uint count; } pc;

void main() {
    const uint i = frnn_thread_index();
    if (i >= pc.count) return;
    tmp[start[point_slot[i]] + point_rank[i]] = i;
}
