// Brute-force O(N*M) reference search: the oracle every grid query is tested against, and
// the O(N^2) baseline of the benchmarks. Single-threaded, header-only; distances use exactly
// the grid's formula (coordinates wrapped into the box and the minimum image on the axes whose
// `periodic` length is > 0, frnn/periodic_wrap.hpp) and its search scale for
// extreme radii (frnn/search_scale.hpp), so decisions at |d| == r agree.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "frnn/csr.hpp"
#include "frnn/options.hpp"
#include "frnn/search_scale.hpp"

namespace frnn {

/// Squared distance in the caller's units, without the search scale: exact only while the
/// squares stay within T's range (distance_test is exact for all finite input).
template <class T, int D>
T brute_distance_squared(const T* a, const T* b, std::span<const double> periodic = {}) {
    T d2 = 0;
    for (int k = 0; k < D; ++k) {
        T d = b[k] - a[k];
        if (!periodic.empty() && periodic[k] > 0) {  // 0: an open axis
            const T box = T(periodic[k]);
            d = wrap_into_box(b[k], box) - wrap_into_box(a[k], box);
            d -= box * std::nearbyint(d / box);
        }
        d2 += d * d;
    }
    return d2;
}

/// Row q: every data index j with |queries_q - data_j| <= r, increasing j, with distances.
/// When `exclude_same` (queries are the data), j == q is left out. The search scale is the
/// grid's: from the radius, the data and the box.
template <class T, int D>
csr<T> brute_force_lists(std::span<const T> queries, std::span<const T> data, T radius,
                         bool exclude_same, std::span<const double> periodic = {}) {
    csr<T> out;
    const std::size_t nq = queries.size() / D, nd = data.size() / D;
    const distance_test<T, D> test(radius, search_scale<T>(radius, largest_magnitude<T>(data, periodic)), periodic);
    out.offsets.assign(nq + 1, 0);
    for (std::size_t q = 0; q < nq; ++q) {
        for (std::size_t j = 0; j < nd; ++j) {
            if (exclude_same && j == q) continue;
            T d2;
            if (test.within(&queries[q * D], &data[j * D], d2)) {
                out.indices.push_back(std::uint32_t(j));
                out.distances.push_back(test.distance(d2));
            }
        }
        out.offsets[q + 1] = out.indices.size();
    }
    return out;
}

/// The same with radii of their own (grid::build with radii, grid::query with query radii):
/// row q holds every data index j with |queries_q - data_j| <= query_radii[q] (gather, or
/// data_radii empty), or <= max(query_radii[q], data_radii[j]) (symmetric). The search scale
/// is that of a grid of radius `grid_radius` (the largest data radius, or the grid's one).
template <class T, int D>
csr<T> brute_force_lists(std::span<const T> queries, std::span<const T> query_radii, std::span<const T> data,
                         std::span<const T> data_radii, radius_rule rule, T grid_radius, bool exclude_same,
                         std::span<const double> periodic = {}) {
    csr<T> out;
    const std::size_t nq = queries.size() / D, nd = data.size() / D;
    const T s = search_scale<T>(grid_radius, largest_magnitude<T>(data, periodic));
    const distance_test<T, D> test(grid_radius, s, periodic);
    const bool symmetric = rule == radius_rule::symmetric && !data_radii.empty();
    auto squared = [&](T r) { return (r * s) * (r * s); };
    out.offsets.assign(nq + 1, 0);
    for (std::size_t q = 0; q < nq; ++q) {
        const T own = squared(query_radii[q]);
        for (std::size_t j = 0; j < nd; ++j) {
            if (exclude_same && j == q) continue;
            const T d2 = test.scaled_distance_squared(&queries[q * D], &data[j * D]);
            if (d2 <= (symmetric ? std::max(own, squared(data_radii[j])) : own)) {
                out.indices.push_back(std::uint32_t(j));
                out.distances.push_back(test.distance(d2));
            }
        }
        out.offsets[q + 1] = out.indices.size();
    }
    return out;
}

}  // namespace frnn
