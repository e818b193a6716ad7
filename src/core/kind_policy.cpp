// The automatic choice of grid kind (kind_policy.hpp).
#include "core/kind_policy.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "cpu/parallel.hpp"

namespace frnn::detail {

namespace {

// The box of the bulk of the points: per axis, the range between the 1/1024 quantiles of a
// sample of about 2^14 points, widened by an eighth of itself (and at least one cell) on each
// side, so that points of a compact bulk all fall inside.
template <class T, int D>
void bulk_box(std::span<const T> coords, double cell, double* lo, double* hi) {
    const std::size_t n = coords.size() / D;
    const std::size_t stride = std::max<std::size_t>(1, n >> 14);
    std::vector<double> v;
    for (int a = 0; a < D; ++a) {
        v.clear();
        for (std::size_t i = 0; i < n; i += stride) v.push_back(double(coords[i * D + a]));
        const std::size_t k = v.size() / 1024;
        std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
        const double low = v[k];
        std::nth_element(v.begin(), v.end() - std::ptrdiff_t(k + 1), v.end());
        const double high = v[v.size() - k - 1];
        const double margin = std::max((high - low) / 8, cell);
        lo[a] = low - margin, hi[a] = high + margin;
    }
}

// How many points lie outside the box [lo, hi].
template <class T, int D>
std::size_t count_outside(std::span<const T> coords, const double* lo, const double* hi, int threads) {
    const std::size_t n = coords.size() / D;
    const std::size_t parts = chunk_count(n, threads, 1 << 15);
    std::vector<std::size_t> outside(parts, 0);
    for_each_chunk(n, parts, threads, [&](std::size_t c, std::size_t b, std::size_t e) {
        std::size_t count = 0;
        for (std::size_t i = b; i < e; ++i) {
            bool out = false;
            for (int a = 0; a < D; ++a) {
                const double x = double(coords[i * D + a]);
                out |= (x < lo[a]) | (x > hi[a]);
            }
            count += out;
        }
        outside[c] = count;
    });
    std::size_t total = 0;
    for (auto v : outside) total += v;
    return total;
}

}  // namespace

template <class T, int D>
kind_answer choose_kind(const kind_question& q, std::span<const T> coords, int threads) {
    auto cells_over = [&](const double* lo, const double* hi) {
        double cells = q.fixed_cells;
        for (int a = 0; a < D; ++a)
            if (!q.fixed[a]) cells *= std::floor((hi[a] - lo[a]) / q.cell) + 1;
        return cells;
    };
    kind_answer out;
    for (int a = 0; a < 3; ++a) out.lo[a] = q.lo[a], out.hi[a] = q.hi[a];
    out.cells = cells_over(q.lo, q.hi);
    out.kind = q.asked;
    if (q.asked != grid_kind::automatic) return out;
    // Cells smaller than r multiply the cells of a box by (r / cell)^D; the hashed grid would
    // then look up that many more cells per point (nearly all empty), which costs far more than
    // their 4 bytes each in a uniform grid. So the budget grows with them, up to 8 times.
    const double cap = std::max(4.0 * double(q.n), 4096.0) * std::min(8.0, std::pow(q.radius / q.cell, D));
    if (out.cells <= cap) {
        out.kind = grid_kind::uniform;
        return out;
    }
    out.kind = grid_kind::hashed;
    if (q.explicit_domain || coords.empty()) return out;
    // A few far outliers should not force the hashed grid: a uniform grid over the bulk takes
    // them into its border cells (exact, as with an explicit domain) when they are at most one
    // in 1024 points. It also takes them, however many, when they lie beyond the hashed grid's
    // keys (slower for them, never wrong), if the box of the rest needs few enough cells.
    double blo[3] = {0, 0, 0}, bhi[3] = {0, 0, 0};
    bulk_box<T, D>(coords, q.cell, blo, bhi);
    bool beyond_keys = false;
    for (int a = 0; a < D; ++a) {
        if (q.fixed[a]) {
            blo[a] = -INFINITY, bhi[a] = INFINITY;  // nobody is outside on a fixed axis
            continue;
        }
        beyond_keys |= std::max(std::abs(q.lo[a]), std::abs(q.hi[a])) / q.cell >= q.hashed_key_limit;
    }
    const double bulk_cells = cells_over(blo, bhi);
    if (bulk_cells <= cap && count_outside<T, D>(coords, blo, bhi, threads) <= q.n / 1024) {
        for (int a = 0; a < D; ++a)
            if (!q.fixed[a]) out.lo[a] = blo[a], out.hi[a] = bhi[a];
        out.cells = bulk_cells;
        out.kind = grid_kind::uniform;
    } else if (beyond_keys) {
        // Too many for the bulk's quantiles: the box of the coordinates within a quarter of
        // the keys, per axis (a point beyond it on one axis is folded on that axis only).
        const double near = q.hashed_key_limit / 4 * q.cell;
        double klo[3] = {0, 0, 0}, khi[3] = {0, 0, 0};
        for (int a = 0; a < D; ++a) klo[a] = INFINITY, khi[a] = -INFINITY;
        for (std::size_t i = 0; i < coords.size(); ++i) {
            const double x = double(coords[i]);
            const int a = int(i % D);
            if (std::abs(x) < near) klo[a] = std::min(klo[a], x), khi[a] = std::max(khi[a], x);
        }
        for (int a = 0; a < D; ++a)
            if (klo[a] > khi[a]) klo[a] = khi[a] = 0;  // no coordinate near: one layer of cells
        const double cells = cells_over(klo, khi);
        if (cells <= q.uniform_cell_limit) {
            for (int a = 0; a < D; ++a)
                if (!q.fixed[a]) out.lo[a] = klo[a], out.hi[a] = khi[a];
            out.cells = cells;
            out.kind = grid_kind::uniform;
        }
    }
    return out;
}

template <class T, int D>
void span_open_axes(kind_question q, const bool* wraps, const double* box, std::span<const T> coords, int threads,
                    double* lo, double* hi) {
    bool open = false;
    q.asked = grid_kind::automatic;
    q.fixed_cells = 1;
    for (int a = 0; a < D; ++a) {
        q.lo[a] = lo[a], q.hi[a] = hi[a];
        q.fixed[a] = wraps[a];
        if (wraps[a]) q.fixed_cells *= std::clamp(std::floor(box[a] / q.cell), 1.0, 0x1p30);
        open = open || !wraps[a];
    }
    if (!open) return;
    const kind_answer choice = choose_kind<T, D>(q, coords, threads);
    for (int a = 0; a < D; ++a)
        if (!wraps[a]) lo[a] = choice.lo[a], hi[a] = choice.hi[a];
}

template kind_answer choose_kind<float, 2>(const kind_question&, std::span<const float>, int);
template kind_answer choose_kind<float, 3>(const kind_question&, std::span<const float>, int);
template kind_answer choose_kind<double, 2>(const kind_question&, std::span<const double>, int);
template kind_answer choose_kind<double, 3>(const kind_question&, std::span<const double>, int);

template void span_open_axes<float, 2>(kind_question, const bool*, const double*, std::span<const float>, int,
                                       double*, double*);
template void span_open_axes<float, 3>(kind_question, const bool*, const double*, std::span<const float>, int,
                                       double*, double*);
template void span_open_axes<double, 2>(kind_question, const bool*, const double*, std::span<const double>, int,
                                        double*, double*);
template void span_open_axes<double, 3>(kind_question, const bool*, const double*, std::span<const double>, int,
                                        double*, double*);

}  // namespace frnn::detail
