// Compares every query path of frnn::grid<T, D> with frnn::brute_force_lists.
//
// The reference rows come from the brute-force oracle (increasing neighbor index); the grid's
// answer is put in the same form (rows of the traversal order `none` are sorted first) and must
// match exactly: same pairs, same distances bit for bit (the oracle uses the grid's formula).
// Ties of "sorted by distance" are accepted when broken by index either on the squared
// distance or on the distance, since both are valid readings of "by distance, ties by index".
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "core/grid_access.hpp"
#include "frnn/brute_force.hpp"
#include "frnn/grid.hpp"

namespace frnn::test {

template <class T>
struct entry {
    std::uint32_t j;
    T dist;  ///< distance, as the oracle gives it
    T d2;    ///< squared distance, as callbacks give it
    /// Squared distance in search space (frnn/search_scale.hpp): rows by distance are sorted
    /// on it, since it keeps apart distances that the caller's units round together.
    T key;
};
template <class T>
using rows_t = std::vector<std::vector<entry<T>>>;

/// The oracle's lists as rows of entries (with the squared distances of `test`).
template <class T, int D>
rows_t<T> rows_of(const csr<T>& lists, std::span<const T> queries, std::span<const T> data,
                  const distance_test<T, D>& test) {
    rows_t<T> rows(lists.rows());
    for (std::size_t q = 0; q < lists.rows(); ++q) {
        for (std::uint64_t k = lists.offsets[q]; k < lists.offsets[q + 1]; ++k) {
            const std::uint32_t j = lists.indices[k];
            const T key = test.scaled_distance_squared(&queries[q * D], &data[j * D]);
            rows[q].push_back({j, lists.distances[k], test.distance_squared(key), key});
        }
    }
    return rows;
}

/// Oracle rows for `queries` against `data`, each sorted by neighbor index.
template <class T, int D>
rows_t<T> reference_rows(std::span<const T> queries, std::span<const T> data, T radius,
                         bool exclude_same, std::span<const double> periodic) {
    const csr<T> lists = brute_force_lists<T, D>(queries, data, radius, exclude_same, periodic);
    const distance_test<T, D> test(radius, search_scale<T>(radius, largest_magnitude<T>(data, periodic)), periodic);
    return rows_of<T, D>(lists, queries, data, test);
}

/// Radii of their own (empty spans: the grid's one radius): the data points' (grid::build
/// with radii) and the query points' (grid::query with radii), and the rule that pairs them.
template <class T>
struct radii_spec {
    std::span<const T> data, queries;
    radius_rule rule = radius_rule::gather;
    bool any() const { return !data.empty() || !queries.empty(); }
};

/// Oracle rows with radii of their own: query q against the data within query_radii[q] (or
/// max with data_radii[j], symmetric); scale of a grid of radius `grid_radius`.
template <class T, int D>
rows_t<T> reference_rows(std::span<const T> queries, std::span<const T> query_radii, std::span<const T> data,
                         std::span<const T> data_radii, radius_rule rule, T grid_radius, bool exclude_same,
                         std::span<const double> periodic) {
    const csr<T> lists = brute_force_lists<T, D>(queries, query_radii, data, data_radii, rule, grid_radius,
                                                 exclude_same, periodic);
    const distance_test<T, D> test(grid_radius, search_scale<T>(grid_radius, largest_magnitude<T>(data, periodic)),
                                   periodic);
    return rows_of<T, D>(lists, queries, data, test);
}

/// Oracle rows of the data set against itself, renumbered into `space` and filtered by `half`
/// and `self` as list_options define them.
template <class T>
rows_t<T> expected_self_rows(const rows_t<T>& ref, std::span<const std::uint32_t> perm,
                             std::span<const std::uint32_t> inverse, const list_options& o) {
    const bool sorted = o.space == index_space::sorted;
    rows_t<T> out(ref.size());
    for (std::size_t r = 0; r < ref.size(); ++r) {
        const std::size_t src = sorted ? perm[r] : r;
        auto& row = out[r];
        for (const auto& e : ref[src]) {
            const std::uint32_t j = sorted ? inverse[e.j] : e.j;
            if (o.half && j <= r) continue;
            row.push_back({j, e.dist, e.d2, e.key});
        }
        if (o.self) row.push_back({std::uint32_t(r), T(0), T(0), T(0)});
        std::sort(row.begin(), row.end(), [](auto& a, auto& b) { return a.j < b.j; });
    }
    return out;
}

/// Oracle rows of queries against the grid's points, neighbor indices in `space`.
template <class T>
rows_t<T> expected_query_rows(const rows_t<T>& ref, std::span<const std::uint32_t> inverse,
                              index_space space) {
    rows_t<T> out = ref;
    if (space == index_space::sorted) {
        for (auto& row : out) {
            for (auto& e : row) e.j = inverse[e.j];
            std::sort(row.begin(), row.end(), [](auto& a, auto& b) { return a.j < b.j; });
        }
    }
    return out;
}

/// The two accepted distance orders of an index-sorted row (ties by index).
template <class T>
std::vector<entry<T>> by_d2(std::vector<entry<T>> row) {
    std::stable_sort(row.begin(), row.end(), [](auto& a, auto& b) { return a.key < b.key; });
    return row;
}
template <class T>
std::vector<entry<T>> by_dist(std::vector<entry<T>> row) {
    std::stable_sort(row.begin(), row.end(), [](auto& a, auto& b) { return a.dist < b.dist; });
    return row;
}

template <class T>
std::string describe_row(std::span<const std::uint32_t> idx, std::span<const T> dist) {
    std::ostringstream s;
    s.precision(17);
    s << "[";
    for (std::size_t k = 0; k < idx.size() && k < 40; ++k) {
        s << (k ? " " : "") << idx[k];
        if (!dist.empty()) s << ":" << dist[k];
    }
    if (idx.size() > 40) s << " ...";
    s << "] (" << idx.size() << " entries)";
    return s.str();
}

/// True when `got` (indices, optional distances) equals `want` exactly.
template <class T>
bool row_equals(std::span<const std::uint32_t> idx, std::span<const T> dist,
                const std::vector<entry<T>>& want) {
    if (idx.size() != want.size()) return false;
    for (std::size_t k = 0; k < want.size(); ++k) {
        if (idx[k] != want[k].j) return false;
        if (!dist.empty() && dist[k] != want[k].dist) return false;
    }
    return true;
}

/// Empty when `got` matches `want` under `order`, else a description of the first bad row.
/// `k` > 0 truncates each expected distance-sorted row to k entries (nearest queries).
template <class T>
std::string compare_csr(const csr<T>& got, const rows_t<T>& want, bool distances,
                        row_order order, std::size_t k = 0) {
    const std::size_t n = want.size();
    if (got.offsets.size() != n + 1)
        return "offsets has " + std::to_string(got.offsets.size()) + " entries, expected " +
               std::to_string(n + 1);
    if (got.offsets[0] != 0) return "offsets[0] != 0";
    if (got.offsets[n] != got.indices.size()) return "offsets.back() != indices.size()";
    for (std::size_t r = 0; r < n; ++r)
        if (got.offsets[r] > got.offsets[r + 1])
            return "offsets decrease at row " + std::to_string(r);
    if (distances && got.distances.size() != got.indices.size())
        return "distances requested but has " + std::to_string(got.distances.size()) +
               " values for " + std::to_string(got.indices.size()) + " indices";
    if (!got.distances.empty() && got.distances.size() != got.indices.size())
        return "distances and indices differ in length";
    for (std::size_t r = 0; r < n; ++r) {
        std::vector<std::uint32_t> idx(got.row(r).begin(), got.row(r).end());
        std::vector<T> dist;
        if (distances) dist.assign(got.row_distances(r).begin(), got.row_distances(r).end());
        bool ok;
        if (k > 0 || order == row_order::distance) {
            auto a = by_d2(want[r]), b = by_dist(want[r]);
            if (k > 0 && a.size() > k) a.resize(k);
            if (k > 0 && b.size() > k) b.resize(k);
            ok = row_equals<T>(idx, dist, a) || row_equals<T>(idx, dist, b);
        } else {
            if (order == row_order::none) {
                std::vector<std::size_t> p(idx.size());
                std::iota(p.begin(), p.end(), 0);
                std::sort(p.begin(), p.end(), [&](auto x, auto y) { return idx[x] < idx[y]; });
                std::vector<std::uint32_t> i2;
                std::vector<T> d2;
                for (auto x : p) {
                    i2.push_back(idx[x]);
                    if (distances) d2.push_back(dist[x]);
                }
                idx = std::move(i2);
                dist = std::move(d2);
            }
            ok = row_equals<T>(idx, dist, want[r]);
        }
        if (!ok) {
            std::vector<std::uint32_t> wi;
            std::vector<T> wd;
            for (auto& e : want[r]) {
                wi.push_back(e.j);
                wd.push_back(e.dist);
            }
            return "row " + std::to_string(r) + ": got " +
                   describe_row<T>(got.row(r), distances ? std::span<const T>(got.row_distances(r))
                                                         : std::span<const T>()) +
                   ", oracle (by index" + (k ? ", k=" + std::to_string(k) : std::string()) +
                   ") " + describe_row<T>(wi, wd);
        }
    }
    return {};
}

/// Empty when callback results (j, d2) match the index-sorted row `want` (as a set, exactly).
template <class T>
std::string compare_callback(std::vector<std::pair<std::uint32_t, T>> got,
                             const std::vector<entry<T>>& want, const std::string& where) {
    std::sort(got.begin(), got.end());
    bool ok = got.size() == want.size();
    for (std::size_t k = 0; ok && k < want.size(); ++k)
        ok = got[k].first == want[k].j && got[k].second == want[k].d2;
    if (ok) return {};
    std::ostringstream s;
    s.precision(17);
    s << where << ": callback gave " << got.size() << " neighbors, oracle " << want.size()
      << "; got";
    for (std::size_t k = 0; k < got.size() && k < 30; ++k)
        s << " " << got[k].first << ":" << got[k].second;
    s << "; oracle";
    for (std::size_t k = 0; k < want.size() && k < 30; ++k) s << " " << want[k].j << ":" << want[k].d2;
    return s.str();
}

inline const char* name(row_order o) {
    return o == row_order::none ? "none" : o == row_order::index ? "index" : "distance";
}
inline const char* name(index_space s) { return s == index_space::original ? "original" : "sorted"; }

inline std::string describe(const list_options& o) {
    return std::string("half=") + (o.half ? "1" : "0") + " distances=" + (o.distances ? "1" : "0") +
           " self=" + (o.self ? "1" : "0") + " order=" + name(o.order) + " space=" + name(o.space);
}

/// Structure invariants: the permutation and its inverse, the sorted copy of the points.
template <class T, int D>
std::string check_structure(const grid<T, D>& g, std::span<const T> coords) {
    const std::size_t n = coords.size() / D;
    if (g.size() != n) return "size() " + std::to_string(g.size()) + " != " + std::to_string(n);
    const auto perm = g.sorted_to_original();
    const auto inv = g.original_to_sorted();
    if (perm.size() != n || inv.size() != n) return "permutation sizes differ from N";
    std::vector<char> seen(n, 0);
    for (std::size_t s = 0; s < n; ++s) {
        if (perm[s] >= n || seen[perm[s]]) return "sorted_to_original is not a permutation";
        seen[perm[s]] = 1;
        if (inv[perm[s]] != s) return "original_to_sorted is not the inverse at " + std::to_string(s);
        for (int a = 0; a < D; ++a)
            if (g.sorted_coord(s, a) != coords[std::size_t(perm[s]) * D + a])
                return "sorted_coord(" + std::to_string(s) + ") differs from the input point";
    }
    if (g.kind() == grid_kind::automatic) return "kind() reports automatic";
    // Each point lies in the cell of its run (whose end it finds), and the sort is stable:
    // within each cell the points keep the caller's order.
    for (std::uint32_t s = 0; s < n;) {
        const std::uint32_t e = frnn::detail::grid_access::cell_group_end(g, s);
        if (e <= s || e > n) return "cell_group_end(" + std::to_string(s) + ") = " + std::to_string(e);
        for (std::uint32_t j = s + 1; j < e; ++j) {
            if (frnn::detail::grid_access::cell_group_end(g, j) != e) return "sorted point " + std::to_string(j) + " lies outside its run's cell";
            if (perm[j] < perm[j - 1]) return "points of a cell out of the caller's order at " + std::to_string(j);
        }
        s = e;
    }
    return {};
}

/// How much of the option space check_grid covers. `full`: every combination of list options,
/// callbacks at every point. `basic`: every option value at least once, callbacks at every
/// fifth point (for the many grid configurations of one set, where the traversal differs but
/// the list options' logic does not).
enum class depth { basic, full };

/// The list options used at depth::basic: each value of each option appears at least once.
inline std::vector<list_options> basic_list_options() {
    auto make = [](bool half, bool dist, bool self, row_order order, index_space space) {
        list_options o;
        o.half = half;
        o.distances = dist;
        o.self = self;
        o.order = order;
        o.space = space;
        return o;
    };
    return {make(false, true, false, row_order::none, index_space::original),
            make(true, false, false, row_order::index, index_space::sorted),
            make(true, true, true, row_order::distance, index_space::original),
            make(false, true, true, row_order::index, index_space::sorted),
            make(false, false, false, row_order::distance, index_space::sorted),
            make(true, true, false, row_order::none, index_space::sorted)};
}

inline std::vector<list_options> all_list_options() {
    std::vector<list_options> out;
    for (int mask = 0; mask < 8; ++mask) {
        for (auto order : {row_order::none, row_order::index, row_order::distance}) {
            for (auto space : {index_space::original, index_space::sorted}) {
                list_options o;
                o.half = mask & 1;
                o.distances = mask & 2;
                o.self = mask & 4;
                o.order = order;
                o.space = space;
                out.push_back(o);
            }
        }
    }
    return out;
}

/// Checks every query path of `g` (built over `coords` with `radius` and periodic box
/// `periodic`) and every query from `queries` against the oracle. Failures are reported with
/// ADD_FAILURE, one per path at most.
template <class T, int D>
void check_grid(const grid<T, D>& g, std::span<const T> coords, T radius,
                std::span<const double> periodic, std::span<const T> queries,
                depth level = depth::full, radii_spec<T> radii = {}) {
    const std::size_t n = coords.size() / D;
    const bool full = level == depth::full;
    const std::size_t stride = full ? 1 : 5;
    auto fail = [](const std::string& path, const std::string& msg) {
        if (!msg.empty()) {
            ADD_FAILURE() << path << ": " << msg;
        }
        return !msg.empty();
    };
    if (fail("structure", check_structure<T, D>(g, coords))) return;
    const auto perm = g.sorted_to_original();
    const auto inv = g.original_to_sorted();
    const rows_t<T> ref = radii.data.empty()
                              ? reference_rows<T, D>(coords, coords, radius, true, periodic)
                              : reference_rows<T, D>(coords, radii.data, coords, radii.data, radii.rule, radius, true,
                                                     periodic);

    // for_each_neighbor: caller's indices, squared distances.
    for (std::size_t i = 0; i < n; i += stride) {
        std::vector<std::pair<std::uint32_t, T>> got;
        g.for_each_neighbor(i, [&](std::uint32_t j, T d2) { got.emplace_back(j, d2); });
        if (fail("for_each_neighbor", compare_callback<T>(got, ref[i], "point " + std::to_string(i))))
            break;
    }

    // count_neighbors in both index spaces.
    {
        const auto c = g.count_neighbors(index_space::original);
        const auto cs = g.count_neighbors(index_space::sorted);
        std::string msg;
        if (c.size() != n || cs.size() != n) msg = "wrong length";
        for (std::size_t i = 0; msg.empty() && i < n; ++i) {
            if (c[i] != ref[i].size())
                msg = "original point " + std::to_string(i) + ": " + std::to_string(c[i]) +
                      " != oracle " + std::to_string(ref[i].size());
            else if (cs[i] != ref[perm[i]].size())
                msg = "sorted point " + std::to_string(i) + ": " + std::to_string(cs[i]) +
                      " != oracle " + std::to_string(ref[perm[i]].size());
        }
        fail("count_neighbors", msg);
    }

    // reorder/restore_order, then for_each_neighbor_sorted on the reordered arrays.
    {
        std::vector<T> moved(coords.begin(), coords.end());
        g.reorder(std::span<T>(moved), D);
        std::vector<std::uint32_t> ids(n);
        std::iota(ids.begin(), ids.end(), 0u);
        g.reorder(std::span<std::uint32_t>(ids));
        std::string msg;
        for (std::size_t s = 0; msg.empty() && s < n; ++s) {
            if (ids[s] != perm[s]) msg = "reorder(ids)[" + std::to_string(s) + "] != sorted_to_original";
            for (int a = 0; msg.empty() && a < D; ++a)
                if (moved[s * D + a] != g.sorted_coord(s, a))
                    msg = "reorder(coords) differs from sorted_coord at " + std::to_string(s);
        }
        g.restore_order(std::span<std::uint32_t>(ids));
        for (std::size_t i = 0; msg.empty() && i < n; ++i)
            if (ids[i] != i) msg = "restore_order(reorder(ids)) != ids at " + std::to_string(i);
        fail("reorder/restore_order", msg);

        list_options so;
        so.space = index_space::sorted;
        const rows_t<T> sref = expected_self_rows<T>(ref, perm, inv, so);
        for (std::size_t s = 0; s < n; s += stride) {
            std::vector<std::pair<std::uint32_t, T>> got;
            g.for_each_neighbor_sorted(s, [&](std::uint32_t j, T d2) { got.emplace_back(j, d2); });
            if (fail("for_each_neighbor_sorted",
                     compare_callback<T>(got, sref[s], "sorted point " + std::to_string(s))))
                break;
        }
    }

    // neighbor_lists: every combination of the list options (or each value once).
    for (const list_options& o : full ? all_list_options() : basic_list_options()) {
        const auto want = expected_self_rows<T>(ref, perm, inv, o);
        fail("neighbor_lists(" + describe(o) + ")",
             compare_csr<T>(g.neighbor_lists(o), want, o.distances, o.order));
    }

    // Rows for the first m points only (of the chosen numbering): the first m rows of the
    // whole lists, the other points still neighbors. (At full depth: the traversal of smaller
    // cells does not change which rows are skipped.)
    for (list_options o : full ? basic_list_options() : std::vector<list_options>{}) {
        for (std::size_t m : {std::size_t(0), n / 3}) {
            o.rows = m;
            rows_t<T> want = expected_self_rows<T>(ref, perm, inv, o);
            want.resize(m);
            const std::string what = describe(o) + ", rows " + std::to_string(m);
            fail("neighbor_lists(" + what + ")", compare_csr<T>(g.neighbor_lists(o), want, o.distances, o.order));
            fail("nearest(4, " + what + ")", compare_csr<T>(g.nearest(4, o), want, o.distances, row_order::distance, 4));
        }
    }

    // nearest(k): at most k within r, by distance.
    for (std::size_t k : {std::size_t(1), std::size_t(4), std::size_t(100000)}) {
        if (!full && k != 4) continue;
        for (auto space : {index_space::original, index_space::sorted}) {
            for (bool dist : {false, true}) {
                if (!full && dist == (space == index_space::sorted)) continue;
                list_options o;
                o.space = space;
                o.distances = dist;
                const auto want = expected_self_rows<T>(ref, perm, inv, o);
                fail("nearest(" + std::to_string(k) + ", " + describe(o) + ")",
                     compare_csr<T>(g.nearest(k, o), want, dist, row_order::distance, k));
            }
        }
    }

    // for_each_neighbor_of at the data points (each finds itself) and at the queries.
    // With radii, the data points query with their own radius (or the grid's), the queries
    // with radii.queries.
    std::vector<T> all, all_radii;
    for (std::size_t i = 0; i < n; i += stride) {
        all.insert(all.end(), coords.begin() + i * D, coords.begin() + (i + 1) * D);
        all_radii.push_back(radii.data.empty() ? radius : radii.data[i]);
    }
    all.insert(all.end(), queries.begin(), queries.end());
    for (std::size_t q = 0; q < queries.size() / D; ++q) all_radii.push_back(radii.queries.empty() ? radius : radii.queries[q]);
    if (!radii.any()) all_radii.clear();
    const rows_t<T> qref = all_radii.empty() ? reference_rows<T, D>(all, coords, radius, false, periodic)
                                             : reference_rows<T, D>(all, all_radii, coords, radii.data, radii.rule,
                                                                    radius, false, periodic);
    for (std::size_t q = 0; q < qref.size(); ++q) {
        typename grid<T, D>::point x;
        for (int a = 0; a < D; ++a) x[a] = all[q * D + a];
        std::vector<std::pair<std::uint32_t, T>> got;
        if (all_radii.empty()) g.for_each_neighbor_of(x, [&](std::uint32_t j, T d2) { got.emplace_back(j, d2); });
        else g.for_each_neighbor_of(x, all_radii[q], [&](std::uint32_t j, T d2) { got.emplace_back(j, d2); });
        if (fail("for_each_neighbor_of", compare_callback<T>(got, qref[q], "query " + std::to_string(q))))
            break;
    }

    // query / query_counts / query_nearest from another point set.
    const std::size_t nq = all.size() / D;
    std::span<const T> qs(all);
    {
        const auto c = all_radii.empty() ? g.query_counts(qs) : g.query_counts(qs, all_radii);
        std::string msg = c.size() == nq ? "" : "wrong length";
        for (std::size_t q = 0; msg.empty() && q < nq; ++q)
            if (c[q] != qref[q].size())
                msg = "query " + std::to_string(q) + ": " + std::to_string(c[q]) + " != oracle " +
                      std::to_string(qref[q].size());
        fail("query_counts", msg);
    }
    for (auto space : {index_space::original, index_space::sorted}) {
        const auto want = expected_query_rows<T>(qref, inv, space);
        for (auto order : {row_order::none, row_order::index, row_order::distance}) {
            for (bool dist : {false, true}) {
                const bool orig = space == index_space::original;
                const bool basic_combo = (orig && order == row_order::none && dist) ||
                                         (orig && order == row_order::index && !dist) ||
                                         (!orig && order == row_order::distance && !dist);
                if (!full && !basic_combo) continue;
                list_options o;
                o.space = space;
                o.order = order;
                o.distances = dist;
                fail("query(" + describe(o) + ")",
                     compare_csr<T>(all_radii.empty() ? g.query(qs, o) : g.query(qs, all_radii, o), want, dist, order));
            }
        }
        for (std::size_t k : {std::size_t(1), std::size_t(5)}) {
            if (!full && k == 1) continue;
            list_options o;
            o.space = space;
            o.distances = true;
            fail("query_nearest(" + std::to_string(k) + ", " + describe(o) + ")",
                 compare_csr<T>(all_radii.empty() ? g.query_nearest(qs, k, o) : g.query_nearest(qs, all_radii, k, o),
                                want, true, row_order::distance, k));
        }
    }
}

/// Expects the outputs of one run to equal those of another bit for bit (offsets, indices,
/// distances); `what` names the run in failures.
template <class T>
void expect_identical(const std::vector<csr<T>>& got, const std::vector<csr<T>>& ref, const std::string& what) {
    ASSERT_EQ(got.size(), ref.size()) << what;
    for (std::size_t k = 0; k < ref.size(); ++k) {
        EXPECT_EQ(got[k].offsets, ref[k].offsets) << "output " << k << ", " << what;
        EXPECT_EQ(got[k].indices, ref[k].indices) << "output " << k << ", " << what;
        ASSERT_EQ(got[k].distances.size(), ref[k].distances.size()) << "output " << k << ", " << what;
        EXPECT_TRUE(ref[k].distances.empty() || std::memcmp(got[k].distances.data(), ref[k].distances.data(),
                                                            ref[k].distances.size() * sizeof(T)) == 0)
            << "output " << k << ", " << what;
    }
}

/// Builds a grid and runs check_grid; a throwing build is a failure. Unless the options ask
/// for a thread count, one thread: outputs at 2 and 4 threads are compared bit for bit with it
/// in threads_test.cpp, and at these sizes more threads only add waiting.
template <class T, int D>
void check_all(const std::vector<T>& coords, T radius, grid_options opt,
               const std::vector<T>& queries, depth level = depth::full) {
    if (opt.threads == 0) opt.threads = 1;
    grid<T, D> g;
    try {
        g.build(coords, radius, opt);
    } catch (const std::exception& e) {
        ADD_FAILURE() << "build threw: " << e.what();
        return;
    }
    // Periodic grids are always uniform (the box bounds them); otherwise the kind asked for.
    if (opt.kind != grid_kind::automatic && opt.periodic.empty()) {
        EXPECT_EQ(g.kind(), opt.kind);
    }
    check_grid<T, D>(g, coords, radius, opt.periodic, queries, level);
}

/// Full depth for the default cell size, basic for the smaller ones.
inline depth depth_for_cell(double fraction) { return fraction == 1.0 ? depth::full : depth::basic; }

inline std::string kind_name(grid_kind k) {
    return k == grid_kind::automatic ? "auto" : k == grid_kind::uniform ? "uniform" : "hashed";
}

/// check_all on every grid kind, with cells of r times each of `fractions` (1: the default).
template <class T, int D>
void check_kinds_and_cells(const std::vector<T>& pts, T r, const std::vector<T>& queries,
                           std::initializer_list<double> fractions, const grid_options& base = {}) {
    for (auto kind : {grid_kind::automatic, grid_kind::uniform, grid_kind::hashed}) {
        for (double f : fractions) {
            grid_options opt = base;
            opt.kind = kind;
            opt.cell_size = f == 1.0 ? 0.0 : double(r) * f;
            SCOPED_TRACE("kind=" + kind_name(kind) + " cell=r*" + std::to_string(f));
            check_all<T, D>(pts, r, opt, queries, depth_for_cell(f));
        }
    }
}

// The checks are instantiated once, in oracle_check.cpp, for the four point types: every
// test file uses them, and compiling them in each file took most of its build time.
#define FRNN_ORACLE_CHECKS(prefix, T, D)                                                              \
    prefix template std::string check_structure<T, D>(const grid<T, D>&, std::span<const T>);          \
    prefix template void check_grid<T, D>(const grid<T, D>&, std::span<const T>, T, std::span<const double>, \
                                          std::span<const T>, depth, radii_spec<T>);                   \
    prefix template void check_all<T, D>(const std::vector<T>&, T, grid_options, const std::vector<T>&, depth); \
    prefix template void check_kinds_and_cells<T, D>(const std::vector<T>&, T, const std::vector<T>&,   \
                                                     std::initializer_list<double>, const grid_options&);
FRNN_ORACLE_CHECKS(extern, float, 2)
FRNN_ORACLE_CHECKS(extern, float, 3)
FRNN_ORACLE_CHECKS(extern, double, 2)
FRNN_ORACLE_CHECKS(extern, double, 3)

}  // namespace frnn::test
