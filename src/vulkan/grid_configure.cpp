// What a Vulkan grid build will set up, computed and checked before anything changes: its
// grid_geometry (the CPU grid's kind policy and cell rules, with cells r wide) and, from it, the
// parameters of grid.glsl.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/cell_rules.hpp"
#include "core/kind_policy.hpp"
#include "frnn/search_scale.hpp"
#include "grid_state.hpp"

namespace frnn::vulkan::detail {

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
    grid_layout l;
    grid_geometry<float>& g = l.geometry;
    g.scale = s;
    g.search_radius = r * s;
    // The device visits the cells that [x - r, x + r] touches, with its own float margin
    // (grid.glsl), so cells are as asked, without the CPU grid's margin.
    const double cell = o.cell_size > 0 ? o.cell_size * double(s) : double(g.search_radius);
    g.reach = int(std::ceil(double(g.search_radius) / cell));
    const double max_cells = double(dev->info().max_storage_buffer_range) / 4 - 1;
    bool periodic = false;
    for (double length : o.periodic) periodic = periodic || length != 0;
    if (!o.periodic.empty() && o.periodic.size() != std::size_t(dim))
        throw error("vulkan::grid::build: periodic box needs " + std::to_string(dim) +
                    " lengths (0 for an open axis), got " + std::to_string(o.periodic.size()));
    if (periodic) {
        configure_periodic(g, o, count, r, s, cell, lo, hi, points);
    } else {
        frnn::detail::kind_question q;
        q.asked = o.kind;
        q.n = count;
        for (int a = 0; a < dim; ++a) q.lo[a] = lo[a], q.hi[a] = hi[a];
        q.explicit_domain = !o.domain_min.empty();
        q.cell = cell;
        q.radius = double(g.search_radius);
        q.hashed_key_limit = INFINITY;
        q.uniform_cell_limit = max_cells;
        // (One thread: the host's share of a device build is a sample and one pass.)
        const frnn::detail::kind_answer choice = dim == 2 ? frnn::detail::choose_kind<float, 2>(q, points, 1)
                                                          : frnn::detail::choose_kind<float, 3>(q, points, 1);
        g.kind = choice.kind;
        if (g.kind == grid_kind::uniform && !(choice.cells <= max_cells))
            throw error("vulkan::grid::build: a uniform grid over this domain would need " +
                        std::to_string(choice.cells) + " cells, more than one storage buffer of this device holds (" +
                        std::to_string(std::size_t(max_cells)) + "); use the hashed grid");
        // Both kinds count cells from the lower corner: small cell coordinates keep the float
        // rounding (and the search margin that covers it) small.
        frnn::detail::lay_out_open_cells(g, choice.lo, choice.hi, dim, cell, count);
    }
    // Checked here, not when allocating: a build that cannot fit leaves the grid as it was.
    if (!(double(g.slots) <= max_cells))
        throw error("vulkan::grid::build: " + std::to_string(g.slots) + " slots need more than one storage buffer "
                    "of this device holds (maxStorageBufferRange " +
                    std::to_string(dev->info().max_storage_buffer_range) + " bytes)");
    l.params = device_params(g, count);
    return l;
}

// A box with periodic axes, [0, L) on each: the CPU grid's cells (cell_rules.hpp), its open
// axes over the points' span or bulk (kind_policy.hpp). Lengths are checked in the caller's units.
void grid_state::configure_periodic(grid_geometry<float>& g, const grid_options& o, std::size_t count, float r,
                                    float s, double cell, double* lo, double* hi, std::span<const float> points) const {
    double search_box[3] = {0, 0, 0};
    g.periodic = true;
    for (int a = 0; a < dim; ++a) {
        const double length = o.periodic[a];
        if (length == 0) continue;  // an open axis
        if (!std::isfinite(length) || length < 0 || length > double(std::numeric_limits<float>::max()))
            throw error("vulkan::grid::build: periodic box length " + std::to_string(length) + " on axis " +
                        std::to_string(a) + " is not 0 (open) or a positive finite float");
        if (length < 2 * double(r))
            throw error("vulkan::grid::build: periodic box length " + std::to_string(length) + " on axis " +
                        std::to_string(a) + " is smaller than twice the radius (" + std::to_string(2 * double(r)) + ")");
        // The oracle's box: the length rounded to float, then scaled (exact: a power of two).
        g.box[a] = float(length) * s;
        g.wraps[a] = true;
        search_box[a] = length * double(s);
    }
    frnn::detail::kind_question q;
    q.n = count;
    q.cell = cell;
    q.radius = double(g.search_radius);
    q.hashed_key_limit = INFINITY;
    q.uniform_cell_limit = double(dev->info().max_storage_buffer_range) / 4 - 1;
    if (dim == 2) frnn::detail::span_open_axes<float, 2>(q, g.wraps.data(), search_box, points, 1, lo, hi);
    else frnn::detail::span_open_axes<float, 3>(q, g.wraps.data(), search_box, points, 1, lo, hi);
    frnn::detail::lay_out_periodic_cells(g, search_box, lo, hi, dim, cell, count);
}

// grid.glsl's parameters from the geometry.
grid_params grid_state::device_params(const grid_geometry<float>& g, std::size_t count) const {
    grid_params p{};
    for (int a = 0; a < 4; ++a) p.dims[a] = 1, p.inv_cell[a] = 1;
    for (int a = 0; a < dim; ++a) {
        p.origin[a] = float(g.origin[a]);
        p.inv_cell[a] = float(g.inv_cell[a]);
        p.box[a] = g.box[a];
        if (g.kind == grid_kind::uniform) p.dims[a] = std::int32_t(g.dims[a]);
    }
    p.radius = g.search_radius;
    p.radius2 = g.search_radius * g.search_radius;  // the CPU grid's r2, in float and search units
    p.count = std::uint32_t(count);
    p.hashed = g.kind == grid_kind::hashed;
    p.mask = g.kind == grid_kind::hashed ? std::uint32_t(g.slots - 1) : 0;
    p.slots = std::uint32_t(g.slots);
    p.periodic = g.periodic;
    return p;
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

// The search scale of frnn/search_scale.hpp, from the bounding box (caller's units) on the open
// axes and the box lengths, which bound the periodic axes' coordinates once wrapped.
float grid_state::scale_for(float r, const float* lo, const float* hi, const grid_options& o) const {
    float largest = largest_magnitude<float>({}, o.periodic);
    for (int a = 0; a < dim; ++a)
        if (!(std::size_t(a) < o.periodic.size() && o.periodic[a] > 0))
            largest = std::max({largest, std::abs(lo[a]), std::abs(hi[a])});
    try {
        return frnn::search_scale<float>(r, largest);
    } catch (const error& e) {
        throw error(std::string("vulkan::grid::build: ") + e.what());
    }
}

}  // namespace frnn::vulkan::detail
