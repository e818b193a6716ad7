// Baseline: brute force O(N^2), single-threaded, for N <= 32,768 only (bench/README.md). The
// lists come from frnn's own oracle (frnn/brute_force.hpp); the counts use its distance formula
// without storing anything. Thread-safe: no shared state.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "frnn/brute_force.hpp"

namespace frnn::bench {

inline constexpr std::size_t brute_max_points = 32768;

template <class T, int D>
std::vector<std::uint32_t> brute_count_neighbors(std::span<const T> coords, T radius) {
    const std::size_t n = coords.size() / D;
    const T r2 = radius * radius;
    std::vector<std::uint32_t> counts(n, 0);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            if (j != i && brute_distance_squared<T, D>(&coords[i * D], &coords[j * D]) <= r2)
                ++counts[i];
    return counts;
}

template <class T, int D>
csr<T> brute_neighbor_lists(std::span<const T> coords, T radius) {
    return brute_force_lists<T, D>(coords, coords, radius, true);
}

}  // namespace frnn::bench
