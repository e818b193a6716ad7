#version 450
// Neighbor count of every point (capped at pc.cap), written to its row.
#include "query_common.glsl"
layout(local_size_x = FRNN_GROUP_SIZE) in;

layout(std430, binding = 5) writeonly buffer counts_block { uint counts[]; };

void main() {
    const uint s = frnn_thread_index();
    if (s >= frnn_grid.count) return;
    frnn_iterator it = frnn_begin(frnn_sorted_position(s));
    uint j;
    float d2;
    uint c = 0u;
    while (frnn_next(it, j, d2))
        if (frnn_keep(s, j)) ++c;
    counts[frnn_result_index(s)] = min(c, pc.cap);
}
