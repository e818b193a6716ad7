// The baselines find exactly the brute-force oracle's neighbors: |xi - xj| <= r (the real
// radius, pairs at exactly r included), j != i, on jittered and on exact integer lattices.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "frnn/bench/brute_baseline.hpp"
#include "frnn/bench/cell_list.hpp"
#include "frnn/bench/nanoflann_baseline.hpp"
#include "frnn/bench/workloads.hpp"
#include "frnn/error.hpp"

namespace fb = frnn::bench;

namespace {

// Rows as sorted index lists, so that lists in any order compare equal.
template <class T>
std::vector<std::vector<std::uint32_t>> sorted_rows(const frnn::csr<T>& lists) {
    std::vector<std::vector<std::uint32_t>> rows;
    for (std::size_t i = 0; i < lists.rows(); ++i) {
        auto r = lists.row(i);
        rows.emplace_back(r.begin(), r.end());
        std::sort(rows.back().begin(), rows.back().end());
    }
    return rows;
}

template <class T>
std::vector<std::uint32_t> row_sizes(const frnn::csr<T>& lists) {
    std::vector<std::uint32_t> s;
    for (std::size_t i = 0; i < lists.rows(); ++i) s.push_back(std::uint32_t(lists.row(i).size()));
    return s;
}

// Integer lattice: many pairs at exactly distance r = 2 (and sqrt(2), sqrt(3), ...).
template <class T, int D>
std::vector<T> exact_lattice(int side) {
    std::vector<T> p;
    const int nz = D == 3 ? side : 1;
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < side; ++j)
            for (int i = 0; i < side; ++i) {
                p.push_back(T(i));
                p.push_back(T(j));
                if (D == 3) p.push_back(T(k));
            }
    return p;
}

template <class T, int D>
void check_against_oracle(const std::vector<T>& points, T radius) {
    const std::span<const T> pts(points);
    const auto oracle = fb::brute_neighbor_lists<T, D>(pts, radius);
    const auto expected = sorted_rows(oracle);
    ASSERT_GT(oracle.size(), 0u);
    EXPECT_EQ((fb::brute_count_neighbors<T, D>(pts, radius)), row_sizes(oracle));

    const fb::nanoflann_baseline<T, D> tree(pts, radius);
    EXPECT_EQ(sorted_rows(tree.neighbor_lists(1)), expected);
    EXPECT_EQ(sorted_rows(tree.neighbor_lists(3)), expected);
    EXPECT_EQ(tree.neighbor_lists(1).indices, tree.neighbor_lists(2).indices);
    EXPECT_EQ(tree.count_neighbors(2), row_sizes(oracle));
    EXPECT_GT(tree.memory_bytes(), 0u);

    ASSERT_TRUE((fb::cell_list<T, D>::cells_needed(pts, radius)));
    const fb::cell_list<T, D> cells(pts, radius);
    EXPECT_EQ(sorted_rows(cells.neighbor_lists()), expected);
    EXPECT_EQ(cells.count_neighbors(), row_sizes(oracle));
}

}  // namespace

TEST(BenchBaselines, ExactLatticeIncludesPairsAtExactlyR3D) {
    check_against_oracle<float, 3>(exact_lattice<float, 3>(7), 2.0f);
    check_against_oracle<double, 3>(exact_lattice<double, 3>(7), 2.0);
    // An interior point has every lattice vector of length <= 2: 32 neighbors, 6 at exactly 2.
    const auto p = exact_lattice<double, 3>(7);
    const auto counts = fb::nanoflann_baseline<double, 3>(p, 2.0).count_neighbors(1);
    EXPECT_EQ(counts[(3 * 7 + 3) * 7 + 3], 32u);
}

TEST(BenchBaselines, ExactLatticeIncludesPairsAtExactlyR2D) {
    check_against_oracle<float, 2>(exact_lattice<float, 2>(15), 2.0f);
    check_against_oracle<double, 2>(exact_lattice<double, 2>(15), 1.0);
}

TEST(BenchBaselines, JitteredWorkloadsMatchOracle) {
    for (const char* id : {"W1", "W4"}) {
        const auto& w = fb::find_workload(id);
        if (w.dim == 3)
            check_against_oracle<float, 3>(fb::generate<float>(w, 729), float(w.radius));  // side 9
        else
            check_against_oracle<double, 2>(fb::generate<double>(w, 900), w.radius);  // side 30
    }
    const auto& w2 = fb::find_workload("W2");
    check_against_oracle<double, 3>(fb::generate<double>(w2, 1500), w2.radius);
}

TEST(BenchBaselines, DuplicatePointsAreNeighborsOfEachOther) {
    // Three copies of one point and one point far away: the copies see each other, not
    // themselves (nanoflann's self-match is skipped by index, not by distance).
    const std::vector<double> p{1, 1, 1, 1, 1, 1, 1, 1, 1, 9, 9, 9};
    check_against_oracle<double, 3>(p, 0.5);
    EXPECT_EQ((fb::nanoflann_baseline<double, 3>(p, 0.5).count_neighbors(1)),
              (std::vector<std::uint32_t>{2, 2, 2, 0}));
}

TEST(BenchBaselines, TextbookCellListRefusesHugeEmptySpace) {
    const auto& w5 = fb::find_workload("W5");
    const auto p = fb::generate<float>(w5, 65);  // side 4 and the outlier
    EXPECT_FALSE((fb::cell_list<float, 3>::cells_needed(p, 2.0f)));
    EXPECT_THROW((fb::cell_list<float, 3>(p, 2.0f)), frnn::error);
    // nanoflann has no such limit and still agrees with the oracle.
    const fb::nanoflann_baseline<float, 3> tree(p, 2.0f);
    const auto counts = tree.count_neighbors(2);
    EXPECT_EQ(counts.back(), 0u);
    EXPECT_EQ(std::accumulate(counts.begin(), counts.end(), 0ull),
              (fb::brute_neighbor_lists<float, 3>(p, 2.0f).size()));
}
