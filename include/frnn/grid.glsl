// frnn/grid.glsl: the neighbor loop of an frnn Vulkan grid, for your own compute shaders.
//
// Include it after defining FRNN_DIM (2 or 3, default 3) and optionally FRNN_SET (descriptor
// set of the grid's buffers, default 0). The grid's buffers take bindings 0-4 of that set:
// bind them with frnn::vulkan::grid::shader_buffers() (or run the shader with
// frnn::vulkan::kernel, which does it). Your own buffers use bindings 5 and up.
//
//   frnn_iterator it = frnn_begin(frnn_sorted_position(s));
//   uint j; float d2;
//   while (frnn_next(it, j, d2)) { if (j != s) { ... } }
//
// s and j number the points in cell order ("sorted"); frnn_original_index(s) gives the
// caller's index. Every point j with |x - x_j| <= radius is visited exactly once, in a fixed
// order (rows of cells, then increasing original index), so sums are reproducible run to run.
// frnn_begin(x) takes any point x, not only grid points (for queries from other points).
// Cost: the (2*ceil(r/cell)+1)^d cells around x, ~27 cells' points in 3D with cell = r.
// After the loop, it.done is true unless the driver stopped it early (lavapipe stops the loops
// of a group of 8 invocations after 65535 iterations in all): test it to detect a cut result.
// Distances are computed with `precise` arithmetic, bit for bit like frnn's CPU grid; in a
// periodic box they use the minimum image on its periodic axes, d -= L * roundEven(d / L),
// between coordinates wrapped into [0, L) exactly (frnn_wrap_into_box; grid points are stored
// wrapped, and frnn_begin wraps x).
#ifndef FRNN_GRID_GLSL
#define FRNN_GRID_GLSL

#ifndef FRNN_DIM
#define FRNN_DIM 3
#endif
#ifndef FRNN_SET
#define FRNN_SET 0
#endif

#if FRNN_DIM == 3
#define frnn_vec vec3
#define frnn_ivec ivec3
#elif FRNN_DIM == 2
#define frnn_vec vec2
#define frnn_ivec ivec2
#else
#error "FRNN_DIM must be 2 or 3"
#endif

// Grid parameters, written by the host at build time (std430, 96 bytes).
struct frnn_grid_params {
    vec4 origin;      // lower corner of cell (0,0,0)
    vec4 inv_cell;    // 1 / cell edge, per axis
    ivec4 dims;       // uniform grid: cells per axis
    vec4 box;         // periodic box lengths (periodic grids only; 0 on an open axis)
    float radius;
    float radius2;    // radius * radius, the acceptance test d2 <= radius2
    uint count;       // number of points
    uint hashed;      // 0: uniform grid, 1: hashed grid
    uint mask;        // hashed: slots - 1
    uint slots;       // cells (uniform) or table slots (hashed)
    uint periodic;    // 1: a periodic axis, [0, L) where box > 0; uniform grid
    uint pad;
};

layout(std430, set = FRNN_SET, binding = 0) readonly buffer frnn_params_block {
    frnn_grid_params frnn_grid;
};

// The grid's kind as a specialization constant, so the driver compiles only the branch in use
// (2-3x faster loops): 0 uniform, 1 hashed, 2 periodic, 3 (default) read from the parameters
// at run time. frnn::vulkan::kernel sets it; with your own pipeline, set constant_id
// FRNN_KIND_CONSTANT_ID (default 0) to grid::shader_kind(), or leave the default.
#ifndef FRNN_KIND_CONSTANT_ID
#define FRNN_KIND_CONSTANT_ID 0
#endif
layout(constant_id = FRNN_KIND_CONSTANT_ID) const uint frnn_kind = 3u;

bool frnn_is_hashed() { return frnn_kind == 3u ? frnn_grid.hashed != 0u : frnn_kind == 1u; }
bool frnn_is_periodic() { return frnn_kind == 3u ? frnn_grid.periodic != 0u : frnn_kind == 2u; }
// Whether axis a wraps: a periodic grid's axes with a box length (the others are open).
bool frnn_wraps(int a) { return frnn_is_periodic() && frnn_grid.box[a] > 0.0; }

// x wrapped into [0, box) (x finite, box > 0) exactly as frnn/periodic_wrap.hpp does on the
// CPU: the remainder of |x| by long division, where each step subtracts box * 2^k from within
// a factor of 2 of the remainder (an exact subtraction), then box minus the remainder for a
// negative x, rounded once; a result that rounds up to box is 0. At most about 280 steps for
// a float many boxes out, none for a point in the box.
float frnn_wrap_into_box(float x, float box) {
    if (x >= 0.0 && x < box) return x;
    int box_exponent;
    frexp(box, box_exponent);
    precise float m = abs(x);
    while (m >= box) {
        int e;
        frexp(m, e);
        precise float k = ldexp(box, e - box_exponent);  // box's digits at m's exponent
        if (k > m) k = k * 0.5;
        m = m - k;
    }
    precise float w = m;
    if (x < 0.0 && m > 0.0) w = box - m;
    return w < box ? w : 0.0;
}

// Largest hashed cell coordinate: clamping is monotone, so far outliers share the border cells
// and stay exact (they are compared by distance anyway).
const float frnn_max_cell = 1073741824.0;

// Cell coordinate on one axis, before clamping (float, may be huge for outliers). Periodic
// axis: the coordinate wrapped into [0, L) first.
float frnn_cell_float(float x, int axis) {
    if (frnn_wraps(axis)) {
        precise float u = frnn_wrap_into_box(x, frnn_grid.box[axis]) * frnn_grid.inv_cell[axis];
        return u;
    }
    precise float u = (x - frnn_grid.origin[axis]) * frnn_grid.inv_cell[axis];
    return u;
}

int frnn_clamp_cell(float f, int axis) {
    if (frnn_is_hashed()) return int(clamp(f, -frnn_max_cell, frnn_max_cell));
    return int(clamp(f, 0.0, float(frnn_grid.dims[axis] - 1)));
}

frnn_ivec frnn_cell_of(frnn_vec x) {
    frnn_ivec c;
    for (int a = 0; a < FRNN_DIM; ++a) c[a] = frnn_clamp_cell(floor(frnn_cell_float(x[a], a)), a);
    return c;
}

// Hashed grid: a row of cells (y, z) hashes to a base slot and x adds to it, so the cells of one
// stencil row are consecutive slots (one run of points), as in frnn's CPU grid.
uint frnn_row_hash(int y, int z) {
    uint h = uint(y) * 0x9E3779B1u ^ uint(z) * 0x85EBCA77u;
    h ^= h >> 16;
    h *= 0x7FEB352Du;
    h ^= h >> 15;
    return h;
}

uint frnn_slot_of(frnn_ivec c) {
#if FRNN_DIM == 3
    if (frnn_is_hashed()) return (frnn_row_hash(c.y, c.z) + uint(c.x)) & frnn_grid.mask;
    return uint(c.x + frnn_grid.dims.x * (c.y + frnn_grid.dims.y * c.z));
#else
    if (frnn_is_hashed()) return (frnn_row_hash(c.y, 0) + uint(c.x)) & frnn_grid.mask;
    return uint(c.x + frnn_grid.dims.x * c.y);
#endif
}

// Flat invocation index of a dispatch that frnn::vulkan::kernel split into rows of groups. A
// macro: gl_WorkGroupSize is only known after your layout(local_size_x) declaration.
#define frnn_invocation_index() \
    (gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x)

#ifndef FRNN_GRID_PARAMS_ONLY

layout(std430, set = FRNN_SET, binding = 1) readonly buffer frnn_sorted_pos_block {
    float frnn_sorted_pos[];    // FRNN_DIM floats per point, cell order
};
layout(std430, set = FRNN_SET, binding = 2) readonly buffer frnn_sorted_cell_block {
    int frnn_sorted_cell[];     // FRNN_DIM cell coordinates per point, cell order
};
layout(std430, set = FRNN_SET, binding = 3) readonly buffer frnn_start_block {
    uint frnn_start[];          // slots + 1 entries: points of slot k are [start[k], start[k+1])
};
layout(std430, set = FRNN_SET, binding = 4) readonly buffer frnn_perm_block {
    uint frnn_perm[];           // sorted index -> caller's index
};

frnn_vec frnn_sorted_position(uint s) {
    frnn_vec x;
    for (int a = 0; a < FRNN_DIM; ++a) x[a] = frnn_sorted_pos[s * FRNN_DIM + a];
    return x;
}

uint frnn_original_index(uint s) { return frnn_perm[s]; }

// Walks the rows of cells (fixed y[, z]) around a point; each row is one run of sorted points,
// two when it wraps around the end of the hash table or of a periodic axis.
struct frnn_iterator {
    frnn_vec x;
    frnn_ivec lo;       // first cell per axis (periodic: wrapped into [0, dims))
    frnn_ivec span;     // cells per axis
    frnn_ivec step;     // current row: steps taken on axes 1 (and 2); x component unused
    uint j, end;        // current run
    uint next_begin, next_end;  // second half of a wrapped run
    bool done;
};

// Cell coordinate of the current row on axis a (a >= 1).
int frnn_row_cell(in frnn_iterator it, int a) {
    const int c = it.lo[a] + it.step[a];
    return (frnn_wraps(a) && c >= frnn_grid.dims[a]) ? c - frnn_grid.dims[a] : c;
}

// Sets the run(s) of the current row.
void frnn_load_row(inout frnn_iterator it) {
    frnn_ivec a;
    for (int k = 1; k < FRNN_DIM; ++k) a[k] = frnn_row_cell(it, k);
    a.x = it.lo.x;
    const uint sa = frnn_slot_of(a);
    const uint width = uint(it.span.x);  // cells in the row
    it.next_begin = it.next_end = 0u;
    // Slots of one row are consecutive; `limit` is where they wrap to 0.
    uint first_end = sa + width, limit = frnn_grid.slots;
    if (frnn_wraps(0)) limit = sa - uint(it.lo.x) + uint(frnn_grid.dims.x);
    it.j = frnn_start[sa];
    if (first_end <= limit) {
        it.end = frnn_start[first_end];
    } else {
        it.end = frnn_start[limit];
        const uint base = frnn_wraps(0) ? sa - uint(it.lo.x) : 0u;
        it.next_begin = frnn_start[base];
        it.next_end = frnn_start[base + (first_end - limit)];
    }
}

frnn_iterator frnn_begin(frnn_vec x) {
    frnn_iterator it;
    for (int a = 0; a < FRNN_DIM; ++a)
        if (frnn_wraps(a)) x[a] = frnn_wrap_into_box(x[a], frnn_grid.box[a]);
    it.x = x;
    // Every accepted pair (d2 <= radius2 in float) has |x_a - y_a| <= r (1 + 4 * 2^-24) on each
    // axis; `reach` is a little more.
    precise float reach = frnn_grid.radius * (1.0 + 1.0 / 1048576.0);
    for (int a = 0; a < FRNN_DIM; ++a) {
        if (frnn_wraps(a)) {
            // Wrapped coordinates are not monotone in x: a margin covers the rounding of both
            // points' cell coordinates (u < dims, so it stays a fraction of a cell).
            const float u = frnn_cell_float(x[a], a);
            const float cells = frnn_grid.radius * frnn_grid.inv_cell[a];
            const float margin = 1e-3 + (abs(u) + cells) * (1.0 / 1048576.0);
            const int dims = frnn_grid.dims[a];
            const int lo = int(floor(u - cells - margin));
            const int hi = int(floor(u + cells + margin));
            if (hi - lo + 1 >= dims) {
                it.lo[a] = 0;  // the whole axis, each cell once
                it.span[a] = dims;
            } else {
                it.lo[a] = (lo + 8 * dims) % dims;  // lo >= -6: u >= 0, cells <= 4
                it.span[a] = hi - lo + 1;
            }
        } else {
            // The cell of a coordinate is monotone in it (rounded subtraction, multiplication,
            // floor and clamp all are), so every float y in [x - reach, x + reach] lies in the
            // cells of the two rounded ends: no margin, and a far point whose float spacing
            // exceeds r searches one cell instead of a block that grows with |x| (which on
            // lavapipe ran past its 65535 loop iterations per SIMD group and cut the loops of
            // the other points of the group short). The ends stay finite: an infinite end
            // would clamp to the last hashed cell and open a search of 2^30 cells.
            precise float below = max(x[a] - reach, -3.40282347e38);
            precise float above = min(x[a] + reach, 3.40282347e38);
            it.lo[a] = frnn_clamp_cell(floor(frnn_cell_float(below, a)), a);
            it.span[a] = frnn_clamp_cell(floor(frnn_cell_float(above, a)), a) - it.lo[a] + 1;
        }
    }
    it.step = frnn_ivec(0);
    it.done = frnn_grid.count == 0u;
    if (!it.done) frnn_load_row(it);
    return it;
}

// Next neighbor: j (sorted index) and its squared distance; false when done.
bool frnn_next(inout frnn_iterator it, out uint j, out float d2) {
    while (!it.done) {
        while (it.j < it.end) {
            const uint k = it.j++;
            if (frnn_is_hashed()) {
                // Other cells share the slots: keep only this row's cells in range.
                const int cx = frnn_sorted_cell[k * FRNN_DIM];
                if (cx < it.lo.x || cx >= it.lo.x + it.span.x) continue;
                bool same_row = true;
                for (int a = 1; a < FRNN_DIM; ++a)
                    same_row = same_row && frnn_sorted_cell[k * FRNN_DIM + a] == frnn_row_cell(it, a);
                if (!same_row) continue;
            }
            // Same formula and order as frnn's CPU grid: d = x_j - x, d2 = sum of d*d.
            precise float sum = 0.0;
            for (int a = 0; a < FRNN_DIM; ++a) {
                precise float d = frnn_sorted_pos[k * FRNN_DIM + a] - it.x[a];
                if (frnn_wraps(a)) {
                    const float box = frnn_grid.box[a];
                    d = d - box * roundEven(d / box);
                }
                sum = sum + d * d;
            }
            if (sum <= frnn_grid.radius2) {
                j = k;
                d2 = sum;
                return true;
            }
        }
        if (it.next_end > it.next_begin) {
            it.j = it.next_begin;
            it.end = it.next_end;
            it.next_begin = it.next_end = 0u;
            continue;
        }
        // Next row.
        bool advanced = false;
        for (int a = 1; a < FRNN_DIM && !advanced; ++a) {
            if (it.step[a] + 1 < it.span[a]) {
                it.step[a] += 1;
                advanced = true;
            } else {
                it.step[a] = 0;
            }
        }
        if (!advanced) {
            it.done = true;
        } else {
            frnn_load_row(it);
        }
    }
    j = 0u;
    d2 = 0.0;
    return false;
}

#endif  // FRNN_GRID_PARAMS_ONLY
#endif  // FRNN_GRID_GLSL
