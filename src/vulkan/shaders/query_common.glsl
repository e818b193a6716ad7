// Shared by the query shaders: where a row's point comes from (a grid point, or an external
// query point), which pairs a row keeps (half, self) and how rows and neighbors are numbered
// (caller's order or cell order). Each shader defines FRNN_QUERY_BINDING first.
#ifndef FRNN_QUERY_COMMON_GLSL
#define FRNN_QUERY_COMMON_GLSL
#include "frnn/grid.glsl"
#include "common.glsl"

#define FRNN_FLAG_HALF 1u
#define FRNN_FLAG_SELF 2u
#define FRNN_FLAG_ORIGINAL 4u
#define FRNN_FLAG_DISTANCES 8u
#define FRNN_FLAG_EXTERNAL 16u  // rows are the query points of binding FRNN_QUERY_BINDING

layout(push_constant) uniform push_block {
    uint flags;
    uint cap;    // at most this many neighbors per row (k of k-nearest; 0xFFFFFFFF otherwise)
    uint rows;   // number of rows (grid points or query points)
    uint row_begin, row_end;  // fill and knn: the rows of this chunk; their pairs start at
                              // offsets[row_begin] in the output buffers
} pc;

layout(std430, binding = FRNN_QUERY_BINDING) readonly buffer query_block { float query_pos[]; };

bool frnn_external() { return (pc.flags & FRNN_FLAG_EXTERNAL) != 0u; }

// Index of sorted point s in the numbering of the results.
uint frnn_result_index(uint s) {
    return (pc.flags & FRNN_FLAG_ORIGINAL) != 0u ? frnn_perm[s] : s;
}

// The row written by thread t (a grid point in cell order, or query point t).
uint frnn_row_of(uint t) { return frnn_external() ? t : frnn_result_index(t); }

// The point whose neighbors row t holds.
frnn_vec frnn_row_point(uint t) {
    if (!frnn_external()) return frnn_sorted_position(t);
    frnn_vec x;
    for (int a = 0; a < FRNN_DIM; ++a) x[a] = query_pos[t * FRNN_DIM + a];
    return x;
}

// Whether the pair (row t, neighbor j) belongs to the results; query points keep every pair.
bool frnn_keep(uint t, uint j) {
    if (frnn_external()) return true;
    if (j == t) return (pc.flags & FRNN_FLAG_SELF) != 0u;
    if ((pc.flags & FRNN_FLAG_HALF) != 0u) return frnn_result_index(j) > frnn_result_index(t);
    return true;
}
#endif
