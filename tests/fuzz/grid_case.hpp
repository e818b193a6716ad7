// A search case decoded from a fuzzer's bytes, shared by the harnesses that check a backend
// against the brute-force oracle (grid_fuzz.cpp: the CPU grid; vulkan_fuzz.cpp: the Vulkan
// grid), so that one corpus drives both: up to 39 points, a radius or a radius per point, a
// rule, a kind, a cell size, a box with open and periodic axes, and up to 7 query points
// (with radii on a grid of radii), a k for the k nearest, and a skin and a move of every point
// for Verlet lists. Values come from fuzz_input::value: quarter integers times a
// power of two, special values or raw bit patterns.
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <tuple>
#include <cstring>
#include <type_traits>
#include <vector>

#include "frnn/csr.hpp"
#include "frnn/options.hpp"
#include "fuzz_input.hpp"

namespace frnn::fuzz {

template <class T, int D>
struct grid_case {
    std::vector<T> points, radii;          ///< radii: empty, or one per point
    std::vector<T> queries, query_radii;   ///< query_radii: one per query on a grid of radii
    T radius = 1;
    grid_options options;
    bool per_point = false;                ///< radii and query radii are given (none for no points)
    std::size_t k = 1;                     ///< for the k nearest, 1 to 4
    T skin = 0;                            ///< for Verlet lists
    std::vector<T> moves;                  ///< for Verlet lists: a displacement per coordinate
};

/// The case the bytes describe (the order of reads is the corpus's format: keep it).
template <class T, int D>
grid_case<T, D> decode_grid_case(fuzz_input& in) {
    grid_case<T, D> c;
    const std::size_t n = in.below(40);
    const T scale = in.scale<T>(std::is_same_v<T, float> ? 130 : 1030);
    c.per_point = in.flag();
    c.options.kind = grid_kind(in.below(3));
    c.options.rule = in.flag() ? radius_rule::symmetric : radius_rule::gather;
    c.radius = in.value<T>(scale);
    if (c.per_point)
        for (std::size_t i = 0; i < n; ++i) c.radii.push_back(in.value<T>(scale));
    if (in.flag())
        for (int a = 0; a < D; ++a) c.options.periodic.push_back(in.flag() ? 0.0 : double(in.value<T>(scale)));
    if (!c.per_point) {
        const double fraction[] = {0, 1, 0.5, 1.0 / 3, 0.25};
        c.options.cell_size = fraction[in.below(5)] * double(c.radius);
    }
    c.points.resize(n * D);
    for (auto& v : c.points) v = in.value<T>(scale);
    const std::size_t m = in.below(8);
    c.queries.resize(m * D);
    for (auto& v : c.queries) v = in.value<T>(scale);
    for (std::size_t q = 0; c.per_point && q < m; ++q) c.query_radii.push_back(in.value<T>(scale));
    c.k = 1 + in.below(4);
    c.skin = in.value<T>(scale);
    c.moves.resize(n * D);
    for (auto& v : c.moves) v = in.value<T>(scale);
    return c;
}

/// The decoded case, for a person reading a finding (FRNN_FUZZ_PRINT=1).
template <class T, int D>
void print(const grid_case<T, D>& c) {
    const grid_options& o = c.options;
    std::fprintf(stderr, "%s %dD, %zu points, kind %d, rule %d, cell %.17g, radius %.17g\n", sizeof(T) == 4 ? "float" : "double",
                 D, c.points.size() / D, int(o.kind), int(o.rule), o.cell_size, double(c.radius));
    for (double b : o.periodic) std::fprintf(stderr, "  box %.17g\n", b);
    auto rows = [](const char* what, const std::vector<T>& xs, const std::vector<T>& rs) {
        for (std::size_t i = 0; i < xs.size() / D; ++i) {
            std::fprintf(stderr, "  %s %zu:", what, i);
            for (int a = 0; a < D; ++a) std::fprintf(stderr, " %.17g", double(xs[i * D + a]));
            if (!rs.empty()) std::fprintf(stderr, "  r %.17g", double(rs[i]));
            std::fprintf(stderr, "\n");
        }
    };
    rows("point", c.points, c.radii);
    rows("query", c.queries, c.query_radii);
    std::fprintf(stderr, "  k %zu, skin %.17g\n", c.k, double(c.skin));
    rows("move", c.moves, {});
}

/// Whether two lists are the same: offsets, indices and (when `distances`) distances bit for bit.
template <class T>
bool same(const csr<T>& a, const csr<T>& b, bool distances) {
    if (a.offsets.size() != b.offsets.size() || a.indices.size() != b.indices.size()) return false;
    if (!std::equal(a.offsets.begin(), a.offsets.end(), b.offsets.begin())) return false;
    if (!std::equal(a.indices.begin(), a.indices.end(), b.indices.begin())) return false;
    return !distances || (a.distances.size() == b.distances.size() &&
                          (a.distances.empty() ||
                           std::memcmp(a.distances.data(), b.distances.data(), a.distances.size() * sizeof(T)) == 0));
}

/// The k nearest of each row of `lists` (rows by index, with distances), as the grids order
/// them: by squared distance in search space, d2(i, j) for row i and entry j, ties by index
/// (the reported distances alone can tie where the squares do not).
template <class T, class F>
csr<T> nearest_rows(const csr<T>& lists, std::size_t k, F&& d2) {
    csr<T> out;
    out.offsets.assign(lists.rows() + 1, 0);
    std::vector<std::tuple<T, std::uint32_t, T>> row;
    for (std::size_t i = 0; i < lists.rows(); ++i) {
        row.clear();
        for (auto e = lists.offsets[i]; e < lists.offsets[i + 1]; ++e)
            row.emplace_back(d2(i, lists.indices[e]), lists.indices[e], lists.distances[e]);
        std::sort(row.begin(), row.end());
        if (row.size() > k) row.resize(k);
        for (const auto& [square, j, distance] : row) {
            out.indices.push_back(j);
            out.distances.push_back(distance);
        }
        out.offsets[i + 1] = out.indices.size();
    }
    return out;
}

/// Whether `half` holds, in each row i, exactly the entries of full row i past i (rows by index).
template <class T>
bool half_rows_match(const csr<T>& full, const csr<T>& half) {
    const std::size_t n = full.rows();
    if (half.rows() != n) return false;
    for (std::size_t i = 0; i < n; ++i) {
        std::vector<std::uint32_t> want;
        for (auto k = full.offsets[i]; k < full.offsets[i + 1]; ++k)
            if (full.indices[k] > i) want.push_back(full.indices[k]);
        if (half.offsets[i + 1] - half.offsets[i] != want.size() ||
            !std::equal(want.begin(), want.end(), half.indices.begin() + std::ptrdiff_t(half.offsets[i])))
            return false;
    }
    return true;
}

}  // namespace frnn::fuzz
