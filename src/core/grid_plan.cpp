// The choice of a grid's geometry (grid_plan.hpp): validation of the input, search scale, kind,
// cell size, reach, cells per axis or table slots.
#include "core/grid_plan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "core/cell_rules.hpp"
#include "core/kind_policy.hpp"
#include "core/sweep.hpp"
#include "cpu/parallel.hpp"
#include "frnn/error.hpp"
#include "frnn/periodic_wrap.hpp"
#include "frnn/search_scale.hpp"

namespace frnn::detail {

namespace {

// Cells are made this much larger than asked so that rounding in the cell computation can
// never separate two points within r by more than `reach` cells.
constexpr double cell_margin = 1.0 + 0x1p-20;
// Cell coordinates beyond this magnitude are rejected: neighbors are found at +-reach, and the
// coordinates must stay exact in a double.
constexpr double max_cell_coordinate = 0x1p52;
// A uniform grid may have at most this many cells when asked for explicitly, or over the
// points near the origin when others lie beyond the hashed grid's keys: 4 bytes each, so at
// most 64 MB or 256 bytes per point (three points 2^30 cells apart took 8 GB under a fixed
// 2^31), and below 2^31 for 32-bit slots.
double uniform_cell_budget(std::size_t n) { return std::min(0x1p31, std::max(0x1p24, 64.0 * double(n))); }
std::string fmt_double(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

}  // namespace

// Validates the input and chooses the geometry: search scale, kind, cell size, reach,
// dimensions. Changes nothing, so that a build that throws leaves the grid as it was.
template <class T, int D>
grid_geometry<T> plan_geometry(std::span<const T> coords, T radius, const grid_options& o, buffer<T>& scaled) {
    scaled.clear();  // a build's scratch: its memory stays for the next build
    grid_geometry<T> l;
    if (!std::isfinite(radius) || radius <= 0)
        throw error("radius must be finite and > 0 (got " + fmt_double(double(radius)) + ")");
    if (coords.size() % D != 0)
        throw error("coordinate array has " + std::to_string(coords.size()) +
                    " values, not a multiple of the dimension " + std::to_string(D));
    const std::size_t n = coords.size() / D;
    if (n >= std::numeric_limits<std::uint32_t>::max())
        throw error("too many points: " + std::to_string(n) + " (at most 2^32 - 2)");
    const double user_r = double(radius);
    if (o.cell_size != 0) {
        const double asked = o.cell_size;
        if (!std::isfinite(asked) || asked <= 0)
            throw error("cell size must be finite and > 0 (got " + fmt_double(asked) + ")");
        if (asked > user_r * (1 + 1e-12))
            throw error("cell size " + fmt_double(asked) + " is larger than the radius " + fmt_double(user_r));
        if (asked < user_r / 4 * (1 - 1e-12))
            throw error("cell size " + fmt_double(asked) + " is smaller than radius/4 = " + fmt_double(user_r / 4));
    }
    const int threads = resolve_thread_count(o.threads);
    const std::size_t layout_n = o.layout_points > 0 ? o.layout_points : n;  // what the cells are laid out for

    // Finite coordinates, and the bounding box (first bad index reported).
    std::array<double, 3> lo{0, 0, 0}, hi{0, 0, 0};
    {
        const std::size_t parts = chunk_count(n, threads, 1 << 15);
        std::vector<std::size_t> first_bad(parts, n);
        std::vector<std::array<double, 6>> box(parts);
        for_each_chunk(n, parts, threads, [&](std::size_t c, std::size_t b, std::size_t e) {
            T mn[D], mx[D], nonfinite[D];
            sweep_for_cpu<T, D>().bounds(coords.data(), b, e, mn, mx, nonfinite);
            std::array<double, 6> bb;
            for (int a = 0; a < 3; ++a) bb[a] = INFINITY, bb[3 + a] = -INFINITY;
            for (int a = 0; a < D; ++a) {
                bb[a] = double(mn[a]), bb[3 + a] = double(mx[a]);
                if (nonfinite[a] != 0) {
                    for (std::size_t i = b; i < e && first_bad[c] == n; ++i)
                        for (int k = 0; k < D; ++k)
                            if (!std::isfinite(coords[i * D + k])) first_bad[c] = i;
                }
            }
            box[c] = bb;
        });
        for (std::size_t c = 0; c < parts; ++c) {
            if (first_bad[c] < n)
                throw error("point " + std::to_string(first_bad[c]) + " has a non-finite coordinate");
        }
        for (int a = 0; a < D; ++a) {
            lo[a] = INFINITY, hi[a] = -INFINITY;
            for (const auto& bb : box) lo[a] = std::min(lo[a], bb[a]), hi[a] = std::max(hi[a], bb[3 + a]);
            if (n == 0) lo[a] = hi[a] = 0;
        }
    }

    if (!o.periodic.empty()) {
        if (o.periodic.size() != std::size_t(D))
            throw error("periodic box needs " + std::to_string(D) + " lengths (0 for an open axis), got " +
                        std::to_string(o.periodic.size()));
        for (int a = 0; a < D; ++a) {
            const double box = o.periodic[a];
            if (box == 0) continue;  // an open axis
            if (!std::isfinite(box) || box < 0 || box > double(std::numeric_limits<T>::max()))
                throw error("periodic box length " + fmt_double(box) + " on axis " + std::to_string(a) +
                            " is not 0 (open) or a positive finite value of the points' type");
            if (box < 2 * user_r)
                throw error("periodic box length " + fmt_double(box) + " on axis " + std::to_string(a) +
                            " is smaller than twice the radius (" + fmt_double(2 * user_r) + ")");
            l.wraps[a] = true;
            l.periodic = true;
        }
    }

    // The search scale: coordinates, radius, cell size and box in search space from here on.
    // Coordinates of periodic axes are wrapped into the box first (frnn/periodic_wrap.hpp), so
    // the box lengths bound them.
    T largest = largest_magnitude<T>({}, o.periodic);
    for (int a = 0; a < D; ++a)
        if (!l.wraps[a]) largest = std::max(largest, T(std::max(std::abs(lo[a]), std::abs(hi[a]))));
    l.scale = frnn::search_scale<T>(radius, largest);
    l.search_radius = radius * l.scale;
    std::array<T, D> caller_box{};  // 0 on open axes
    bool wrap = false;
    for (int a = 0; a < D; ++a) {
        if (!l.wraps[a]) continue;
        caller_box[a] = T(o.periodic[a]);
        wrap = wrap || lo[a] < 0 || hi[a] >= double(caller_box[a]);
    }
    if (l.scale != 1 || wrap) {
        scaled.resize(coords.size());
        for_each_chunk(n, chunk_count(n, threads, 1 << 15), threads, [&](std::size_t, std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i)
                for (int a = 0; a < D; ++a) {
                    const T v = coords[i * D + a];
                    scaled[i * D + a] = (l.wraps[a] ? wrap_into_box(v, caller_box[a]) : v) * l.scale;
                }
        });
        coords = scaled;
        // Periodic axes are laid out from the box alone; open ones from the scaled span.
        for (int a = 0; a < D; ++a) lo[a] = double(T(lo[a]) * l.scale), hi[a] = double(T(hi[a]) * l.scale);
    }
    const double r = double(l.search_radius);
    const double cell = (o.cell_size == 0 ? r : o.cell_size * double(l.scale)) * cell_margin;
    l.reach = int(std::ceil(r / cell));

    if (l.periodic) {
        double box[3] = {0, 0, 0};
        for (int a = 0; a < D; ++a) {
            if (!l.wraps[a]) continue;
            box[a] = o.periodic[a] * double(l.scale);
            l.box[a] = caller_box[a] * l.scale;
        }
        kind_question q;
        q.n = n;
        q.cell = cell;
        q.radius = r;
        q.hashed_key_limit = max_cell_coordinate;
        q.uniform_cell_limit = uniform_cell_budget(layout_n);
        span_open_axes<T, D>(q, l.wraps.data(), box, coords, threads, lo.data(), hi.data());
        if (!o.domain_min.empty() || !o.domain_max.empty()) {  // bounds for the open axes
            std::array<double, 3> dlo = lo, dhi = hi;
            apply_domain(o, D, double(l.scale), double(std::numeric_limits<T>::max()), dlo.data(), dhi.data(), "");
            for (int a = 0; a < D; ++a)
                if (!l.wraps[a]) lo[a] = dlo[a], hi[a] = dhi[a];
        }
        lay_out_periodic_cells(l, box, lo.data(), hi.data(), D, cell, layout_n);
    } else {
        apply_domain(o, D, double(l.scale), double(std::numeric_limits<T>::max()), lo.data(), hi.data(), "");
        kind_question q;
        q.asked = o.kind;
        q.n = n;
        for (int a = 0; a < D; ++a) q.lo[a] = lo[a], q.hi[a] = hi[a];
        q.explicit_domain = !o.domain_min.empty();
        q.cell = cell;
        q.radius = r;
        q.hashed_key_limit = max_cell_coordinate;
        q.uniform_cell_limit = uniform_cell_budget(layout_n);
        const kind_answer choice = choose_kind<T, D>(q, coords, threads);
        const grid_kind kind = choice.kind;
        const double cells = choice.cells;
        for (int a = 0; a < D; ++a) lo[a] = choice.lo[a], hi[a] = choice.hi[a];
        if (kind == grid_kind::uniform && !(cells <= uniform_cell_budget(layout_n)))
            throw error("a uniform grid over this domain would need " + fmt_double(cells) +
                        " cells (extent / cell size), more than its budget of " + fmt_double(uniform_cell_budget(layout_n)) +
                        " for " + std::to_string(layout_n) + " points (the larger of 2^24 and 64 per point); use the hashed grid");
        l.kind = kind;
        lay_out_open_cells(l, lo.data(), hi.data(), D, cell, layout_n);
        if (l.kind == grid_kind::hashed) {
            double extent = 0;
            for (int a = 0; a < D; ++a) {
                // The CPU's hashed kernels count cells from 0: the keys of far cells stay exact
                // up to 2^52 cells out, with no subtraction to round.
                l.origin[a] = 0;
                const double far = std::max(std::abs(lo[a]), std::abs(hi[a]));
                if (far * l.inv_cell[a] >= max_cell_coordinate)
                    throw error("coordinates too far out for the hashed grid: |" +
                                fmt_double(far / double(l.scale)) + "| on axis " + std::to_string(a) +
                                " is more than 2^52 cells from the origin");
                extent = std::max(extent, far);
            }
            // Queries farther out than every point by the stencil and a cell have no neighbors.
            l.far_bound = extent + (l.reach + 2) * cell;
        }
    }
    return l;
}

template grid_geometry<float> plan_geometry<float, 2>(std::span<const float>, float, const grid_options&,
                                                      buffer<float>&);
template grid_geometry<float> plan_geometry<float, 3>(std::span<const float>, float, const grid_options&,
                                                      buffer<float>&);
template grid_geometry<double> plan_geometry<double, 2>(std::span<const double>, double, const grid_options&,
                                                        buffer<double>&);
template grid_geometry<double> plan_geometry<double, 3>(std::span<const double>, double, const grid_options&,
                                                        buffer<double>&);

}  // namespace frnn::detail
