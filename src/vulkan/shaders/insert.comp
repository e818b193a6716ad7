#version 450
// Insertion: the cell of each point, its slot, and its index inside the slot (atomicAdd on the
// per-slot counts). The counts become slot starts after the exclusive scan.
#define FRNN_GRID_PARAMS_ONLY
#include "frnn/grid.glsl"
#include "common.glsl"
layout(local_size_x = FRNN_GROUP_SIZE) in;

layout(std430, binding = 1) readonly buffer pos_block { float pos[]; };
layout(std430, binding = 2) buffer counts_block { uint counts[]; };
layout(std430, binding = 3) writeonly buffer slot_block { uint point_slot[]; };
layout(std430, binding = 4) writeonly buffer rank_block { uint point_rank[]; };
layout(std430, binding = 5) writeonly buffer cell_block { int point_cell[]; };

void main() {
    const uint i = frnn_thread_index();
    if (i >= frnn_grid.count) return;
    frnn_vec x;
    for (int a = 0; a < FRNN_DIM; ++a) x[a] = pos[i * FRNN_DIM + a];
    const frnn_ivec c = frnn_cell_of(x);
    for (int a = 0; a < FRNN_DIM; ++a) point_cell[i * FRNN_DIM + a] = c[a];
    const uint slot = frnn_slot_of(c);
    point_slot[i] = slot;
    point_rank[i] = atomicAdd(counts[slot], 1u);
}
