// The rules of cell_rules.hpp.
#include "core/cell_rules.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

#include "frnn/error.hpp"

namespace frnn::detail {

void apply_domain(const grid_options& o, int dim, double scale, double limit, double* lo, double* hi,
                  std::string_view who) {
    const std::string prefix(who);
    if (o.domain_min.empty() != o.domain_max.empty())
        throw error(prefix + "domain needs both domain_min and domain_max");
    if (o.domain_min.empty()) return;
    if (o.domain_min.size() != std::size_t(dim) || o.domain_max.size() != std::size_t(dim))
        throw error(prefix + "domain bounds need " + std::to_string(dim) + " values each");
    for (int a = 0; a < dim; ++a) {
        if (!std::isfinite(o.domain_min[a]) || !std::isfinite(o.domain_max[a]) || o.domain_min[a] > o.domain_max[a])
            throw error(prefix + "domain bounds on axis " + std::to_string(a) + " are not finite and ordered");
        lo[a] = std::clamp(o.domain_min[a], -limit, limit) * scale;
        hi[a] = std::clamp(o.domain_max[a], -limit, limit) * scale;
    }
}

std::array<std::int64_t, 3> box_cells(const double* box, const double* lo, const double* hi, int dim, double cell,
                                      std::size_t n) {
    std::array<std::int64_t, 3> dims{1, 1, 1};
    double cells = 1;
    for (int a = 0; a < dim; ++a) {
        const double along = box[a] > 0 ? std::floor(box[a] / cell) : std::floor((hi[a] - lo[a]) / cell) + 1;
        dims[a] = std::int64_t(std::clamp(along, 1.0, 0x1p30));
        cells *= double(dims[a]);
    }
    const double cap = std::max(8.0 * double(n), 4096.0);
    if (cells > cap) {
        // Fewer cells on the axes with the most first: the largest t for which at most t cells
        // per axis make no more than `cap` (a long open axis gives up cells before short ones).
        auto cells_at_most = [&](std::int64_t t) {
            double c = 1;
            for (int a = 0; a < dim; ++a) c *= double(std::min(dims[a], t));
            return c;
        };
        std::int64_t good = 1, bad = *std::max_element(dims.begin(), dims.begin() + dim);
        while (bad - good > 1) {
            const std::int64_t mid = good + (bad - good) / 2;
            (cells_at_most(mid) <= cap ? good : bad) = mid;
        }
        for (int a = 0; a < dim; ++a) dims[a] = std::min(dims[a], good);
    }
    return dims;
}

std::array<std::int64_t, 3> uniform_cells(const double* lo, const double* hi, int dim, double cell) {
    std::array<std::int64_t, 3> dims{1, 1, 1};
    for (int a = 0; a < dim; ++a) dims[a] = std::int64_t(std::floor((hi[a] - lo[a]) / cell)) + 1;
    return dims;
}

namespace {
template <class T>
void count_slots(grid_geometry<T>& g, int dim, std::size_t n) {
    g.slots = 1;
    if (g.kind == grid_kind::hashed) {
        g.slots = std::bit_ceil(std::max<std::size_t>(n, 64));
        return;
    }
    for (int a = 0; a < dim; ++a) g.slots *= std::size_t(g.dims[a]);
}
}  // namespace

template <class T>
void lay_out_periodic_cells(grid_geometry<T>& g, const double* box, const double* lo, const double* hi, int dim,
                            double cell, std::size_t n) {
    g.kind = grid_kind::uniform;
    g.dims = box_cells(box, lo, hi, dim, cell, n);
    for (int a = 0; a < dim; ++a) {
        if (box[a] > 0) {
            g.cell[a] = double(g.box[a]) / double(g.dims[a]);
            g.inv_cell[a] = double(g.dims[a]) / double(g.box[a]);
            g.origin[a] = 0;
        } else {
            // Fewer cells than asked only when the box is sparse: then as wide as covers [lo, hi].
            g.cell[a] = std::max(cell, hi[a] / double(g.dims[a]) - lo[a] / double(g.dims[a]));
            g.inv_cell[a] = 1.0 / g.cell[a];
            g.origin[a] = lo[a];
        }
    }
    count_slots(g, dim, n);
}

template <class T>
void lay_out_open_cells(grid_geometry<T>& g, const double* lo, const double* hi, int dim, double cell,
                        std::size_t n) {
    g.dims = {1, 1, 1};
    if (g.kind == grid_kind::uniform) g.dims = uniform_cells(lo, hi, dim, cell);
    for (int a = 0; a < dim; ++a) {
        g.cell[a] = cell;
        g.inv_cell[a] = 1.0 / cell;
        g.origin[a] = lo[a];
    }
    count_slots(g, dim, n);
}

template void lay_out_periodic_cells(grid_geometry<float>&, const double*, const double*, const double*, int, double,
                                     std::size_t);
template void lay_out_periodic_cells(grid_geometry<double>&, const double*, const double*, const double*, int, double,
                                     std::size_t);
template void lay_out_open_cells(grid_geometry<float>&, const double*, const double*, int, double, std::size_t);
template void lay_out_open_cells(grid_geometry<double>&, const double*, const double*, int, double, std::size_t);

}  // namespace frnn::detail
