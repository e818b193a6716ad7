#include "frnn/bench/cell_list.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "frnn/bench/row_builder.hpp"
#include "frnn/error.hpp"

namespace frnn::bench {
namespace {

template <class T, int D>
void bounds(std::span<const T> coords, std::array<double, D>& lo, std::array<double, D>& hi) {
    lo.fill(std::numeric_limits<double>::infinity());
    hi.fill(-std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < coords.size(); i += D)
        for (int a = 0; a < D; ++a) {
            lo[a] = std::min(lo[a], double(coords[i + a]));
            hi[a] = std::max(hi[a], double(coords[i + a]));
        }
}

// Cells per axis for an extent: floor(extent / r) + 1 covers [lo, hi] with cells of edge r.
double cells_on_axis(double extent, double r) { return std::floor(extent / r) + 1; }

}  // namespace

template <class T, int D>
std::optional<std::size_t> cell_list<T, D>::cells_needed(std::span<const T> coords, T radius) {
    if (coords.empty()) return std::size_t(1);
    std::array<double, D> lo, hi;
    bounds<T, D>(coords, lo, hi);
    double cells = 1;
    for (int a = 0; a < D; ++a) cells *= cells_on_axis(hi[a] - lo[a], double(radius));
    const double limit = std::max(8.0 * double(coords.size() / D), double(1 << 20));
    if (!(cells <= limit)) return std::nullopt;  // also catches NaN/inf
    return std::size_t(cells);
}

template <class T, int D>
cell_list<T, D>::cell_list(std::span<const T> coords, T radius) : coords_(coords), radius_(radius) {
    if (coords.size() % D != 0)
        throw error("cell list: " + std::to_string(coords.size()) +
                    " coordinates is not a multiple of " + std::to_string(D));
    if (!(radius > 0)) throw error("cell list: radius must be > 0");
    const auto cells = cells_needed(coords, radius);
    if (!cells) throw error("cell list: the bounding box needs too many cells of edge r");
    std::array<double, D> hi;
    bounds<T, D>(coords, lower_, hi);
    for (int a = 0; a < D; ++a)
        dims_[a] = coords.empty() ? 1 : std::int64_t(cells_on_axis(hi[a] - lower_[a], double(radius)));
    const std::size_t n = coords.size() / D;
    cells_.resize(*cells);
    for (std::size_t i = 0; i < n; ++i) {
        const auto c = cell_of(&coords[i * D]);
        std::size_t flat = 0;
        for (int a = D - 1; a >= 0; --a) flat = flat * std::size_t(dims_[a]) + std::size_t(c[a]);
        cells_[flat].push_back(std::uint32_t(i));
    }
}

template <class T, int D>
std::size_t cell_list<T, D>::memory_bytes() const {
    std::size_t bytes = cells_.size() * sizeof(cells_[0]);
    for (const auto& cell : cells_) bytes += cell.capacity() * sizeof(std::uint32_t);
    return bytes;
}

template <class T, int D>
std::array<std::int64_t, D> cell_list<T, D>::cell_of(const T* x) const {
    // The difference of two floats is exact in double and the division is correctly rounded,
    // so two points within r land at most one cell apart.
    std::array<std::int64_t, D> c;
    for (int a = 0; a < D; ++a) {
        const auto k = std::int64_t(std::floor((double(x[a]) - lower_[a]) / double(radius_)));
        c[a] = std::clamp<std::int64_t>(k, 0, dims_[a] - 1);
    }
    return c;
}

template <class T, int D>
template <class Emit>
void cell_list<T, D>::for_each_neighbor(std::size_t i, Emit&& emit) const {
    const T* x = &coords_[i * D];
    const auto c = cell_of(x);
    const T r2 = radius_ * radius_;
    std::array<std::int64_t, 3> lo{0, 0, 0}, hi{0, 0, 0};
    for (int a = 0; a < D; ++a) {
        lo[a] = std::max<std::int64_t>(c[a] - 1, 0);
        hi[a] = std::min<std::int64_t>(c[a] + 1, dims_[a] - 1);
    }
    for (std::int64_t cz = lo[2]; cz <= hi[2]; ++cz)
        for (std::int64_t cy = lo[1]; cy <= hi[1]; ++cy)
            for (std::int64_t cx = lo[0]; cx <= hi[0]; ++cx) {
                std::size_t flat = std::size_t(cx) + std::size_t(dims_[0]) * std::size_t(cy);
                if constexpr (D == 3) flat += std::size_t(dims_[0] * dims_[1]) * std::size_t(cz);
                for (const std::uint32_t j : cells_[flat]) {
                    if (j == i) continue;
                    const T* y = &coords_[std::size_t(j) * D];
                    T d2 = 0;
                    for (int a = 0; a < D; ++a) {
                        const T d = y[a] - x[a];
                        d2 += d * d;
                    }
                    if (d2 <= r2) emit(j);
                }
            }
}

template <class T, int D>
std::vector<std::uint32_t> cell_list<T, D>::count_neighbors() const {
    return detail::counts_from_rows(size(), 1,
                                    [this](std::size_t i, auto&& emit) { for_each_neighbor(i, emit); });
}

template <class T, int D>
csr<T> cell_list<T, D>::neighbor_lists() const {
    return detail::lists_from_rows<T>(size(), 1,
                                      [this](std::size_t i, auto&& emit) { for_each_neighbor(i, emit); });
}

template class cell_list<float, 2>;
template class cell_list<float, 3>;
template class cell_list<double, 2>;
template class cell_list<double, 3>;

}  // namespace frnn::bench
