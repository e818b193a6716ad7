#version 450
// Exclusive prefix sum, level 1 of a multi-level scan: each workgroup scans one block of
// FRNN_SCAN_BLOCK values in place and writes the block's total to sums[block]. Plain shared
// memory (no subgroup operations), so it is correct for any subgroup size.
#include "common.glsl"
#define FRNN_SCAN_THREADS 256
#define FRNN_SCAN_PER_THREAD 4
#define FRNN_SCAN_BLOCK (FRNN_SCAN_THREADS * FRNN_SCAN_PER_THREAD)
layout(local_size_x = FRNN_SCAN_THREADS) in;

layout(std430, binding = 0) buffer data_block { uint data[]; };
layout(std430, binding = 1) writeonly buffer sums_block { uint sums[]; };
layout(push_constant) uniform push_block { uint count; } pc;

shared uint s_part[FRNN_SCAN_THREADS];

void main() {
    const uint block = frnn_group_index();
    // Groups past the last block exist when a large dispatch is split into rows.
    if (block * FRNN_SCAN_BLOCK >= pc.count) return;  // uniform over the workgroup
    const uint t = gl_LocalInvocationID.x;
    const uint base = block * FRNN_SCAN_BLOCK + t * FRNN_SCAN_PER_THREAD;
    uint v[FRNN_SCAN_PER_THREAD];
    uint total = 0u;
    for (int k = 0; k < FRNN_SCAN_PER_THREAD; ++k) {
        v[k] = base + k < pc.count ? data[base + k] : 0u;
        total = frnn_sat_add(total, v[k]);
    }
    // Inclusive Hillis-Steele scan of the per-thread totals.
    s_part[t] = total;
    barrier();
    for (uint w = 1u; w < FRNN_SCAN_THREADS; w <<= 1) {
        const uint add = t >= w ? s_part[t - w] : 0u;
        barrier();
        s_part[t] = frnn_sat_add(s_part[t], add);
        barrier();
    }
    uint run = t > 0u ? s_part[t - 1u] : 0u;
    for (int k = 0; k < FRNN_SCAN_PER_THREAD; ++k) {
        if (base + k < pc.count) data[base + k] = run;
        run = frnn_sat_add(run, v[k]);
    }
    if (t == FRNN_SCAN_THREADS - 1u) sums[block] = s_part[t];
}
