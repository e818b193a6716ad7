// Small hand-checked cases of the grid; the exhaustive comparisons live in tests/oracle.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "core/grid_access.hpp"
#include "frnn/frnn.hpp"

using frnn::detail::grid_access;  // the grid's traversal internals

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

// 3000 points in a box of 125,000 cells of 0.2, nearly all in cells of their own: the hashed
// grid's table of 4096 slots holds several cells in many of its slots.
TEST(grid_basics, hashed_grid_counts_cells_not_slots_and_keeps_cells_apart_in_shared_slots) {
    const auto p = random_points(3000, 3, 10.0, 11);
    frnn::grid_options o;
    o.kind = frnn::grid_kind::hashed;
    o.cell_size = 0.2;
    frnn::grid<double, 3> g(p, 0.8, o);
    std::set<std::array<std::int64_t, 3>> cells;
    for (std::size_t i = 0; i < 3000; ++i) cells.insert(g.geometry().cell_of(std::array<double, 3>{p[3 * i], p[3 * i + 1], p[3 * i + 2]}));
    const std::size_t occupied = grid_access::cell_starts(g).size() - 1;  // one start per occupied slot
    ASSERT_LT(occupied + 500, cells.size());  // many slots are shared
    EXPECT_EQ(g.occupied_slots(), cells.size());
    const auto ref = frnn::brute_force_lists<double, 3>(p, p, 0.8, true);
    frnn::list_options lo;
    lo.order = frnn::row_order::index;
    EXPECT_EQ(g.neighbor_lists(lo).indices, ref.indices);
    lo.half = true;
    EXPECT_EQ(g.neighbor_lists(lo).size() * 2, ref.size());
    std::vector<std::uint32_t> sizes(3000);
    for (std::size_t i = 0; i < 3000; ++i) sizes[i] = std::uint32_t(ref.offsets[i + 1] - ref.offsets[i]);
    EXPECT_EQ(g.count_neighbors(), sizes);
}

// A hashed grid over clustered points: its table holds a start per occupied slot only, so the
// structure beyond the points and their permutation stays well under a byte per point (a start
// per slot took 4).
TEST(grid_basics, hashed_grid_of_clusters_keeps_starts_of_occupied_slots_only) {
    const std::size_t n = 1 << 16;
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> centre(0, 1e4);
    std::normal_distribution<double> spread(0, 0.5);
    std::vector<double> centres(8 * 3), p(n * 3);
    for (auto& v : centres) v = centre(rng);
    for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) p[i * 3 + a] = centres[(i % 8) * 3 + a] + spread(rng);
    frnn::grid_options o;
    o.kind = frnn::grid_kind::hashed;
    frnn::grid<double, 3> g(p, 1.0, o);
    ASSERT_GE(g.slot_count(), n);
    // One start per occupied slot (a few slots hold two cells).
    EXPECT_LE(grid_access::cell_starts(g).size() - 1, g.occupied_slots());
    EXPECT_GT(grid_access::cell_starts(g).size() - 1, g.occupied_slots() * 9 / 10);
    const std::size_t points = (n + frnn::detail::coordinate_padding) * 3 * sizeof(double) + n * sizeof(std::uint32_t);
    EXPECT_LT(g.memory_bytes() - points, n);
    // The same after a rebuild over other points: the table of every slot is built and freed again.
    std::reverse(p.begin(), p.end());
    g.rebuild(p);
    EXPECT_LT(g.memory_bytes() - points, n);
    const auto first = frnn::brute_force_lists<double, 3>(std::span(p).first(3), p, 1.0, true);
    EXPECT_EQ(g.count_neighbors()[0], first.size());
}

// Cells of r/4 on a lattice fill one cell in 8: 8 cells per point, twice the budget of cells
// of size r. The automatic kind must still pick the uniform grid (the hashed grid would look
// up 729 cells per point, nearly all empty), and stay exact.
TEST(grid_basics, small_cells_on_a_dense_lattice_keep_the_uniform_grid) {
    std::vector<double> p;
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> jitter(-0.1, 0.1);
    for (int z = 0; z < 20; ++z)
        for (int y = 0; y < 20; ++y)
            for (int x = 0; x < 20; ++x) p.insert(p.end(), {x + jitter(rng), y + jitter(rng), z + jitter(rng)});
    frnn::grid_options o;
    o.cell_size = 0.5;
    frnn::grid<double, 3> g(p, 2.0, o);
    EXPECT_EQ(g.kind(), frnn::grid_kind::uniform);
    EXPECT_GT(g.slot_count(), 4 * g.size());
    const auto ref = frnn::brute_force_lists<double, 3>(p, p, 2.0, true);
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

namespace {

bool is_inverse(std::span<const std::uint32_t> inv, std::span<const std::uint32_t> perm) {
    if (inv.size() != perm.size()) return false;
    for (std::size_t s = 0; s < perm.size(); ++s)
        if (inv[perm[s]] != s) return false;
    return true;
}

// original_to_sorted is computed on first use: it must follow rebuilds and copies, and its
// memory is only held once asked for.
TEST(grid_basics, original_to_sorted_is_computed_on_first_use_and_follows_rebuilds) {
    const std::size_t n = 5000;
    auto p = random_points(n, 3, 10.0, 3);
    frnn::grid<double, 3> g(p, 0.7);
    const std::size_t before = g.memory_bytes();
    EXPECT_TRUE(is_inverse(g.original_to_sorted(), g.sorted_to_original()));
    EXPECT_EQ(g.memory_bytes(), before + n * sizeof(std::uint32_t));

    std::reverse(p.begin(), p.end());  // other points, so another permutation
    g.rebuild(p);
    EXPECT_TRUE(is_inverse(g.original_to_sorted(), g.sorted_to_original()));
    const frnn::grid<double, 3> copy = g;
    EXPECT_TRUE(is_inverse(copy.original_to_sorted(), copy.sorted_to_original()));
    // for_each_neighbor(i) goes through the map: its neighbors are i's true neighbors.
    std::size_t found = 0;
    g.for_each_neighbor(17, [&](std::uint32_t j, double d2) {
        double e2 = 0;
        for (int a = 0; a < 3; ++a) e2 += (p[j * 3 + a] - p[17 * 3 + a]) * (p[j * 3 + a] - p[17 * 3 + a]);
        EXPECT_EQ(d2, e2);
        ++found;
    });
    EXPECT_EQ(found, g.count_neighbors()[17]);
}

// Input already in cell order takes the build's direct scatter: the sort must still be stable
// (identity permutation) for any thread count, and equal the sort of shuffled input.
TEST(grid_basics, input_in_cell_order_sorts_stably_for_any_thread_count) {
    auto p = random_points(40000, 3, 30.0, 9);
    const frnn::grid<double, 3> shuffled(p, 1.0);
    shuffled.reorder(std::span<double>(p), 3);
    for (int threads : {1, 2, 3}) {
        frnn::grid_options o;
        o.threads = threads;
        const frnn::grid<double, 3> g(p, 1.0, o);
        const auto perm = g.sorted_to_original();
        std::size_t moved = 0;
        for (std::size_t s = 0; s < perm.size(); ++s) moved += perm[s] != s;
        EXPECT_EQ(moved, 0u) << threads << " threads";
        for (std::size_t s = 0; s < perm.size(); ++s)
            for (int a = 0; a < 3; ++a)
                ASSERT_EQ(g.sorted_coord(s, a), shuffled.sorted_coord(s, a)) << s;
    }
}

// Input in random order goes through the scatter's records, whose memory a grid keeps for its
// next build (lazily freed in between): rebuilds over other, more and fewer points, and of a
// copy, must equal first builds over the same points.
TEST(grid_basics, rebuilds_of_input_in_random_order_equal_first_builds) {
    auto expect_same = [](const frnn::grid<double, 3>& g, const std::vector<double>& p, const char* what) {
        const frnn::grid<double, 3> fresh(p, 1.0);
        ASSERT_EQ(g.size(), fresh.size()) << what;
        for (std::size_t s = 0; s < g.size(); ++s) {
            ASSERT_EQ(g.sorted_to_original()[s], fresh.sorted_to_original()[s]) << what << ", point " << s;
            for (int a = 0; a < 3; ++a) ASSERT_EQ(g.sorted_coord(s, a), fresh.sorted_coord(s, a)) << what << ", point " << s;
        }
    };
    // 150,000 points of 32-byte records: 4.8 MB, whole huge pages included.
    const auto first = random_points(150000, 3, 53.0, 21), second = random_points(150000, 3, 53.0, 22);
    const auto more = random_points(200000, 3, 58.0, 23), fewer = random_points(1000, 3, 10.0, 24);
    frnn::grid<double, 3> g(first, 1.0);
    expect_same(g, first, "first build");
    g.rebuild(second);
    expect_same(g, second, "rebuild");
    g.rebuild(first);
    expect_same(g, first, "second rebuild");
    frnn::grid<double, 3> copy = g;
    copy.rebuild(second);
    expect_same(copy, second, "rebuild of a copy");
    g.rebuild(more);
    expect_same(g, more, "rebuild over more points");
    g.rebuild(fewer);
    expect_same(g, fewer, "rebuild over fewer points");
    g.rebuild(second);
    expect_same(g, second, "rebuild after fewer points");
}

}  // namespace
