#version 450
// Fills the CSR rows: neighbors in traversal order (fixed, since the sort is stable).
#define FRNN_QUERY_BINDING 8
#define FRNN_STATUS_BINDING 9
#include "query_common.glsl"
layout(local_size_x = FRNN_GROUP_SIZE) in;

layout(std430, binding = 5) readonly buffer offsets_block { uint offsets[]; };
layout(std430, binding = 6) writeonly buffer indices_block { uint indices[]; };
layout(std430, binding = 7) writeonly buffer d2_block { float dist2[]; };

void main() {
    const uint t = frnn_thread_index();
    if (t >= pc.rows) return;
    const uint row = frnn_row_of(t);
    if (row < pc.row_begin || row >= pc.row_end) return;
    uint out_pos = offsets[row] - offsets[pc.row_begin];
    const bool write_d2 = (pc.flags & FRNN_FLAG_DISTANCES) != 0u;
    frnn_iterator it = frnn_begin(frnn_row_point(t));
    uint j;
    float d2;
    while (frnn_next(it, j, d2)) {
        if (!frnn_keep(t, j)) continue;
        indices[out_pos] = frnn_result_index(j);
        if (write_d2) dist2[out_pos] = d2;
        ++out_pos;
    }
    if (!it.done) frnn_loop_cut();
}
