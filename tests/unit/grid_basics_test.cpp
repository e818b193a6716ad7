// Small hand-checked cases of the grid; the exhaustive comparisons live in tests/oracle.
#include <gtest/gtest.h>

#include <random>

#include "frnn/frnn.hpp"

namespace {

std::vector<double> random_points(std::size_t n, int dim, double side, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, side);
    std::vector<double> p(n * dim);
    for (auto& v : p) v = u(rng);
    return p;
}

TEST(grid_basics, two_points_at_exactly_the_radius_are_neighbors) {
    const std::vector<double> p{0, 0, 0, 2, 0, 0, 4.5, 0, 0};
    frnn::grid<double, 3> g(p, 2.0);
    const auto c = g.count_neighbors();
    EXPECT_EQ(c, (std::vector<std::uint32_t>{1, 1, 0}));
}

TEST(grid_basics, lists_match_brute_force_for_both_kinds) {
    const auto p = random_points(3000, 3, 10.0, 7);
    const auto ref = frnn::brute_force_lists<double, 3>(p, p, 0.8, true);
    for (auto kind : {frnn::grid_kind::uniform, frnn::grid_kind::hashed}) {
        for (double cell : {0.8, 0.4, 0.2}) {
            frnn::grid_options o;
            o.kind = kind;
            o.cell_size = cell;
            frnn::grid<double, 3> g(p, 0.8, o);
            frnn::list_options lo;
            lo.order = frnn::row_order::index;
            lo.distances = true;
            const auto got = g.neighbor_lists(lo);
            EXPECT_EQ(got.offsets, ref.offsets) << to_string(kind) << " cell " << cell;
            EXPECT_EQ(got.indices, ref.indices) << to_string(kind) << " cell " << cell;
            EXPECT_EQ(got.distances, ref.distances);
        }
    }
}

TEST(grid_basics, one_far_outlier_picks_the_hashed_grid) {
    auto p = random_points(1000, 3, 10.0, 3);
    p.insert(p.end(), {1e7, 1e7, 1e7});
    frnn::grid<double, 3> g(p, 1.0);
    EXPECT_EQ(g.kind(), frnn::grid_kind::hashed);
    const auto ref = frnn::brute_force_lists<double, 3>(p, p, 1.0, true);
    frnn::list_options lo;
    lo.order = frnn::row_order::index;
    EXPECT_EQ(g.neighbor_lists(lo).indices, ref.indices);
}

TEST(grid_basics, nan_is_rejected_with_its_index) {
    std::vector<float> p{0, 0, 1, 1, NAN, 2};
    try {
        frnn::grid<float, 2> g(p, 1.0f);
        FAIL() << "no exception";
    } catch (const frnn::error& e) {
        EXPECT_NE(std::string(e.what()).find("point 2"), std::string::npos) << e.what();
    }
}

}  // namespace

namespace {

// Reusing one csr across calls (as a time-step loop does) gives exactly what fresh calls give,
// when the lists grow, shrink, gain or lose distances, and on the periodic path.
TEST(grid_basics, neighbor_lists_into_a_reused_csr_equal_fresh_ones) {
    frnn::csr<double> reused;
    std::size_t step = 0;
    for (double radius : {0.5, 1.2, 0.3, 0.9}) {
        for (bool periodic : {false, true}) {
            const auto p = random_points(1500 + 300 * step, 3, 8.0, 40 + step);
            frnn::grid_options go;
            if (periodic) go.periodic = {8.0, 8.0, 8.0};
            const frnn::grid<double, 3> g(p, radius, go);
            frnn::list_options lo;
            lo.distances = step % 2 == 0;
            lo.space = step % 3 == 0 ? frnn::index_space::sorted : frnn::index_space::original;
            const auto fresh = g.neighbor_lists(lo);
            g.neighbor_lists(reused, lo);
            EXPECT_EQ(reused.offsets, fresh.offsets) << "step " << step;
            EXPECT_EQ(reused.indices, fresh.indices) << "step " << step;
            EXPECT_EQ(reused.distances, fresh.distances) << "step " << step;
            ++step;
        }
    }
}

}  // namespace
