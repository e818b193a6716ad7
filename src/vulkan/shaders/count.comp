#version 450
// Neighbor count of every row (capped at pc.cap).
#define FRNN_QUERY_BINDING 6
#define FRNN_STATUS_BINDING 7
#include "query_common.glsl"
layout(local_size_x = FRNN_GROUP_SIZE) in;

layout(std430, binding = 5) writeonly buffer counts_block { uint counts[]; };

void main() {
    const uint t = frnn_thread_index();
    if (t >= pc.rows) return;
    frnn_iterator it = frnn_begin(frnn_row_point(t));
    uint j;
    float d2;
    uint c = 0u;
    while (frnn_next(it, j, d2))
        if (frnn_keep(t, j)) ++c;
    if (!it.done) frnn_loop_cut();
    counts[frnn_row_of(t)] = min(c, pc.cap);
}
