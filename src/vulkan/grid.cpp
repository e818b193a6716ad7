// frnn::vulkan::grid: build (bounding box, insert, scan, scatter, stable) and queries (count,
// CSR lists, k nearest) recorded as dispatches of the embedded shaders.
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

namespace frnn::vulkan {

namespace detail {

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

std::size_t groups_for(std::size_t n, std::size_t per_group) { return (n + per_group - 1) / per_group; }

// Nine significant digits: every float reads back exactly (std::to_string prints 1e-30 as 0).
std::string shortest(double v) {
    char s[32];
    std::snprintf(s, sizeof s, "%.9g", v);
    return s;
}

// What a build sets, computed (and checked) before any member changes.
struct grid_layout {
    grid_params params{};
    grid_kind kind = grid_kind::uniform;
    std::size_t slots = 1;
};

struct grid_state {
    context* ctx = nullptr;
    device* dev = nullptr;
    int dim = 3;
    std::size_t n = 0;
    float radius = 0;  // the caller's
    float scale = 1;   // the search scale s (frnn/search_scale.hpp): the device works on x*s, r*s
    grid_kind kind = grid_kind::uniform;
    std::size_t slots = 1;
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
                start.view(0, (slots + 1) * 4), perm.view(0, std::max<std::size_t>(n * 4, 4))};
    }

    // The specialization of the kind-dependent shaders (insert and the queries).
    kind_constant kind_code() const {
        if (params.periodic) return kind_constant::periodic;
        return kind == grid_kind::hashed ? kind_constant::hashed : kind_constant::uniform;
    }

    void check_built(const char* what) const {
        if (!built) throw error(std::string("vulkan::grid::") + what + ": the grid is not built");
    }

    grid_layout configure(const grid_options& o, std::size_t count, float r, float s, const float* lo,
                          const float* hi, std::span<const float> points) const;
    void configure_periodic(grid_layout& l, const grid_options& o, std::size_t count, float r, float s, double cell,
                            const double* lo, const double* hi) const;
    void check_arguments(std::size_t count, float r, const grid_options& o) const;
    float scale_for(float r, const float* lo, const float* hi, const grid_options& o) const;
    // A build checks everything first (the grid stays as it was when a check fails), then
    // commits; a failure during the commit leaves the grid empty.
    void build_from_host(std::span<const float> coords, float r, const grid_options& o);
    void build_from_device(buffer_view coords, std::size_t count, float r, const grid_options& o);
    void commit(const float* host, buffer_view coords, std::size_t count, float r, float s, const grid_layout& l);
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

// `automatic`: the CPU grid's policy (core/kind_policy.hpp); the hashed grid here has no key
// limit (it clamps cell coordinates at 2^30, which only merges far cells). lo/hi: the bounding
// box in search units (already multiplied by s); `points`: the scaled points when they are on
// the host (empty: no bulk box is tried). Changes nothing.
grid_layout grid_state::configure(const grid_options& o, std::size_t count, float r, float s, const float* lo_in,
                                  const float* hi_in, std::span<const float> points) const {
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (int a = 0; a < dim; ++a) lo[a] = lo_in[a], hi[a] = hi_in[a];
    frnn::detail::apply_domain(o, dim, double(s), double(std::numeric_limits<float>::max()), lo, hi,
                               "vulkan::grid::build: ");
    const float search_r = r * s;
    const double cell = o.cell_size > 0 ? o.cell_size * double(s) : double(search_r);
    grid_layout l;
    grid_params& p = l.params;
    for (int a = 0; a < 4; ++a) p.dims[a] = 1, p.inv_cell[a] = 1;
    p.radius = search_r;
    p.radius2 = search_r * search_r;  // the CPU grid's r2, in float and search units
    p.count = std::uint32_t(count);
    const double max_cells = double(dev->info().max_storage_buffer_range) / 4 - 1;
    if (!o.periodic.empty()) {
        configure_periodic(l, o, count, r, s, cell, lo, hi);
    } else {
        frnn::detail::kind_question q;
        q.asked = o.kind;
        q.n = count;
        for (int a = 0; a < dim; ++a) q.lo[a] = lo[a], q.hi[a] = hi[a];
        q.explicit_domain = !o.domain_min.empty();
        q.cell = cell;
        q.radius = double(search_r);
        q.hashed_key_limit = INFINITY;
        q.uniform_cell_limit = max_cells;
        // (One thread: the host's share of a device build is a sample and one pass.)
        const frnn::detail::kind_answer choice = dim == 2 ? frnn::detail::choose_kind<float, 2>(q, points, 1)
                                                          : frnn::detail::choose_kind<float, 3>(q, points, 1);
        const double cells = choice.cells;
        for (int a = 0; a < dim; ++a) lo[a] = choice.lo[a], hi[a] = choice.hi[a];
        l.kind = choice.kind;
        if (l.kind == grid_kind::uniform && !(cells <= max_cells))
            throw error("vulkan::grid::build: a uniform grid over this domain would need " + std::to_string(cells) +
                        " cells, more than one storage buffer of this device holds (" +
                        std::to_string(std::size_t(max_cells)) + "); use the hashed grid");
        const auto dims = frnn::detail::uniform_cells(lo, hi, dim, cell);
        for (int a = 0; a < dim; ++a) {
            p.inv_cell[a] = float(1.0 / cell);
            // Both kinds count cells from the lower corner: small cell coordinates keep the float
            // rounding (and the search margin that covers it) small.
            p.origin[a] = float(lo[a]);
            if (l.kind == grid_kind::uniform) p.dims[a] = std::int32_t(dims[a]);
        }
        if (l.kind == grid_kind::uniform) {
            l.slots = 1;
            for (int a = 0; a < dim; ++a) l.slots *= std::size_t(p.dims[a]);
        } else {
            l.slots = std::bit_ceil(std::max<std::size_t>(count, 64));
        }
        p.hashed = l.kind == grid_kind::hashed;
        p.mask = l.kind == grid_kind::hashed ? std::uint32_t(l.slots - 1) : 0;
        p.slots = std::uint32_t(l.slots);
    }
    // Checked here, not when allocating: a build that cannot fit leaves the grid as it was.
    if (!(double(l.slots) <= max_cells))
        throw error("vulkan::grid::build: " + std::to_string(l.slots) + " slots need more than one storage buffer "
                    "of this device holds (maxStorageBufferRange " +
                    std::to_string(dev->info().max_storage_buffer_range) + " bytes)");
    return l;
}

// Periodic box [0, L) per axis: a uniform grid of at least r-sized cells, L / dims each, as on
// the CPU (very sparse boxes get fewer, larger cells). Lengths are checked in the caller's units.
void grid_state::configure_periodic(grid_layout& l, const grid_options& o, std::size_t count, float r, float s,
                                    double cell, const double* lo, const double* hi) const {
    if (o.periodic.size() != std::size_t(dim))
        throw error("vulkan::grid::build: periodic box needs " + std::to_string(dim) + " lengths, got " +
                    std::to_string(o.periodic.size()));
    grid_params& p = l.params;
    double search_box[3] = {0, 0, 0};
    for (int a = 0; a < dim; ++a) {
        const double length = o.periodic[a];
        if (!std::isfinite(length) || length < 2 * double(r) || length > double(std::numeric_limits<float>::max()))
            throw error("vulkan::grid::build: periodic box length " + std::to_string(length) + " on axis " +
                        std::to_string(a) + " is smaller than twice the radius (" + std::to_string(2 * double(r)) +
                        ") or not a finite float");
        // The oracle's box: the length rounded to float, then scaled (exact: a power of two).
        p.box[a] = float(length) * s;
        if (std::max(std::abs(lo[a]), std::abs(hi[a])) >= double(p.box[a]) * 0x1p30)
            throw error("vulkan::grid::build: a point lies more than 2^30 periodic boxes away on axis " +
                        std::to_string(a));
        search_box[a] = length * double(s);
    }
    const auto dims = frnn::detail::periodic_cells(search_box, dim, cell, count);
    for (int a = 0; a < dim; ++a) p.dims[a] = std::int32_t(dims[a]);
    l.kind = grid_kind::uniform;
    l.slots = 1;
    for (int a = 0; a < dim; ++a) {
        p.inv_cell[a] = float(double(p.dims[a]) / double(p.box[a]));
        l.slots *= std::size_t(p.dims[a]);
    }
    p.periodic = 1;
    p.hashed = 0;
    p.slots = std::uint32_t(l.slots);
}

// The checks that need neither the points nor the device.
void grid_state::check_arguments(std::size_t count, float r, const grid_options& o) const {
    if (!(r > 0) || !std::isfinite(r))
        throw error("vulkan::grid::build: radius must be positive and finite, got " + shortest(r));
    if (o.cell_size != 0 && !(o.cell_size >= double(r) / 4 && o.cell_size <= double(r)))
        throw error("vulkan::grid::build: cell_size must lie in [r/4, r], got " + std::to_string(o.cell_size));
    if (count >= 0x7FFFFFFFu) throw error("vulkan::grid::build: too many points (" + std::to_string(count) + ")");
    const std::size_t bytes = count * dim * sizeof(float);
    if (bytes > dev->info().max_storage_buffer_range)
        throw error("vulkan::grid::build: " + std::to_string(count) + " points need " + std::to_string(bytes) +
                    " bytes, more than one storage buffer of this device holds (maxStorageBufferRange " +
                    std::to_string(dev->info().max_storage_buffer_range) + " bytes)");
}

// The search scale of frnn/search_scale.hpp, from the bounding box (caller's units) and the box.
float grid_state::scale_for(float r, const float* lo, const float* hi, const grid_options& o) const {
    float largest = largest_magnitude<float>({}, o.periodic);
    for (int a = 0; a < dim; ++a) largest = std::max({largest, std::abs(lo[a]), std::abs(hi[a])});
    try {
        return frnn::search_scale<float>(r, largest);
    } catch (const error& e) {
        throw error(std::string("vulkan::grid::build: ") + e.what());
    }
}

// Host coordinates: checked, measured and scaled on the host, so that nothing of the grid
// changes before all checks passed.
void grid_state::build_from_host(std::span<const float> coords, float r, const grid_options& o) {
    if (coords.size() % dim != 0)
        throw error("vulkan::grid::build: " + std::to_string(coords.size()) + " coordinates is not a multiple of " +
                    std::to_string(dim));
    const std::size_t count = coords.size() / dim;
    check_arguments(count, r, o);
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    if (count > 0)
        for (int a = 0; a < dim; ++a) lo[a] = hi[a] = coords[a];
    for (std::size_t i = 0; i < coords.size(); ++i) {
        const float v = coords[i];
        if (!std::isfinite(v))
            throw error("vulkan::grid::build: point " + std::to_string(i / dim) + " has a non-finite coordinate");
        const int a = int(i % dim);
        lo[a] = std::min(lo[a], v), hi[a] = std::max(hi[a], v);
    }
    const float s = scale_for(r, lo, hi, o);
    // Scaling is monotone, so the scaled box is the box of the scaled points.
    for (int a = 0; a < dim; ++a) lo[a] *= s, hi[a] *= s;
    std::vector<float> scaled;
    if (s != 1) {
        // The oracle's multiplication, in float: below a quarter of FLT_MAX (search_scale), exact.
        scaled.resize(coords.size());
        for (std::size_t i = 0; i < coords.size(); ++i) scaled[i] = coords[i] * s;
        coords = scaled;
    }
    const grid_layout l = configure(o, count, r, s, lo, hi, coords);
    commit(coords.data(), {}, count, r, s, l);
}

// The caller's buffer: checked and measured on the device (scratch buffers only).
void grid_state::build_from_device(buffer_view coords, std::size_t count, float r, const grid_options& o) {
    check_arguments(count, r, o);
    const std::size_t pos_bytes = count * dim * sizeof(float);
    if (count > 0 && (!coords.buffer || coords.size < pos_bytes))
        throw error("vulkan::grid::build: the coordinate buffer holds " + std::to_string(coords.size) +
                    " bytes, " + std::to_string(count) + " points need " + std::to_string(pos_bytes));
    const buffer_view in{coords.buffer, coords.offset, std::max<std::size_t>(pos_bytes, 4)};
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    ensure(box, 64, "bounding box");
    if (count > 0) {
        const std::size_t words = 2 * dim + 1;
        dev->begin();
        dev->fill(box.view(0, words * 4), 0xFFFFFFFFu);
        dev->fill(box.view(dim * 4, dim * 4), 0u);
        const std::uint32_t c = std::uint32_t(count);
        dev->dispatch(dev->get(shader::bbox, dim), {in, box.view(0, words * 4)}, &c, 4, groups_for(count, group_size));
        dev->submit();
        std::uint32_t keys[7];
        dev->download(box.view(0, words * 4), keys, words * 4);
        if (keys[2 * dim] != 0xFFFFFFFFu)
            throw error("vulkan::grid::build: point " + std::to_string(keys[2 * dim]) +
                        " has a non-finite coordinate");
        auto from_key = [](std::uint32_t k) {
            const std::uint32_t b = (k & 0x80000000u) ? (k & 0x7FFFFFFFu) : ~k;
            float f;
            std::memcpy(&f, &b, 4);
            return f;
        };
        for (int a = 0; a < dim; ++a) lo[a] = from_key(keys[a]), hi[a] = from_key(keys[dim + a]);
    }
    // The caller's buffer is read in place, so it cannot be scaled: radii whose square float
    // cannot hold exactly are refused, not answered in the wrong units.
    if (scale_for(r, lo, hi, o) != 1)
        throw error("vulkan::grid::build: radius " + shortest(r) + " needs a search scale (r^2 leaves "
                    "float's normal range outside [2^-49, 2^63) = [1.78e-15, 9.22e18]), which a build from a "
                    "buffer_view cannot apply in place; build from host coordinates (scaled on the host)");
    commit(nullptr, in, count, r, 1, configure(o, count, r, 1, lo, hi, {}));
}

// Everything checked: from here the grid changes, and any failure leaves it empty.
void grid_state::commit(const float* host, buffer_view coords, std::size_t count, float r, float s,
                        const grid_layout& l) {
    try {
        built = false;
        n = count;
        radius = r;
        scale = s;
        params = l.params;
        kind = l.kind;
        slots = l.slots;
        const std::size_t nb = std::max<std::size_t>(n, 1);
        if (host) {
            ensure(own_pos, nb * dim * 4, "input positions");
            dev->upload(own_pos.view(), host, n * dim * sizeof(float));
            coords = own_pos.view(0, nb * dim * 4);
        }
        pos = coords;
        ensure(params_buf, sizeof(grid_params), "grid parameters");
        ensure(start, (slots + 1) * 4, "cell starts");
        ensure(point_slot, nb * 4, "point slots");
        ensure(point_rank, nb * 4, "point ranks");
        ensure(point_cell, nb * dim * 4, "point cells");
        ensure(tmp, nb * 4, "scatter buffer");
        ensure(perm, nb * 4, "sorted-to-original map");
        ensure(inverse, nb * 4, "original-to-sorted map");
        ensure(sorted_pos, nb * dim * 4, "sorted positions");
        ensure(sorted_cell, nb * dim * 4, "sorted cells");
        ensure(scan_scratch, scan_scratch_bytes(slots + 1), "scan scratch");

        // Insert, scan, scatter, stable pass: one submission.
        const std::uint32_t c = std::uint32_t(n);
        const auto n4 = [&](std::size_t per) { return std::max<std::size_t>(n * per * 4, 4); };
        dev->begin();
        clear_status();
        dev->update(params_buf.view(0, sizeof(grid_params)), &params, sizeof(grid_params));
        dev->fill(start.view(0, (slots + 1) * 4), 0u);
        if (n > 0) {
            dev->dispatch(dev->get(shader::insert, dim, kind_code()),
                          {params_buf.view(0, sizeof(grid_params)), pos, start.view(0, (slots + 1) * 4),
                           point_slot.view(0, n4(1)), point_rank.view(0, n4(1)), point_cell.view(0, n4(dim))},
                          nullptr, 0, groups_for(n, group_size));
            record_scan(start.view(0, (slots + 1) * 4), slots + 1, 0);
            dev->dispatch(dev->get(shader::scatter, dim),
                          {start.view(0, (slots + 1) * 4), point_slot.view(0, n4(1)), point_rank.view(0, n4(1)),
                           tmp.view(0, n4(1))},
                          &c, 4, groups_for(n, group_size));
            dev->dispatch(dev->get(shader::stable, dim),
                          {start.view(0, (slots + 1) * 4), point_slot.view(0, n4(1)), tmp.view(0, n4(1)), pos,
                           point_cell.view(0, n4(dim)), perm.view(0, n4(1)), inverse.view(0, n4(1)),
                           sorted_pos.view(0, n4(dim)), sorted_cell.view(0, n4(dim)), status_word()},
                          &c, 4, groups_for(n, group_size));
        }
        dev->submit();
        check_status("build");
        built = true;
    } catch (...) {
        clear();
        throw;
    }
}

void grid_state::clear() {
    built = false;
    n = 0;
    radius = 0;
    scale = 1;
    params = {};
    kind = grid_kind::uniform;
    slots = 1;
    pos = {};
}

grid_state::row_source grid_state::upload_queries(std::span<const float> q, const char* what) {
    if (q.size() % dim != 0)
        throw error(std::string("vulkan::grid::") + what + ": " + std::to_string(q.size()) +
                    " query coordinates is not a multiple of " + std::to_string(dim));
    const std::size_t count = q.size() / dim;
    if (count >= 0x7FFFFFFFu) throw error(std::string("vulkan::grid::") + what + ": too many query points");
    for (std::size_t i = 0; i < q.size(); ++i) {
        if (!std::isfinite(q[i]))
            throw error(std::string("vulkan::grid::") + what + ": query point " + std::to_string(i / dim) +
                        " has a non-finite coordinate (axis " + std::to_string(i % dim) + ")");
        if (params.periodic && std::abs(double(q[i]) * scale) >= double(params.box[i % dim]) * 0x1p30)
            throw error(std::string("vulkan::grid::") + what + ": query point " + std::to_string(i / dim) +
                        " lies more than 2^30 periodic boxes away on axis " + std::to_string(i % dim));
    }
    std::vector<float> scaled;
    if (scale != 1) {
        // In search units, as the oracle multiplies them. A far query may overflow when s > 1:
        // the oracle's differences are then infinite (no neighbors), and a point at 2^127 has
        // none either, since scaled data lie below 2^126 (search_scale) and r*s is far smaller.
        scaled.resize(q.size());
        for (std::size_t i = 0; i < q.size(); ++i) {
            const float y = q[i] * scale;
            scaled[i] = std::isinf(y) ? std::copysign(0x1p127f, q[i]) : y;
        }
        q = scaled;
    }
    ensure(query_pos, std::max<std::size_t>(q.size() * 4, 4), "query points");
    dev->upload(query_pos.view(), q.data(), q.size() * 4);
    return {count, query_pos.view(0, std::max<std::size_t>(q.size() * 4, 4)), true};
}

void grid_state::record_count(std::uint32_t f, std::uint32_t cap, const row_source& src) {
    const auto g = grid_views();
    const std::uint32_t push[3] = {f | (src.external ? flag_external : 0u), cap, std::uint32_t(src.rows)};
    dev->dispatch(dev->get(shader::count, dim, kind_code()),
                  {g[0], g[1], g[2], g[3], g[4], counts.view(0, src.rows * 4), src.queries, status_word()}, push,
                  sizeof(push),
                  groups_for(src.rows, group_size));
}

std::size_t grid_state::count_and_scan(std::uint32_t f, std::uint32_t cap, const char* what, const row_source& src) {
    rows = src.rows;
    const std::size_t rows_bytes = (rows + 1) * 4;
    ensure(counts, rows_bytes, "neighbor counts");
    ensure(scan_scratch, scan_scratch_bytes(rows + 1), "scan scratch");
    dev->begin();
    clear_status();
    dev->fill(counts.view(0, rows_bytes), 0u);
    record_count(f, cap, src);
    record_scan(counts.view(0, rows_bytes), rows + 1, 0);
    dev->submit();
    check_status(what);
    std::uint32_t total = 0;
    dev->download(counts.view(rows * 4, 4), &total, 4);
    if (total == 0xFFFFFFFFu)
        throw error(std::string("vulkan::grid::") + what + ": 2^32 or more pairs; query fewer points");
    return total;
}

grid_state::list_plan grid_state::plan(const list_options& o, std::size_t k, const row_source& src) const {
    list_plan p;
    p.nearest = k > 0;
    p.need_d2 = o.distances || p.nearest || o.order == row_order::distance;
    p.flags = flags(o) | (p.need_d2 ? flag_distances : 0u) | (src.external ? flag_external : 0u);
    p.cap = p.nearest ? std::uint32_t(std::min<std::size_t>(k, 0xFFFFFFFFu)) : 0xFFFFFFFFu;
    p.sort = p.nearest ? 0u : o.order == row_order::distance ? 2u : o.order == row_order::index ? 1u : 0u;
    return p;
}

// Fills rows [r0, r1) (whose pairs, `chunk` of them, start at offsets[r0]) into the start of
// the index and distance buffers, sorting them when asked.
void grid_state::fill_rows(const list_plan& p, const row_source& src, std::size_t r0, std::size_t r1,
                           std::size_t chunk, const char* what) {
    ensure(indices, chunk * 4, "neighbor indices");
    if (p.need_d2) ensure(dist2, chunk * 4, "neighbor distances");
    const auto g = grid_views();
    const buffer_view offsets = counts.view(0, (rows + 1) * 4);
    const buffer_view idx = indices.view(0, std::max<std::size_t>(chunk * 4, 4));
    const buffer_view d2 = p.need_d2 ? dist2.view(0, std::max<std::size_t>(chunk * 4, 4)) : unused_binding();
    const std::uint32_t push[5] = {p.flags, p.cap, std::uint32_t(rows), std::uint32_t(r0), std::uint32_t(r1)};
    dev->begin();
    clear_status();
    if (chunk > 0) {
        dev->dispatch(dev->get(p.nearest ? shader::knn : shader::fill, dim, kind_code()),
                      {g[0], g[1], g[2], g[3], g[4], offsets, idx, d2, src.queries, status_word()}, push,
                      sizeof(push), groups_for(rows, group_size));
        if (p.sort) {
            const std::uint32_t sp[4] = {std::uint32_t(r1 - r0), p.sort, p.need_d2 ? 1u : 0u, std::uint32_t(r0)};
            dev->dispatch(dev->get(shader::sort_rows, dim), {offsets, idx, d2, status_word()}, sp, sizeof(sp),
                          groups_for(r1 - r0, group_size));
        }
    }
    dev->submit();
    check_status(what);
}

std::string grid_state::too_many_pairs(const char* what, std::size_t count) const {
    const std::size_t limit = dev->info().max_storage_buffer_range;
    return std::string("vulkan::grid::") + what + ": " + std::to_string(count) + " pairs need " +
           std::to_string(count * 4) + " bytes per array, more than one storage buffer of this device holds (" +
           "maxStorageBufferRange " + std::to_string(limit) + " bytes)";
}

// Counts, scans and fills all rows on the device (k > 0: k nearest); one binding must hold them.
void grid_state::lists_on_device(const list_options& o, std::size_t k, const row_source& src, const char* what) {
    const list_plan p = plan(o, k, src);
    pairs = count_and_scan(p.flags, p.cap, what, src);
    if (pairs * 4 > dev->info().max_storage_buffer_range)
        throw error(too_many_pairs(what, pairs) + "; use the host results (split automatically), query fewer "
                                                   "points or a smaller radius");
    fill_rows(p, src, 0, rows, pairs, what);
}

// Lists to the host: rows are filled in chunks whose pairs fit one storage buffer, so results
// larger than maxStorageBufferRange still work (one more pass over the points per chunk).
csr<float> grid_state::lists_to_host(const list_options& o, std::size_t k, const row_source& src, const char* what) {
    const list_plan p = plan(o, k, src);
    pairs = count_and_scan(p.flags, p.cap, what, src);
    std::vector<std::uint32_t> off(rows + 1);
    dev->download(counts.view(0, (rows + 1) * 4), off.data(), (rows + 1) * 4);
    csr<float> out;
    out.offsets.assign(off.begin(), off.end());
    out.indices.resize(pairs);
    if (o.distances) out.distances.resize(pairs);
    const std::size_t per_chunk = dev->info().max_storage_buffer_range / 4;
    for (std::size_t r0 = 0; r0 < rows;) {
        // The most rows from r0 whose pairs fit one buffer.
        const std::size_t r1 =
            std::size_t(std::upper_bound(off.begin() + r0 + 1, off.end(), std::uint64_t(off[r0]) + per_chunk,
                                         [](std::uint64_t v, std::uint32_t e) { return v < e; }) -
                        off.begin()) - 1;
        if (r1 == r0) throw error(too_many_pairs(what, off[r0 + 1] - off[r0]) + " in row " + std::to_string(r0));
        const std::size_t chunk = off[r1] - off[r0];
        fill_rows(p, src, r0, r1, chunk, what);
        dev->download(indices.view(0, chunk * 4), out.indices.data() + off[r0], chunk * 4);
        if (o.distances) {
            float* d = out.distances.data() + off[r0];
            dev->download(dist2.view(0, chunk * 4), d, chunk * 4);
            // The host's sqrt is correctly rounded, so distances match the CPU grid bit for bit;
            // 1/s brings them back to the caller's units (as distance_test::distance does).
            const float inv = 1.0f / scale;
            for (std::size_t e = 0; e < chunk; ++e) d[e] = std::sqrt(d[e]) * inv;
        }
        r0 = r1;
    }
    return out;
}

csr<float> grid_state::query_lists(std::span<const float> queries, std::size_t k, const list_options& o,
                                   const char* what) {
    const auto src = upload_queries(queries, what);
    if (src.rows == 0) return {};
    if (n == 0) {  // an empty grid: empty rows
        csr<float> empty;
        empty.offsets.assign(src.rows + 1, 0);
        return empty;
    }
    return lists_to_host(o, k, src, what);
}

}  // namespace detail

// ---------------------------------------------------------------------------------------------

template <int D>
grid<D>::grid(context& ctx) : state_(std::make_unique<detail::grid_state>()) {
    state_->ctx = &ctx;
    state_->dev = &ctx.impl();
    state_->dim = D;
}

template <int D>
grid<D>::~grid() = default;
template <int D>
grid<D>::grid(grid&&) noexcept = default;
template <int D>
grid<D>& grid<D>::operator=(grid&&) noexcept = default;

template <int D>
void grid<D>::build(std::span<const float> coords, float radius, const grid_options& options) {
    try {
        state_->build_from_host(coords, radius, options);
    } catch (const std::bad_alloc&) {
        state_->clear();  // documented: empty after bad_alloc, wherever it happened
        throw;
    }
}

template <int D>
void grid<D>::build(buffer_view coords, std::size_t n, float radius, const grid_options& options) {
    try {
        state_->build_from_device(coords, n, radius, options);
    } catch (const std::bad_alloc&) {
        state_->clear();
        throw;
    }
}

template <int D>
std::size_t grid<D>::size() const { return state_->n; }
template <int D>
float grid<D>::radius() const { return state_->radius; }
template <int D>
float grid<D>::search_scale() const { return state_->scale; }
template <int D>
grid_kind grid<D>::kind() const { return state_->kind; }
template <int D>
std::size_t grid<D>::cell_count() const { return state_->slots; }
template <int D>
context& grid<D>::owner() const { return *state_->ctx; }

template <int D>
std::vector<std::uint32_t> grid<D>::sorted_to_original() const {
    auto& s = *state_;
    s.check_built("sorted_to_original");
    std::vector<std::uint32_t> out(s.n);
    s.dev->download(s.perm.view(0, s.n * 4), out.data(), s.n * 4);
    return out;
}

template <int D>
std::vector<std::uint32_t> grid<D>::count_neighbors(index_space space) const {
    auto& s = *state_;
    s.check_built("count_neighbors");
    std::vector<std::uint32_t> out(s.n);
    if (s.n == 0) return out;
    list_options o;
    o.space = space;
    s.ensure(s.counts, (s.n + 1) * 4, "neighbor counts");
    s.dev->begin();
    s.clear_status();
    s.record_count(s.flags(o), 0xFFFFFFFFu, s.own_rows());
    s.dev->submit();
    s.check_status("count_neighbors");
    s.dev->download(s.counts.view(0, s.n * 4), out.data(), s.n * 4);
    return out;
}

template <int D>
csr<float> grid<D>::neighbor_lists(const list_options& options) const {
    auto& s = *state_;
    s.check_built("neighbor_lists");
    if (s.n == 0) return {};
    return s.lists_to_host(options, 0, s.own_rows(), "neighbor_lists");
}

template <int D>
csr<float> grid<D>::nearest(std::size_t k, const list_options& options) const {
    auto& s = *state_;
    s.check_built("nearest");
    if (k == 0) throw error("vulkan::grid::nearest: k must be at least 1");
    if (s.n == 0) return {};
    return s.lists_to_host(options, k, s.own_rows(), "nearest");
}

// Queries from other points: `half` and `self` do not apply (as on the CPU).
namespace {
list_options for_queries(list_options o) {
    o.half = false;
    o.self = false;
    return o;
}
}  // namespace

template <int D>
std::vector<std::uint32_t> grid<D>::query_counts(std::span<const float> queries) const {
    auto& s = *state_;
    s.check_built("query_counts");
    const auto src = s.upload_queries(queries, "query_counts");
    std::vector<std::uint32_t> out(src.rows);
    if (src.rows == 0 || s.n == 0) return out;
    s.ensure(s.counts, (src.rows + 1) * 4, "neighbor counts");
    s.dev->begin();
    s.clear_status();
    s.record_count(s.flags(list_options{}), 0xFFFFFFFFu, src);
    s.dev->submit();
    s.check_status("query_counts");
    s.dev->download(s.counts.view(0, src.rows * 4), out.data(), src.rows * 4);
    return out;
}

template <int D>
csr<float> grid<D>::query(std::span<const float> queries, const list_options& options) const {
    state_->check_built("query");
    return state_->query_lists(queries, 0, for_queries(options), "query");
}

template <int D>
csr<float> grid<D>::query_nearest(std::span<const float> queries, std::size_t k, const list_options& options) const {
    state_->check_built("query_nearest");
    if (k == 0) throw error("vulkan::grid::query_nearest: k must be at least 1");
    return state_->query_lists(queries, k, for_queries(options), "query_nearest");
}

template <int D>
typename grid<D>::device_csr grid<D>::neighbor_lists_on_device(const list_options& options) {
    auto& s = *state_;
    s.check_built("neighbor_lists_on_device");
    device_csr out;
    out.rows = s.n;
    if (s.n == 0) return out;
    s.lists_on_device(options, 0, s.own_rows(), "neighbor_lists_on_device");
    out.pairs = s.pairs;
    out.offsets = s.counts.view(0, (s.n + 1) * 4);
    out.indices = s.indices.view(0, std::max<std::size_t>(s.pairs * 4, 4));
    if (options.distances) out.distances_squared = s.dist2.view(0, std::max<std::size_t>(s.pairs * 4, 4));
    return out;
}

template <int D>
std::uint32_t grid<D>::shader_kind() const {
    state_->check_built("shader_kind");
    return std::uint32_t(state_->kind_code());
}

template <int D>
std::array<buffer_view, 5> grid<D>::shader_buffers() const {
    state_->check_built("shader_buffers");
    return state_->grid_views();
}

template class grid<2>;
template class grid<3>;

}  // namespace frnn::vulkan
