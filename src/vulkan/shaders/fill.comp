#version 450
// Fills the CSR rows: neighbors in traversal order (fixed, since the sort is stable).
#include "query_common.glsl"
layout(local_size_x = FRNN_GROUP_SIZE) in;

layout(std430, binding = 5) readonly buffer offsets_block { uint offsets[]; };
layout(std430, binding = 6) writeonly buffer indices_block { uint indices[]; };
layout(std430, binding = 7) writeonly buffer d2_block { float dist2[]; };

void main() {
    const uint s = frnn_thread_index();
    if (s >= frnn_grid.count) return;
    uint out_pos = offsets[frnn_result_index(s)];
    const bool write_d2 = (pc.flags & FRNN_FLAG_DISTANCES) != 0u;
    frnn_iterator it = frnn_begin(frnn_sorted_position(s));
    uint j;
    float d2;
    while (frnn_next(it, j, d2)) {
        if (!frnn_keep(s, j)) continue;
        indices[out_pos] = frnn_result_index(j);
        if (write_d2) dist2[out_pos] = d2;
        ++out_pos;
    }
}
