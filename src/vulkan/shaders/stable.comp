#version 450
// Makes the counting sort stable: inside its slot, a point's final place is the number of
// points of that slot with a smaller original index. O(points in the slot) per point, the same
// order of work as one query, and the sorted order no longer depends on scheduling.
// Also copies positions (wrapped into a periodic box) and cell coordinates into cell order.
#define FRNN_STATUS_BINDING 10
#define FRNN_GRID_PARAMS_ONLY
#include "frnn/grid.glsl"
#include "common.glsl"
layout(local_size_x = FRNN_GROUP_SIZE) in;

layout(std430, binding = 1) readonly buffer start_block { uint start[]; };
layout(std430, binding = 2) readonly buffer slot_block { uint point_slot[]; };
layout(std430, binding = 3) readonly buffer tmp_block { uint tmp[]; };
layout(std430, binding = 4) readonly buffer pos_block { float pos[]; };
layout(std430, binding = 5) readonly buffer cell_block { int point_cell[]; };
layout(std430, binding = 6) writeonly buffer perm_block { uint perm[]; };
layout(std430, binding = 7) writeonly buffer inverse_block { uint inverse_perm[]; };
layout(std430, binding = 8) writeonly buffer sorted_pos_block { float sorted_pos[]; };
layout(std430, binding = 9) writeonly buffer sorted_cell_block { int sorted_cell[]; };
layout(push_constant) uniform push_block { uint count; } pc;

void main() {
    const uint s = frnn_thread_index();
    if (s >= pc.count) return;
    const uint i = tmp[s];
    const uint slot = point_slot[i];
    const uint b = start[slot], e = start[slot + 1u];
    uint dst = b;
    uint t = b;
    for (; t < e; ++t) dst += tmp[t] < i ? 1u : 0u;
    if (t < e) frnn_loop_cut();
    perm[dst] = i;
    inverse_perm[i] = dst;
    for (int a = 0; a < FRNN_DIM; ++a) {
        const float x = pos[i * FRNN_DIM + a];
        sorted_pos[dst * FRNN_DIM + a] = frnn_wraps(a) ? frnn_wrap_into_box(x, frnn_grid.box[a]) : x;
        sorted_cell[dst * FRNN_DIM + a] = point_cell[i * FRNN_DIM + a];
    }
}
