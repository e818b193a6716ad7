// point_sets (activation table) and verlet_lists, checked against brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "frnn/frnn.hpp"

namespace {

std::vector<float> cloud(std::size_t n, float side, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(0, side);
    std::vector<float> p(n * 3);
    for (auto& v : p) v = u(rng);
    return p;
}

frnn::csr<float> sorted_rows(frnn::csr<float> c) {
    for (std::size_t i = 0; i < c.rows(); ++i)
        std::sort(c.indices.begin() + c.offsets[i], c.indices.begin() + c.offsets[i + 1]);
    return c;
}

TEST(point_sets, every_active_pair_matches_brute_force_and_inactive_pairs_are_empty) {
    const auto fluid = cloud(800, 6, 1), boundary = cloud(300, 6, 2);
    frnn::point_sets<float, 3> sets(0.7f);
    const auto f = sets.add(fluid), b = sets.add(boundary);
    sets.set_active(b, f, false);  // boundary particles need no fluid neighbors
    sets.find_neighbors();
    EXPECT_EQ(sorted_rows(sets.neighbors(f, f)).indices,
              (frnn::brute_force_lists<float, 3>(fluid, fluid, 0.7f, true).indices));
    EXPECT_EQ(sorted_rows(sets.neighbors(f, b)).indices,
              (frnn::brute_force_lists<float, 3>(fluid, boundary, 0.7f, false).indices));
    EXPECT_EQ(sorted_rows(sets.neighbors(b, b)).offsets,
              (frnn::brute_force_lists<float, 3>(boundary, boundary, 0.7f, true).offsets));
    EXPECT_EQ(sets.neighbors(b, f).size(), 0u);
    EXPECT_EQ(sets.neighbors(b, f).rows(), boundary.size() / 3);
    EXPECT_THROW(sets.neighbors(0, 5), frnn::error);
}

TEST(verlet_lists, stay_exact_while_points_move_and_rebuild_only_when_needed) {
    auto p = cloud(1000, 8, 3);
    frnn::verlet_lists<float, 3> v(0.8f, 0.2f);
    EXPECT_TRUE(v.update(p));
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<float> step(-0.02f, 0.02f);
    std::size_t rebuilt = 0;
    for (int t = 0; t < 12; ++t) {
        for (auto& x : p) x += step(rng);
        rebuilt += v.update(p);
        const auto ref = frnn::brute_force_lists<float, 3>(p, p, 0.8f, true);
        for (std::size_t i = 0; i < p.size() / 3; ++i) {
            std::vector<std::uint32_t> got;
            v.for_each_neighbor(i, [&](std::uint32_t j, float) { got.push_back(j); });
            std::sort(got.begin(), got.end());
            const auto want = ref.row(i);
            ASSERT_EQ(got, std::vector<std::uint32_t>(want.begin(), want.end())) << "step " << t << " point " << i;
        }
    }
    // Each step moves a point at most 0.02*sqrt(3) ~ 0.035: the 0.1 half-skin lasts >= 2 steps.
    EXPECT_GE(rebuilt, 1u);
    EXPECT_LT(rebuilt, 12u);
    EXPECT_EQ(v.rebuilds(), rebuilt + 1);
}

}  // namespace
