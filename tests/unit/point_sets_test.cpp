// point_sets (activation table) and verlet_lists, checked against brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
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

/// The lists of `got` (rows sorted) against brute force from `queries` into `data`: the same
/// row lengths and the same neighbors.
void expect_brute_force(const frnn::csr<float>& got, const std::vector<float>& queries, const std::vector<float>& data,
                        bool same_set, const char* what) {
    const auto want = frnn::brute_force_lists<float, 3>(queries, data, 0.7f, same_set);
    const auto sorted = sorted_rows(got);
    EXPECT_EQ(sorted.offsets, want.offsets) << what;
    EXPECT_EQ(sorted.indices, want.indices) << what;
    EXPECT_GT(want.indices.size(), 0u) << what << ": no pairs to compare";
}

TEST(point_sets, every_active_pair_matches_brute_force_and_inactive_pairs_are_empty) {
    const auto fluid = cloud(800, 6, 1), boundary = cloud(300, 6, 2);
    frnn::point_sets<float, 3> sets(0.7f);
    const auto f = sets.add(fluid), b = sets.add(boundary);
    sets.set_active(b, f, false);  // boundary particles need no fluid neighbors
    sets.find_neighbors();
    expect_brute_force(sets.neighbors(f, f), fluid, fluid, true, "fluid-fluid");
    expect_brute_force(sets.neighbors(f, b), fluid, boundary, false, "fluid-boundary");
    expect_brute_force(sets.neighbors(b, b), boundary, boundary, true, "boundary-boundary");
    EXPECT_EQ(sets.neighbors(b, f).size(), 0u);
    EXPECT_EQ(sets.neighbors(b, f).rows(), boundary.size() / 3);
    EXPECT_THROW(sets.neighbors(0, 5), frnn::error);
}

// The activation table: every pair active by default, set_active switches one direction only,
// a set added later keeps the table and is active both ways; an unknown set throws.
TEST(point_sets, is_active_reflects_set_active) {
    frnn::point_sets<float, 3> sets(0.7f);
    const auto a = sets.add(cloud(10, 2, 3)), b = sets.add(cloud(20, 2, 4));
    for (std::size_t i : {a, b})
        for (std::size_t j : {a, b}) EXPECT_TRUE(sets.is_active(i, j)) << i << " " << j;
    sets.set_active(b, a, false);
    EXPECT_FALSE(sets.is_active(b, a));
    EXPECT_TRUE(sets.is_active(a, b));
    EXPECT_TRUE(sets.is_active(b, b));
    const auto c = sets.add(cloud(5, 2, 5));
    EXPECT_FALSE(sets.is_active(b, a)) << "adding a set reset the table";
    for (std::size_t k : {a, b, c}) {
        EXPECT_TRUE(sets.is_active(c, k));
        EXPECT_TRUE(sets.is_active(k, c));
    }
    sets.set_active(b, a, true);
    EXPECT_TRUE(sets.is_active(b, a));
    EXPECT_THROW((void)sets.is_active(a, 3), frnn::error);
    EXPECT_THROW(sets.set_active(3, a, false), frnn::error);
}

// update() replaces a set's points (here fewer, elsewhere): points() counts the new set and the
// next find_neighbors() matches brute force on the new coordinates in every direction.
TEST(point_sets, update_moves_a_set_and_the_next_search_follows) {
    const auto fluid = cloud(800, 6, 6), boundary = cloud(300, 6, 7);
    frnn::point_sets<float, 3> sets(0.7f);
    const auto f = sets.add(fluid), b = sets.add(boundary);
    EXPECT_EQ(sets.size(), 2u);
    EXPECT_EQ(sets.points(f), 800u);
    EXPECT_EQ(sets.points(b), 300u);
    sets.find_neighbors();
    const auto moved = cloud(500, 5, 8);
    sets.update(f, moved);
    EXPECT_EQ(sets.points(f), 500u);
    EXPECT_EQ(sets.points(b), 300u);
    sets.find_neighbors();
    ASSERT_EQ(sets.neighbors(f, f).rows(), 500u);
    expect_brute_force(sets.neighbors(f, f), moved, moved, true, "moved-moved");
    expect_brute_force(sets.neighbors(f, b), moved, boundary, false, "moved-boundary");
    expect_brute_force(sets.neighbors(b, f), boundary, moved, false, "boundary-moved");
    expect_brute_force(sets.neighbors(b, b), boundary, boundary, true, "boundary-boundary");
    EXPECT_THROW(sets.update(2, moved), frnn::error);
    EXPECT_THROW((void)sets.points(2), frnn::error);
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

/// Rows of v at `at` against brute force (box: periodic lengths, or empty).
template <class T, int D>
void expect_exact(const frnn::verlet_lists<T, D>& v, const std::vector<T>& at, T r, const std::vector<double>& box,
                  const char* what) {
    const auto ref = frnn::brute_force_lists<T, D>(at, at, r, true, box);
    for (std::size_t i = 0; i < at.size() / D; ++i) {
        std::vector<std::uint32_t> got;
        v.for_each_neighbor(i, [&](std::uint32_t j, T) { got.push_back(j); });
        const auto want = ref.row(i);
        ASSERT_EQ(got, std::vector<std::uint32_t>(want.begin(), want.end())) << what << ", point " << i;
    }
}

// Found by the grid fuzzer: with r = 1e-295 (double) a move of 1e-294 squared to 0, so the
// lists were kept although a point had moved more than the half-skin, and a new pair was
// missed. Moves are now measured without squaring away their size.
TEST(verlet_lists, moves_far_beyond_the_skin_at_tiny_scales_rebuild) {
    const double r = 1e-295, skin = 1e-295;
    std::vector<double> p = {0, 0, 1e-294, 0, 0, 1e-294};  // no pair, no candidate
    frnn::verlet_lists<double, 2> v(r, skin);
    v.update(p);
    expect_exact(v, p, r, {}, "built");
    p[2] = 5e-296;  // moved 9.5e-295, more than skin / 2: now a pair
    EXPECT_TRUE(v.update(p));
    expect_exact(v, p, r, {}, "moved");
}

// A refused update (a NaN, a size that is not a multiple of D) throws and leaves the lists of
// the positions before it (a NaN or negative radius is refused at construction); a point that crosses a periodic face, or moves whole boxes, counts
// its move by the minimum image.
TEST(verlet_lists, refused_updates_keep_the_lists_and_periodic_moves_wrap) {
    std::vector<float> p = cloud(300, 6, 5);
    frnn::grid_options o;
    o.periodic = {6, 6, 6};
    frnn::verlet_lists<float, 3> v(0.9f, 0.3f, o);
    v.update(p);
    std::vector<float> bad = p;
    bad[7] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(v.update(bad), frnn::error);
    EXPECT_THROW(v.update(std::vector<float>(p.begin(), p.end() - 1)), frnn::error);
    EXPECT_THROW((frnn::verlet_lists<float, 3>(std::numeric_limits<float>::quiet_NaN(), 0.3f)), frnn::error);
    EXPECT_THROW((frnn::verlet_lists<float, 3>(-1.0f, 0.3f)), frnn::error);
    expect_exact(v, p, 0.9f, o.periodic, "after refused updates");
    for (std::size_t i = 0; i < p.size(); i += 3) p[i] += i % 2 ? 6.0f : -12.0f;  // whole boxes: no move
    EXPECT_FALSE(v.update(p));
    expect_exact(v, p, 0.9f, o.periodic, "whole boxes away");
}

}  // namespace
