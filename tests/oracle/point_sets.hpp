// Point-set generators for the oracle tests: random sets (uniform, clustered) and adversarial
// ones (integer lattices at exactly distance r, one cell, duplicates, outliers, ...).
// Every generator is deterministic for a given seed; coordinates are N*D interleaved values.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace frnn::test {

/// N points uniform in [lo, hi)^D.
template <class T, int D>
std::vector<T> uniform_points(std::size_t n, double lo, double hi, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(lo, hi);
    std::vector<T> out(n * D);
    for (auto& v : out) v = T(u(rng));
    return out;
}

/// N points in `blobs` gaussian blobs (sigma `sigma`) whose centres are uniform in [lo, hi)^D:
/// dense clusters next to empty space, the typical fluid surface case.
template <class T, int D>
std::vector<T> clustered_points(std::size_t n, std::size_t blobs, double sigma, double lo,
                                double hi, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(lo, hi);
    std::normal_distribution<double> g(0.0, sigma);
    std::vector<double> centres(blobs * D);
    for (auto& c : centres) c = u(rng);
    std::vector<T> out(n * D);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t b = i % blobs;
        for (int a = 0; a < D; ++a) out[i * D + a] = T(centres[b * D + a] + g(rng));
    }
    return out;
}

/// Integer lattice with `side` points per axis, spacing `step`, starting at `origin` on every
/// axis. With an integer radius every distance computation is exact, so pairs at exactly r
/// must be found.
template <class T, int D>
std::vector<T> lattice_points(int side, double step, double origin = 0) {
    std::vector<T> out;
    int idx[3] = {0, 0, 0};
    const int total = D == 2 ? side * side : side * side * side;
    for (int p = 0; p < total; ++p) {
        int rest = p;
        for (int a = 0; a < D; ++a) {
            idx[a] = rest % side;
            rest /= side;
        }
        for (int a = 0; a < D; ++a) out.push_back(T(origin + idx[a] * step));
    }
    return out;
}

/// `points` with every point repeated `copies` times, the copies interleaved (not adjacent).
template <class T>
std::vector<T> with_duplicates(const std::vector<T>& points, int dim, int copies) {
    const std::size_t n = points.size() / dim;
    std::vector<T> out;
    out.reserve(points.size() * copies);
    for (int c = 0; c < copies; ++c)
        for (std::size_t i = 0; i < n; ++i)
            for (int a = 0; a < dim; ++a) out.push_back(points[i * dim + a]);
    return out;
}

/// Random points whose coordinates are integer multiples of `cell` (every point lies exactly on
/// cell faces, edges and corners when the cell size is `cell` and the origin is a multiple).
template <class T, int D>
std::vector<T> on_cell_boundaries(std::size_t n, double cell, int cells_per_axis,
                                  std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<int> u(-cells_per_axis / 2, cells_per_axis / 2);
    std::vector<T> out(n * D);
    for (auto& v : out) v = T(u(rng) * cell);
    return out;
}

/// Sparse points, each in its own cell of edge `cell`, spread over a region of `spread` cells per
/// axis: many distinct cells for few points, so a hash table sized from N has collisions.
template <class T, int D>
std::vector<T> sparse_cells(std::size_t n, double cell, std::int64_t spread, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<std::int64_t> u(-spread / 2, spread / 2);
    std::uniform_real_distribution<double> f(0.1, 0.9);
    std::vector<T> out(n * D);
    for (auto& v : out) v = T((double(u(rng)) + f(rng)) * cell);
    return out;
}

/// Appends one point with all coordinates equal to `value`.
template <class T, int D>
void append_point(std::vector<T>& points, double value) {
    for (int a = 0; a < D; ++a) points.push_back(T(value));
}

}  // namespace frnn::test

namespace frnn::test {

/// Query points for `data`: `n` uniform over its bounding box grown by 2r on every side (so some
/// fall outside the data's cells), plus one far point. On the periodic axes of `periodic`
/// (length > 0), uniform in [0, L) instead; the far point only when no axis is periodic.
template <class T, int D>
std::vector<T> query_points(const std::vector<T>& data, double radius, std::size_t n,
                            const std::vector<double>& periodic, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    if (!data.empty()) {
        for (int a = 0; a < D; ++a) {
            lo[a] = std::numeric_limits<double>::infinity();
            hi[a] = -lo[a];
        }
        for (std::size_t i = 0; i < data.size(); ++i) {
            lo[i % D] = std::min(lo[i % D], double(data[i]));
            hi[i % D] = std::max(hi[i % D], double(data[i]));
        }
        for (int a = 0; a < D; ++a) {
            lo[a] -= 2 * radius;
            hi[a] += 2 * radius;
        }
    }
    bool some_periodic = false;
    for (std::size_t a = 0; a < periodic.size() && a < std::size_t(D); ++a) {
        if (periodic[a] <= 0) continue;
        lo[a] = 0, hi[a] = periodic[a];
        some_periodic = true;
    }
    std::vector<T> out;
    for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < D; ++a)
            out.push_back(T(std::uniform_real_distribution<double>(lo[a], hi[a])(rng)));
    if (!some_periodic) append_point<T, D>(out, -1e6);
    return out;
}

}  // namespace frnn::test
