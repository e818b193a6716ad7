#version 450
// k nearest within the radius: each row, sized min(k, count) by the count pass, keeps the best
// candidates sorted by (squared distance, index): a total order, so the result does not
// depend on traversal order.
#define FRNN_QUERY_BINDING 8
#define FRNN_STATUS_BINDING 9
#include "query_common.glsl"
layout(local_size_x = FRNN_GROUP_SIZE) in;

layout(std430, binding = 5) readonly buffer offsets_block { uint offsets[]; };
layout(std430, binding = 6) buffer indices_block { uint indices[]; };
layout(std430, binding = 7) buffer d2_block { float dist2[]; };

bool before(float da, uint ia, float db, uint ib) { return da < db || (da == db && ia < ib); }

void main() {
    const uint t = frnn_thread_index();
    if (t >= pc.rows) return;
    const uint row = frnn_row_of(t);
    if (row < pc.row_begin || row >= pc.row_end) return;
    const uint b = offsets[row] - offsets[pc.row_begin];
    const uint cap = offsets[row + 1u] - offsets[row];
    if (cap == 0u) return;
    uint len = 0u;
    frnn_iterator it = frnn_begin(frnn_row_point(t));
    uint j;
    float d2;
    while (frnn_next(it, j, d2)) {
        if (!frnn_keep(t, j)) continue;
        const uint idx = frnn_result_index(j);
        if (len == cap && !before(d2, idx, dist2[b + len - 1u], indices[b + len - 1u])) continue;
        // Insertion into the sorted row, dropping the last entry when full.
        uint p = len < cap ? len++ : cap - 1u;
        while (p > 0u && before(d2, idx, dist2[b + p - 1u], indices[b + p - 1u])) {
            dist2[b + p] = dist2[b + p - 1u];
            indices[b + p] = indices[b + p - 1u];
            --p;
        }
        if (p > 0u && before(d2, idx, dist2[b + p - 1u], indices[b + p - 1u])) frnn_loop_cut();
        dist2[b + p] = d2;
        indices[b + p] = idx;
    }
    if (!it.done) frnn_loop_cut();
}
