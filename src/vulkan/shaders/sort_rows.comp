#version 450
// Sorts each CSR row in place by index (mode 1) or by (squared distance, index) (mode 2).
// Insertion sort, one thread per row: rows are short (tens of neighbors).
#include "common.glsl"
layout(local_size_x = FRNN_GROUP_SIZE) in;

layout(std430, binding = 0) readonly buffer offsets_block { uint offsets[]; };
layout(std430, binding = 1) buffer indices_block { uint indices[]; };
layout(std430, binding = 2) buffer d2_block { float dist2[]; };
layout(push_constant) uniform push_block {
    uint rows;
    uint mode;
    uint with_d2;
} pc;

bool before(float da, uint ia, float db, uint ib) {
    if (pc.mode == 2u) return da < db || (da == db && ia < ib);
    return ia < ib;
}

void main() {
    const uint row = frnn_thread_index();
    if (row >= pc.rows) return;
    const uint b = offsets[row], e = offsets[row + 1u];
    const bool carry = pc.with_d2 != 0u;
    for (uint k = b + 1u; k < e; ++k) {
        const uint idx = indices[k];
        const float d = carry ? dist2[k] : 0.0;
        uint p = k;
        while (p > b && before(d, idx, carry ? dist2[p - 1u] : 0.0, indices[p - 1u])) {
            indices[p] = indices[p - 1u];
            if (carry) dist2[p] = dist2[p - 1u];
            --p;
        }
        indices[p] = idx;
        if (carry) dist2[p] = d;
    }
}
