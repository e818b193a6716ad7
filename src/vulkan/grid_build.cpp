// A Vulkan grid build: every check first (from host coordinates or the caller's device buffer),
// then the commit that records bounding box, insert, scan, scatter and stable sort.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <new>
#include <string>

#include "frnn/search_scale.hpp"
#include "grid_state.hpp"

namespace frnn::vulkan::detail {

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
        // The oracle's wrap and multiplication, in float: below a quarter of FLT_MAX
        // (search_scale), exact. Unscaled points are wrapped on the device (stable.comp).
        scaled.resize(coords.size());
        for (std::size_t i = 0; i < coords.size(); ++i) {
            const std::size_t a = i % std::size_t(dim);
            const bool wraps = a < o.periodic.size() && o.periodic[a] > 0;
            scaled[i] = (wraps ? wrap_into_box(coords[i], float(o.periodic[a])) : coords[i]) * s;
        }
        coords = scaled;
    }
    const grid_layout l = configure(o, count, r, s, lo, hi, coords);
    commit(coords.data(), {}, count, r, l);
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
    commit(nullptr, in, count, r, configure(o, count, r, 1, lo, hi, {}));
}

// Everything checked: from here the grid changes, and any failure leaves it empty.
void grid_state::commit(const float* host, buffer_view coords, std::size_t count, float r,
                        const grid_layout& l) {
    try {
        built = false;
        n = count;
        radius = r;
        geometry = l.geometry;
        params = l.params;
        const std::size_t nb = std::max<std::size_t>(n, 1);
        if (host) {
            ensure(own_pos, nb * dim * 4, "input positions");
            dev->upload(own_pos.view(), host, n * dim * sizeof(float));
            coords = own_pos.view(0, nb * dim * 4);
        }
        pos = coords;
        ensure(params_buf, sizeof(grid_params), "grid parameters");
        ensure(start, (geometry.slots + 1) * 4, "cell starts");
        ensure(point_slot, nb * 4, "point slots");
        ensure(point_rank, nb * 4, "point ranks");
        ensure(point_cell, nb * dim * 4, "point cells");
        ensure(tmp, nb * 4, "scatter buffer");
        ensure(perm, nb * 4, "sorted-to-original map");
        ensure(inverse, nb * 4, "original-to-sorted map");
        ensure(sorted_pos, nb * dim * 4, "sorted positions");
        ensure(sorted_cell, nb * dim * 4, "sorted cells");
        ensure(scan_scratch, scan_scratch_bytes(geometry.slots + 1), "scan scratch");

        // Insert, scan, scatter, stable pass: one submission.
        const std::uint32_t c = std::uint32_t(n);
        const auto n4 = [&](std::size_t per) { return std::max<std::size_t>(n * per * 4, 4); };
        dev->begin();
        clear_status();
        dev->update(params_buf.view(0, sizeof(grid_params)), &params, sizeof(grid_params));
        dev->fill(start.view(0, (geometry.slots + 1) * 4), 0u);
        if (n > 0) {
            dev->dispatch(dev->get(shader::insert, dim, kind_code()),
                          {params_buf.view(0, sizeof(grid_params)), pos, start.view(0, (geometry.slots + 1) * 4),
                           point_slot.view(0, n4(1)), point_rank.view(0, n4(1)), point_cell.view(0, n4(dim))},
                          nullptr, 0, groups_for(n, group_size));
            record_scan(start.view(0, (geometry.slots + 1) * 4), geometry.slots + 1, 0);
            dev->dispatch(dev->get(shader::scatter, dim),
                          {start.view(0, (geometry.slots + 1) * 4), point_slot.view(0, n4(1)), point_rank.view(0, n4(1)),
                           tmp.view(0, n4(1))},
                          &c, 4, groups_for(n, group_size));
            dev->dispatch(dev->get(shader::stable, dim),
                          {params_buf.view(0, sizeof(grid_params)), start.view(0, (geometry.slots + 1) * 4),
                           point_slot.view(0, n4(1)), tmp.view(0, n4(1)), pos,
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
    geometry = {};
    geometry.slots = 1;
    params = {};
    pos = {};
}

}  // namespace frnn::vulkan::detail
