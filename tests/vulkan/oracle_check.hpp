// Compares every query of frnn::vulkan::grid<D> with the brute-force oracle: neighbor counts,
// lists for every combination of half/self/space/order (with and without distances), and k
// nearest. Distances must match bit for bit (same float formula, precise arithmetic on the
// device, sqrt on the host).
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <string>
#include <vector>

#include "frnn/brute_force.hpp"
#include "frnn/vulkan.hpp"

namespace frnn::vulkan::test {

struct entry {
    float d2;
    std::uint32_t index;
    float distance;
};

template <int D>
class oracle_checker {
public:
    oracle_checker(context& ctx, const std::vector<float>& pts, float radius,
                   const grid_options& options, std::string label)
        : pts_(pts), radius_(radius), n_(pts.size() / D), g_(ctx), label_(std::move(label)),
          periodic_(options.periodic) {
        ref_ = brute_force_lists<float, D>(pts_, pts_, radius_, true, periodic_);
        g_.build(pts_, radius_, options);
        perm_ = g_.sorted_to_original();
    }

    grid<D>& device_grid() { return g_; }

    // sorted_to_original must be a permutation; builds inv_.
    void check_permutation() {
        ASSERT_EQ(perm_.size(), n_) << label_;
        inv_.assign(n_, 0xFFFFFFFFu);
        for (std::size_t s = 0; s < n_; ++s) {
            ASSERT_LT(perm_[s], n_) << label_;
            ASSERT_EQ(inv_[perm_[s]], 0xFFFFFFFFu) << label_ << ": sorted_to_original is not a permutation";
            inv_[perm_[s]] = std::uint32_t(s);
        }
    }

    // Expected row q (in the chosen space), sorted by (d2, index) or by index.
    std::vector<entry> expected_row(std::size_t q, const list_options& o, bool by_distance) const {
        const bool sorted = o.space == index_space::sorted;
        const std::size_t i = sorted ? perm_[q] : q;
        std::vector<entry> row;
        auto add = [&](std::uint32_t j, float dist) {
            const std::uint32_t out = sorted ? inv_[j] : j;
            if (o.half && out <= q && j != i) return;  // self stays with half, as on the CPU
            const float d2 = brute_distance_squared<float, D>(&pts_[i * D], &pts_[std::size_t(j) * D], periodic_);
            row.push_back({d2, out, dist});
        };
        if (o.self) add(std::uint32_t(i), 0.0f);
        for (std::uint64_t k = ref_.offsets[i]; k < ref_.offsets[i + 1]; ++k) add(ref_.indices[k], ref_.distances[k]);
        std::sort(row.begin(), row.end(), [&](const entry& a, const entry& b) {
            if (by_distance && a.d2 != b.d2) return a.d2 < b.d2;
            return a.index < b.index;
        });
        return row;
    }

    void check_counts() {
        check_permutation();
        if (::testing::Test::HasFatalFailure()) return;
        for (auto space : {index_space::original, index_space::sorted}) {
            const auto counts = g_.count_neighbors(space);
            ASSERT_EQ(counts.size(), n_) << label_;
            for (std::size_t q = 0; q < n_; ++q) {
                const std::size_t i = space == index_space::sorted ? perm_[q] : q;
                ASSERT_EQ(counts[q], ref_.offsets[i + 1] - ref_.offsets[i]) << label_ << " row " << q;
            }
        }
    }

    void check_lists(const list_options& o) {
        const csr<float> got = g_.neighbor_lists(o);
        const std::string what = label_ + " half=" + std::to_string(o.half) + " self=" + std::to_string(o.self) +
                                 " sorted=" + std::to_string(o.space == index_space::sorted) +
                                 " order=" + std::to_string(int(o.order)) + " distances=" + std::to_string(o.distances);
        ASSERT_EQ(got.rows(), n_) << what;
        ASSERT_EQ(got.distances.size(), o.distances ? got.indices.size() : 0u) << what;
        for (std::size_t q = 0; q < n_; ++q) {
            const auto want = expected_row(q, o, o.order == row_order::distance);
            std::vector<entry> have;
            for (std::uint64_t k = got.offsets[q]; k < got.offsets[q + 1]; ++k)
                have.push_back({0, got.indices[k], o.distances ? got.distances[k] : 0.0f});
            ASSERT_EQ(have.size(), want.size()) << what << " row " << q;
            if (o.order == row_order::none)  // traversal order: compare as sets
                std::sort(have.begin(), have.end(), [](auto& a, auto& b) { return a.index < b.index; });
            for (std::size_t k = 0; k < want.size(); ++k) {
                ASSERT_EQ(have[k].index, want[k].index) << what << " row " << q << " entry " << k;
                if (o.distances) {
                    ASSERT_EQ(have[k].distance, want[k].distance) << what << " row " << q << " entry " << k;
                }
            }
        }
    }

    void check_all_lists() {
        for (bool half : {false, true})
            for (bool self : {false, true})
                for (auto space : {index_space::original, index_space::sorted})
                    for (auto order : {row_order::none, row_order::index, row_order::distance}) {
                        list_options o;
                        o.half = half;
                        o.self = self;
                        o.space = space;
                        o.order = order;
                        o.distances = !(half && self);  // one combination without distances
                        check_lists(o);
                    }
    }

    void check_nearest(std::size_t k, const list_options& o) {
        const csr<float> got = g_.nearest(k, o);
        const std::string what = label_ + " nearest k=" + std::to_string(k);
        ASSERT_EQ(got.rows(), n_) << what;
        for (std::size_t q = 0; q < n_; ++q) {
            auto want = expected_row(q, o, true);
            if (want.size() > k) want.resize(k);
            ASSERT_EQ(got.offsets[q + 1] - got.offsets[q], want.size()) << what << " row " << q;
            for (std::size_t e = 0; e < want.size(); ++e) {
                ASSERT_EQ(got.indices[got.offsets[q] + e], want[e].index) << what << " row " << q;
                if (o.distances) {
                    ASSERT_EQ(got.distances[got.offsets[q] + e], want[e].distance) << what;
                }
            }
        }
    }

    // Queries from other points against brute_force_lists(queries, data).
    void check_queries(const std::vector<float>& queries) {
        check_permutation();
        if (::testing::Test::HasFatalFailure()) return;
        const std::size_t nq = queries.size() / D;
        const auto ref = brute_force_lists<float, D>(queries, pts_, radius_, false, periodic_);
        const auto counts = g_.query_counts(queries);
        ASSERT_EQ(counts.size(), nq) << label_;
        for (std::size_t q = 0; q < nq; ++q)
            ASSERT_EQ(counts[q], ref.offsets[q + 1] - ref.offsets[q]) << label_ << " query " << q;
        for (auto space : {index_space::original, index_space::sorted})
            for (auto order : {row_order::none, row_order::index, row_order::distance})
                for (std::size_t k : {std::size_t(0), std::size_t(3)}) {
                    list_options o;
                    o.space = space;
                    o.order = order;
                    o.distances = true;
                    o.half = true;  // ignored for queries, as on the CPU
                    const csr<float> got = k ? g_.query_nearest(queries, k, o) : g_.query(queries, o);
                    const std::string what = label_ + " queries sorted=" + std::to_string(space == index_space::sorted) +
                                             " order=" + std::to_string(int(order)) + " k=" + std::to_string(k);
                    ASSERT_EQ(got.rows(), nq) << what;
                    for (std::size_t q = 0; q < nq; ++q) {
                        std::vector<entry> want;
                        for (auto e = ref.offsets[q]; e < ref.offsets[q + 1]; ++e) {
                            const std::uint32_t j = ref.indices[e];
                            const float d2 = brute_distance_squared<float, D>(&queries[q * D], &pts_[std::size_t(j) * D], periodic_);
                            want.push_back({d2, space == index_space::sorted ? inv_[j] : j, ref.distances[e]});
                        }
                        const bool by_distance = k > 0 || order == row_order::distance;
                        std::sort(want.begin(), want.end(), [&](const entry& a, const entry& b) {
                            if (by_distance && a.d2 != b.d2) return a.d2 < b.d2;
                            return a.index < b.index;
                        });
                        if (k && want.size() > k) want.resize(k);
                        std::vector<entry> have;
                        for (auto e = got.offsets[q]; e < got.offsets[q + 1]; ++e)
                            have.push_back({0, got.indices[e], got.distances[e]});
                        if (!k && order == row_order::none)
                            std::sort(have.begin(), have.end(), [](auto& a, auto& b) { return a.index < b.index; });
                        ASSERT_EQ(have.size(), want.size()) << what << " query " << q;
                        for (std::size_t e = 0; e < want.size(); ++e) {
                            ASSERT_EQ(have[e].index, want[e].index) << what << " query " << q;
                            ASSERT_EQ(have[e].distance, want[e].distance) << what << " query " << q;
                        }
                    }
                }
    }

    void check_everything() {
        check_counts();
        if (::testing::Test::HasFatalFailure()) return;
        check_all_lists();
        list_options o;
        o.distances = true;
        check_nearest(1, o);
        check_nearest(5, o);
        o.self = true;
        o.space = index_space::sorted;
        check_nearest(3, o);
    }

private:
    std::vector<float> pts_;
    float radius_;
    std::size_t n_;
    grid<D> g_;
    std::string label_;
    csr<float> ref_;
    std::vector<std::uint32_t> perm_, inv_;
    std::vector<double> periodic_;
};

}  // namespace frnn::vulkan::test
