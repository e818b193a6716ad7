// Shared by the query shaders: which pairs a row keeps (half, self) and how rows and
// neighbors are numbered (caller's order or cell order).
#ifndef FRNN_QUERY_COMMON_GLSL
#define FRNN_QUERY_COMMON_GLSL
#include "frnn/grid.glsl"
#include "common.glsl"

#define FRNN_FLAG_HALF 1u
#define FRNN_FLAG_SELF 2u
#define FRNN_FLAG_ORIGINAL 4u
#define FRNN_FLAG_DISTANCES 8u

layout(push_constant) uniform push_block {
    uint flags;
    uint cap;    // at most this many neighbors per row (k of k-nearest; 0xFFFFFFFF otherwise)
} pc;

// Index of sorted point s in the numbering of the results.
uint frnn_result_index(uint s) {
    return (pc.flags & FRNN_FLAG_ORIGINAL) != 0u ? frnn_perm[s] : s;
}

// Whether the pair (row point s, neighbor j) belongs to the results.
bool frnn_keep(uint s, uint j) {
    if (j == s) return (pc.flags & FRNN_FLAG_SELF) != 0u;
    if ((pc.flags & FRNN_FLAG_HALF) != 0u) return frnn_result_index(j) > frnn_result_index(s);
    return true;
}
#endif
