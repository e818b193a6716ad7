#version 450
// Bounding box of the points and the first non-finite coordinate, in one pass: a shared-memory
// reduction per workgroup, then one atomic per workgroup on order-preserving integer keys.
#include "common.glsl"
layout(local_size_x = FRNN_GROUP_SIZE) in;

layout(std430, binding = 0) readonly buffer pos_block { float pos[]; };
// [0, D): min keys, [D, 2D): max keys, [2D]: first bad point index (0xFFFFFFFF when none).
layout(std430, binding = 1) buffer box_block { uint box[]; };
layout(push_constant) uniform push_block { uint count; } pc;

shared uint s_min[FRNN_GROUP_SIZE];
shared uint s_max[FRNN_GROUP_SIZE];

// Monotone map float -> uint: a < b as floats iff key(a) < key(b).
uint key_of(float f) {
    const uint b = floatBitsToUint(f);
    return (b & 0x80000000u) != 0u ? ~b : (b | 0x80000000u);
}

void main() {
    const uint i = frnn_thread_index();
    const uint t = gl_LocalInvocationID.x;
    for (int a = 0; a < FRNN_DIM; ++a) {
        uint lo = 0xFFFFFFFFu, hi = 0u;
        if (i < pc.count) {
            const float x = pos[i * FRNN_DIM + a];
            if (isnan(x) || isinf(x)) {
                atomicMin(box[2 * FRNN_DIM], i);
            } else {
                lo = hi = key_of(x);
            }
        }
        s_min[t] = lo;
        s_max[t] = hi;
        barrier();
        for (uint w = FRNN_GROUP_SIZE / 2; w > 0u; w >>= 1) {
            if (t < w) {
                s_min[t] = min(s_min[t], s_min[t + w]);
                s_max[t] = max(s_max[t], s_max[t + w]);
            }
            barrier();
        }
        if (t == 0u) {
            atomicMin(box[a], s_min[0]);
            atomicMax(box[FRNN_DIM + a], s_max[0]);
        }
        barrier();
    }
}
