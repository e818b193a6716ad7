#version 450
// Sorts each CSR row in place by index (mode 1) or by (squared distance, index) (mode 2).
// One thread per row; Shell sort (gaps 1, 4, 13, 40, ...): in place, as fast as insertion sort
// on the short rows of typical data, and ~m^1.3 instead of m^2 on the long rows of dense
// clusters.
#define FRNN_STATUS_BINDING 3
#include "common.glsl"
layout(local_size_x = FRNN_GROUP_SIZE) in;

layout(std430, binding = 0) readonly buffer offsets_block { uint offsets[]; };
layout(std430, binding = 1) buffer indices_block { uint indices[]; };
layout(std430, binding = 2) buffer d2_block { float dist2[]; };
layout(push_constant) uniform push_block {
    uint rows;       // rows of this chunk
    uint mode;
    uint with_d2;
    uint row_begin;  // first row of the chunk; its pairs start at index 0 of the buffers
} pc;

bool before(float da, uint ia, float db, uint ib) {
    if (pc.mode == 2u) return da < db || (da == db && ia < ib);
    return ia < ib;
}

void main() {
    const uint t = frnn_thread_index();
    if (t >= pc.rows) return;
    const uint row = pc.row_begin + t, base = offsets[pc.row_begin];
    const uint b = offsets[row] - base, e = offsets[row + 1u] - base;
    const uint len = e - b;
    const bool carry = pc.with_d2 != 0u;
    uint gap = 1u;
    while (gap < len / 3u) gap = 3u * gap + 1u;
    for (; gap > 0u; gap /= 3u) {
        uint k = b + gap;
        for (; k < e; ++k) {
            const uint idx = indices[k];
            const float d = carry ? dist2[k] : 0.0;
            uint p = k;
            while (p >= b + gap && before(d, idx, carry ? dist2[p - gap] : 0.0, indices[p - gap])) {
                indices[p] = indices[p - gap];
                if (carry) dist2[p] = dist2[p - gap];
                p -= gap;
            }
            if (p >= b + gap && before(d, idx, carry ? dist2[p - gap] : 0.0, indices[p - gap])) frnn_loop_cut();
            indices[p] = idx;
            if (carry) dist2[p] = d;
        }
        if (k < e) frnn_loop_cut();
    }
    if (gap > 0u) frnn_loop_cut();
}
