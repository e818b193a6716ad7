// The state behind frnn::vulkan::grid: the host mirror of grid.glsl's parameters, the
// device buffers, and the steps of a build (grid_configure.cpp: the layout; grid_build.cpp:
// checks, then the commit) and of the queries (grid_lists.cpp). Internal to the Vulkan backend.
#pragma once
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <new>
#include <string>

#include "core/cell_rules.hpp"
#include "core/kind_policy.hpp"
#include "device.hpp"
#include "frnn/search_scale.hpp"
#include "frnn/vulkan.hpp"

namespace frnn::vulkan::detail {

constexpr std::size_t group_size = 128;  // FRNN_GROUP_SIZE of the shaders
constexpr std::size_t scan_block = 1024;  // values scanned by one workgroup
constexpr std::size_t scan_add_group = 256;

enum : std::uint32_t { flag_half = 1, flag_self = 2, flag_original = 4, flag_distances = 8, flag_external = 16 };

// Host mirror of frnn_grid_params in frnn/grid.glsl (std430, 96 bytes).
struct grid_params {
    float origin[4];
    float inv_cell[4];
    std::int32_t dims[4];
    float box[4];
    float radius, radius2;
    std::uint32_t count, hashed, mask, slots, periodic, pad;
};
static_assert(sizeof(grid_params) == 96);

inline std::size_t groups_for(std::size_t n, std::size_t per_group) { return (n + per_group - 1) / per_group; }

// Nine significant digits: every float reads back exactly (std::to_string prints 1e-30 as 0).
inline std::string shortest(double v) {
    char s[32];
    std::snprintf(s, sizeof s, "%.9g", v);
    return s;
}

// What a build sets, computed (and checked) before any member changes.
struct grid_layout {
    grid_geometry<float> geometry;
    grid_params params{};  // grid.glsl's, from the geometry
};

struct grid_state {
    context* ctx = nullptr;
    device* dev = nullptr;
    int dim = 3;
    std::size_t n = 0;
    float radius = 0;  // the caller's
    // Kind, cells, slots and the search scale s (frnn/search_scale.hpp: the device works on
    // x*s, r*s).
    grid_geometry<float> geometry;
    grid_params params{};
    bool built = false;

    buffer params_buf, own_pos, sorted_pos, sorted_cell, start, perm, inverse;
    buffer point_slot, point_rank, point_cell, tmp, scan_scratch, box;
    buffer counts, indices, dist2, dummy, query_pos, status;
    buffer_view pos;  // the input coordinates (own_pos or the caller's buffer)

    // Grows (never shrinks) a scratch buffer so rebuilds and repeated queries reuse memory.
    void ensure(buffer& b, std::size_t bytes, const char* what) {
        if (!b || b.size() < bytes) {
            b = buffer();  // free first: peak memory stays one copy
            b = buffer(*dev, bytes, buffer::kind::storage, what);
        }
    }

    std::size_t scan_scratch_bytes(std::size_t count) const {
        const std::size_t align = std::max<std::size_t>(dev->properties().limits.minStorageBufferOffsetAlignment, 4);
        std::size_t total = 0;
        for (std::size_t c = count;;) {
            const std::size_t groups = groups_for(c, scan_block);
            total += (groups * 4 + align - 1) / align * align;
            if (groups <= 1) break;
            c = groups;
        }
        return total;
    }

    // Exclusive scan in place of `count` uints: one block pass per level, then the
    // back-propagation of the block totals (2 * levels - 1 dispatches).
    void record_scan(buffer_view data, std::size_t count, std::size_t scratch_offset) {
        const std::size_t align = std::max<std::size_t>(dev->properties().limits.minStorageBufferOffsetAlignment, 4);
        const std::size_t groups = groups_for(count, scan_block);
        const buffer_view sums = scan_scratch.view(scratch_offset, groups * 4);
        const std::uint32_t c = std::uint32_t(count);
        dev->dispatch(dev->get(shader::scan_block, dim), {data, sums}, &c, 4, groups);
        if (groups > 1) {
            record_scan(sums, groups, scratch_offset + (groups * 4 + align - 1) / align * align);
            dev->dispatch(dev->get(shader::scan_add, dim), {data, sums}, &c, 4,
                          groups_for(count, scan_add_group));
        }
    }

    std::array<buffer_view, 5> grid_views() const {
        return {params_buf.view(0, sizeof(grid_params)), sorted_pos.view(0, std::max<std::size_t>(n * dim * 4, 4)),
                sorted_cell.view(0, std::max<std::size_t>(n * dim * 4, 4)),
                start.view(0, (geometry.slots + 1) * 4), perm.view(0, std::max<std::size_t>(n * 4, 4))};
    }

    // The specialization of the kind-dependent shaders (insert and the queries).
    kind_constant kind_code() const {
        if (params.periodic) return kind_constant::periodic;
        return geometry.kind == grid_kind::hashed ? kind_constant::hashed : kind_constant::uniform;
    }

    void check_built(const char* what) const {
        if (!built) throw error(std::string("vulkan::grid::") + what + ": the grid is not built");
    }

    grid_layout configure(const grid_options& o, std::size_t count, float r, float s, const float* lo,
                          const float* hi, std::span<const float> points) const;
    void configure_periodic(grid_geometry<float>& g, const grid_options& o, std::size_t count, float r, float s,
                            double cell, double* lo, double* hi, std::span<const float> points) const;
    grid_params device_params(const grid_geometry<float>& g, std::size_t count) const;
    void check_arguments(std::size_t count, float r, const grid_options& o) const;
    float scale_for(float r, const float* lo, const float* hi, const grid_options& o) const;
    // A build checks everything first (the grid stays as it was when a check fails), then
    // commits; a failure during the commit leaves the grid empty.
    void build_from_host(std::span<const float> coords, float r, const grid_options& o);
    void build_from_device(buffer_view coords, std::size_t count, float r, const grid_options& o);
    void commit(const float* host, buffer_view coords, std::size_t count, float r, const grid_layout& l);
    void clear();
    std::uint32_t flags(const list_options& o) const {
        std::uint32_t f = 0;
        if (o.half) f |= flag_half;
        if (o.self) f |= flag_self;
        if (o.space == index_space::original) f |= flag_original;
        return f;
    }
    // The rows of a query: the grid's own points, or external query points.
    struct row_source {
        std::size_t rows;
        buffer_view queries;  // rows * dim floats when external
        bool external;
    };
    // A 16-byte buffer for bindings a shader variant does not use (Vulkan wants one bound).
    buffer_view unused_binding() {
        ensure(dummy, 16, "unused binding");
        return dummy.view(0, 16);
    }
    row_source own_rows() { return {n, unused_binding(), false}; }

    // The shaders' loop-cut flag (common.glsl): cleared in a submission before the shaders
    // that may set it, read after it.
    buffer_view status_word() {
        ensure(status, 4, "loop status");
        return status.view(0, 4);
    }
    void clear_status() { dev->fill(status_word(), 0u); }
    void check_status(const char* what) {
        std::uint32_t cut = 0;
        dev->download(status_word(), &cut, 4);
        if (cut)
            throw error(std::string("vulkan::grid::") + what + ": the driver stopped a shader loop before its end "
                        "(lavapipe stops the loops of each group of 8 invocations after 65535 iterations in all): "
                        "rows of more than about 16,000 candidates, cells of more than 65,535 points or device-"
                        "sorted rows of more than about 5,000 neighbors exceed it; use a smaller radius or cell, "
                        "or the CPU grid");
    }
    row_source upload_queries(std::span<const float> q, const char* what);
    // Counts (capped) into `counts`: one dispatch, recorded.
    void record_count(std::uint32_t flags, std::uint32_t cap, const row_source& src);
    // Counts (capped) into `counts`, scans them; returns the total number of pairs.
    std::size_t count_and_scan(std::uint32_t flags, std::uint32_t cap, const char* what, const row_source& src);
    struct list_plan {
        bool nearest, need_d2;
        std::uint32_t flags, cap, sort;  // sort: 0 none, 1 by index, 2 by distance
    };
    list_plan plan(const list_options& o, std::size_t k, const row_source& src) const;
    void fill_rows(const list_plan& p, const row_source& src, std::size_t r0, std::size_t r1, std::size_t chunk,
                   const char* what);
    std::string too_many_pairs(const char* what, std::size_t count) const;
    void lists_on_device(const list_options& o, std::size_t k, const row_source& src, const char* what);
    csr<float> lists_to_host(const list_options& o, std::size_t k, const row_source& src, const char* what);
    csr<float> query_lists(std::span<const float> queries, std::size_t k, const list_options& o, const char* what);
    std::size_t pairs = 0, rows = 0;
};


}  // namespace frnn::vulkan::detail
