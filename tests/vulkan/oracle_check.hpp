// The CPU oracle checker's comparisons (tests/oracle/oracle_check.hpp: reference rows, their
// renumbering and filtering by list_options, compare_csr), run on frnn::vulkan::grid<D>: the
// device is held to exactly what the CPU grid is held to, row for row and distance for distance.
// Paths the device lacks (callbacks, reorder) are the CPU's alone; everything else is checked:
// the permutation, counts in both numberings, lists for every list_options combination (or
// each value once at depth::basic), k nearest, and queries from other points (counts, lists,
// k nearest).
#pragma once
#include <gtest/gtest.h>

#include <span>
#include <string>
#include <vector>

#include "frnn/vulkan.hpp"
#include "oracle/oracle_check.hpp"

namespace frnn::vulkan::test {

using frnn::test::depth;

/// Empty when got[i] == want(i) for all n rows, else the first difference.
template <class Want>
std::string count_mismatch(const std::vector<std::uint32_t>& got, std::size_t n, const char* row, Want want) {
    if (got.size() != n) return std::to_string(got.size()) + " counts for " + std::to_string(n) + " rows";
    for (std::size_t i = 0; i < n; ++i)
        if (got[i] != want(i))
            return std::string(row) + " " + std::to_string(i) + ": " + std::to_string(got[i]) + " != oracle " +
                   std::to_string(want(i));
    return {};
}

/// Checks every query path of the device grid `g`, built over `coords` with `radius` and the
/// periodic box `periodic`, and queries from `queries`, against the brute-force oracle.
/// Failures are reported with ADD_FAILURE, one per path at most.
template <int D>
void check_device_grid(const grid<D>& g, std::span<const float> coords, float radius,
                       std::span<const double> periodic, std::span<const float> queries,
                       depth level = depth::full) {
    namespace t = frnn::test;
    const std::size_t n = coords.size() / D;
    const bool full = level == depth::full;
    auto fail = [](const std::string& path, const std::string& msg) {
        if (!msg.empty()) {
            ADD_FAILURE() << path << ": " << msg;
        }
        return !msg.empty();
    };
    if (g.size() != n) {
        ADD_FAILURE() << "size() " << g.size() << " != " << n;
        return;
    }
    const auto perm = g.sorted_to_original();
    std::vector<std::uint32_t> inv(n, 0xFFFFFFFFu);
    for (std::size_t s = 0; s < n; ++s) {
        if (perm[s] >= n || inv[perm[s]] != 0xFFFFFFFFu) {
            ADD_FAILURE() << "sorted_to_original is not a permutation (sorted " << s << ")";
            return;
        }
        inv[perm[s]] = std::uint32_t(s);
    }
    const t::rows_t<float> ref = t::reference_rows<float, D>(coords, coords, radius, true, periodic);

    for (auto space : {index_space::original, index_space::sorted})
        fail(std::string("count_neighbors(") + t::name(space) + ")",
             count_mismatch(g.count_neighbors(space), n, "point",
                            [&](std::size_t i) { return ref[space == index_space::sorted ? perm[i] : i].size(); }));

    for (const list_options& o : full ? t::all_list_options() : t::basic_list_options()) {
        const auto want = t::expected_self_rows<float>(ref, perm, inv, o);
        fail("neighbor_lists(" + t::describe(o) + ")", t::compare_csr<float>(g.neighbor_lists(o), want, o.distances, o.order));
    }

    for (std::size_t k : {std::size_t(1), std::size_t(4), std::size_t(100000)}) {
        if (!full && k != 4) continue;
        for (auto space : {index_space::original, index_space::sorted}) {
            list_options o;
            o.space = space;
            o.distances = space == index_space::original || full;
            const auto want = t::expected_self_rows<float>(ref, perm, inv, o);
            fail("nearest(" + std::to_string(k) + ", " + t::describe(o) + ")",
                 t::compare_csr<float>(g.nearest(k, o), want, o.distances, row_order::distance, k));
        }
    }

    // Queries: every fifth data point (each finds itself) and the given points.
    std::vector<float> all;
    for (std::size_t i = 0; i < n; i += 5) all.insert(all.end(), coords.begin() + i * D, coords.begin() + (i + 1) * D);
    all.insert(all.end(), queries.begin(), queries.end());
    const std::size_t nq = all.size() / D;
    const t::rows_t<float> qref = t::reference_rows<float, D>(all, coords, radius, false, periodic);
    fail("query_counts", count_mismatch(g.query_counts(all), nq, "query", [&](std::size_t q) { return qref[q].size(); }));
    for (auto space : {index_space::original, index_space::sorted}) {
        const auto want = t::expected_query_rows<float>(qref, inv, space);
        for (auto order : {row_order::none, row_order::index, row_order::distance}) {
            if (!full && (order == row_order::none) != (space == index_space::original)) continue;
            list_options o;
            o.space = space;
            o.order = order;
            o.distances = order != row_order::index;
            fail("query(" + t::describe(o) + ")", t::compare_csr<float>(g.query(all, o), want, o.distances, order));
        }
        for (std::size_t k : {std::size_t(1), std::size_t(5)}) {
            if (!full && k == 1) continue;
            list_options o;
            o.space = space;
            o.distances = true;
            fail("query_nearest(" + std::to_string(k) + ", " + t::describe(o) + ")",
                 t::compare_csr<float>(g.query_nearest(all, k, o), want, true, row_order::distance, k));
        }
    }
}

/// Builds a device grid and runs check_device_grid; a throwing build is a failure. Returns the
/// kind the grid took (automatic when the build failed).
template <int D>
grid_kind check_device(context& ctx, const std::vector<float>& coords, float radius, const grid_options& opt,
                       const std::vector<float>& queries, depth level = depth::full) {
    grid<D> g(ctx);
    try {
        g.build(coords, radius, opt);
    } catch (const std::exception& e) {
        ADD_FAILURE() << "build threw: " << e.what();
        return grid_kind::automatic;
    }
    // Periodic grids are always uniform; otherwise the kind asked for.
    if (opt.kind != grid_kind::automatic && opt.periodic.empty()) {
        EXPECT_EQ(g.kind(), opt.kind);
    }
    check_device_grid<D>(g, coords, radius, opt.periodic, queries, level);
    return g.kind();
}

}  // namespace frnn::vulkan::test
