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

std::array<std::int64_t, 3> periodic_cells(const double* box, int dim, double cell, std::size_t n) {
    std::array<std::int64_t, 3> dims{1, 1, 1};
    double cells = 1;
    for (int a = 0; a < dim; ++a) {
        dims[a] = std::int64_t(std::clamp(std::floor(box[a] / cell), 1.0, 0x1p30));
        cells *= double(dims[a]);
    }
    const double cap = std::max(8.0 * double(n), 4096.0);
    if (cells > cap) {
        const double shrink = std::pow(cells / cap, 1.0 / dim);
        for (int a = 0; a < dim; ++a) dims[a] = std::max<std::int64_t>(1, std::int64_t(double(dims[a]) / shrink));
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
void lay_out_periodic_cells(grid_geometry<T>& g, const double* box, int dim, double cell, std::size_t n) {
    g.kind = grid_kind::uniform;
    g.dims = periodic_cells(box, dim, cell, n);
    for (int a = 0; a < dim; ++a) {
        g.cell[a] = double(g.box[a]) / double(g.dims[a]);
        g.inv_cell[a] = double(g.dims[a]) / double(g.box[a]);
        g.origin[a] = 0;
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

template void lay_out_periodic_cells(grid_geometry<float>&, const double*, int, double, std::size_t);
template void lay_out_periodic_cells(grid_geometry<double>&, const double*, int, double, std::size_t);
template void lay_out_open_cells(grid_geometry<float>&, const double*, const double*, int, double, std::size_t);
template void lay_out_open_cells(grid_geometry<double>&, const double*, const double*, int, double, std::size_t);

}  // namespace frnn::detail
