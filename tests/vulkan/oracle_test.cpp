// Every device query against the brute-force oracle, on the point sets of the CPU oracle tests:
// random, clustered, outliers, exact-radius ties on integer lattices, points on cell faces,
// sparse cells (hash collisions), duplicates; 2D and 3D; uniform, hashed and automatic grids.
#include <gtest/gtest.h>

#include "oracle/point_sets.hpp"
#include "oracle_check.hpp"
#include "vulkan_env.hpp"

namespace frnn::vulkan::test {
namespace {

using frnn::test::append_point;
using frnn::test::clustered_points;
using frnn::test::lattice_points;
using frnn::test::on_cell_boundaries;
using frnn::test::sparse_cells;
using frnn::test::uniform_points;
using frnn::test::with_duplicates;

class vulkan_oracle : public vulkan_test {
protected:
    template <int D>
    void check(const std::vector<float>& pts, float r, std::vector<grid_kind> kinds, const char* label,
               double cell_size = 0, std::vector<double> periodic = {}) {
        const auto queries = frnn::test::query_points<float, D>(pts, r, 60, periodic, 7);
        for (grid_kind kind : kinds) {
            grid_options o;
            o.kind = kind;
            o.cell_size = cell_size;
            o.periodic = periodic;
            SCOPED_TRACE(std::string(label) + " kind=" + frnn::test::kind_name(kind));
            check_device<D>(ctx(), pts, r, o, queries, cell_size == 0 ? depth::full : depth::basic);
            if (HasFailure()) return;
        }
    }
    const std::vector<grid_kind> all_kinds{grid_kind::automatic, grid_kind::uniform, grid_kind::hashed};
};

TEST_F(vulkan_oracle, uniform_random_3d) {
    check<3>(uniform_points<float, 3>(1500, 0, 10, 1), 1.0f, all_kinds, "uniform3d");
}

TEST_F(vulkan_oracle, small_cells_3d) {
    const auto pts = uniform_points<float, 3>(500, 0, 7, 2);
    check<3>(pts, 1.0f, {grid_kind::uniform, grid_kind::hashed}, "cell r/2", 0.5);
    check<3>(pts, 1.0f, {grid_kind::uniform, grid_kind::hashed}, "cell r/4", 0.25);
}

TEST_F(vulkan_oracle, clustered_3d) {
    check<3>(clustered_points<float, 3>(1500, 6, 1.0, 0, 30, 3), 0.7f, all_kinds, "clustered3d");
}

TEST_F(vulkan_oracle, outlier_3d) {
    auto pts = lattice_points<float, 3>(8, 1.0);
    append_point<float, 3>(pts, 1e7);
    append_point<float, 3>(pts, -3e9);
    check<3>(pts, 1.5f, {grid_kind::automatic, grid_kind::hashed}, "outlier3d");
}

TEST_F(vulkan_oracle, far_from_the_origin_3d) {
    // Coordinates near 1e5 (float spacing 0.008) with a small radius: cell coordinates count
    // from the lower corner, so rounding stays far below a cell.
    check<3>(uniform_points<float, 3>(800, 1e5, 1e5 + 12, 21), 0.6f, all_kinds, "far3d");
}

TEST_F(vulkan_oracle, lattice_ties_3d) {
    // Integer coordinates and radius: distances exactly r must be found.
    const auto pts = lattice_points<float, 3>(7, 1.0, -3);
    check<3>(pts, 1.0f, all_kinds, "lattice3d r=1");
    check<3>(pts, 2.0f, all_kinds, "lattice3d r=2");
}

TEST_F(vulkan_oracle, cell_boundaries_and_duplicates_3d) {
    check<3>(on_cell_boundaries<float, 3>(800, 1.0, 12, 4), 1.0f, all_kinds, "boundaries3d");
    check<3>(with_duplicates(uniform_points<float, 3>(300, 0, 5, 5), 3, 3), 0.8f, all_kinds, "duplicates3d");
}

TEST_F(vulkan_oracle, hash_collisions_3d) {
    // Far more cells than table slots: many slots hold several cells.
    check<3>(sparse_cells<float, 3>(500, 1.0, 40, 6), 1.0f, {grid_kind::hashed}, "sparse3d");
    check<3>(sparse_cells<float, 3>(500, 1.0, 100000, 7), 1.0f, {grid_kind::hashed}, "sparse3d far");
}

TEST_F(vulkan_oracle, uniform_random_2d) {
    check<2>(uniform_points<float, 2>(1500, 0, 30, 8), 1.0f, all_kinds, "uniform2d");
}

TEST_F(vulkan_oracle, clustered_and_outlier_2d) {
    auto pts = clustered_points<float, 2>(1200, 5, 1.0, 0, 50, 9);
    check<2>(pts, 0.6f, all_kinds, "clustered2d");
    append_point<float, 2>(pts, 5e6);
    check<2>(pts, 0.6f, {grid_kind::automatic, grid_kind::hashed}, "outlier2d");
}

TEST_F(vulkan_oracle, lattice_ties_and_collisions_2d) {
    check<2>(lattice_points<float, 2>(30, 1.0), 2.0f, all_kinds, "lattice2d r=2");
    check<2>(sparse_cells<float, 2>(400, 1.0, 60, 10), 1.0f, {grid_kind::hashed}, "sparse2d");
}

TEST_F(vulkan_oracle, periodic_3d) {
    // Points inside the box and some outside it (wrapped by the grid); boxes of many cells and
    // of only two or three cells per axis (every cell visited once).
    auto pts = uniform_points<float, 3>(1200, 0, 10, 12);
    for (std::size_t k = 0; k < 60; ++k) pts[k] += (k % 2 ? 10.0f : -20.0f);
    check<3>(pts, 1.0f, {grid_kind::uniform}, "periodic3d", 0, {10, 10, 10});
    check<3>(uniform_points<float, 3>(400, 0, 4, 13), 1.5f, {grid_kind::uniform}, "periodic3d small box", 0,
             {4, 3.5, 3});
    check<3>(lattice_points<float, 3>(6, 1.0), 2.0f, {grid_kind::uniform}, "periodic3d lattice", 0.5, {6, 6, 6});
}

TEST_F(vulkan_oracle, periodic_2d) {
    check<2>(uniform_points<float, 2>(1000, 0, 25, 14), 1.0f, {grid_kind::uniform}, "periodic2d", 0, {25, 25});
    check<2>(lattice_points<float, 2>(12, 1.0), 2.0f, {grid_kind::uniform}, "periodic2d lattice", 0, {12, 12});
}

TEST_F(vulkan_oracle, domain_smaller_than_the_points) {
    // Points outside an explicit domain share its border cells and stay exact.
    grid_options o;
    o.kind = grid_kind::uniform;
    o.domain_min = {2, 2, 2};
    o.domain_max = {5, 5, 5};
    const auto pts = uniform_points<float, 3>(800, 0, 8, 15);
    check_device<3>(ctx(), pts, 1.0f, o, frnn::test::query_points<float, 3>(pts, 1.0, 60, {}, 16));
}

TEST_F(vulkan_oracle, queries_from_other_points) {
    // Query points over the data's bounding box grown by 2r, plus one far point.
    const auto data3 = clustered_points<float, 3>(1000, 5, 1.0, 0, 20, 16);
    const auto q3 = frnn::test::query_points<float, 3>(data3, 1.0, 300, {}, 17);
    for (grid_kind kind : all_kinds) {
        grid_options o;
        o.kind = kind;
        SCOPED_TRACE("queries3d kind=" + frnn::test::kind_name(kind));
        check_device<3>(ctx(), data3, 1.0f, o, q3);
    }
    grid_options periodic;
    periodic.periodic = {20, 20, 20};
    const auto qp = frnn::test::query_points<float, 3>(data3, 1.0, 300, periodic.periodic, 18);
    check_device<3>(ctx(), data3, 1.0f, periodic, qp);
    const auto data2 = uniform_points<float, 2>(800, 0, 20, 19);
    check_device<2>(ctx(), data2, 1.5f, grid_options{}, frnn::test::query_points<float, 2>(data2, 1.5, 200, {}, 20));
    // Queries without distances as a fresh grid's first lists (their unused distance binding
    // once had no buffer behind it).
    grid<3> fresh(ctx());
    fresh.build(data3, 1.0f);
    list_options plain;
    plain.order = row_order::index;
    const auto rows = fresh.query(q3, plain);
    const auto counts = fresh.query_counts(q3);
    ASSERT_EQ(rows.rows(), counts.size());
    for (std::size_t q = 0; q < counts.size(); ++q) EXPECT_EQ(rows.row(q).size(), counts[q]) << "query " << q;
    // An empty grid answers empty rows; an empty query set, no rows.
    grid<3> empty(ctx());
    empty.build(std::span<const float>(), 1.0f);
    EXPECT_EQ(empty.query(q3).rows(), q3.size() / 3);
    EXPECT_EQ(empty.query(q3).size(), 0u);
    EXPECT_EQ(empty.query_counts(q3), std::vector<std::uint32_t>(q3.size() / 3, 0));
    EXPECT_EQ(empty.query_nearest(std::span<const float>(), 2).rows(), 0u);
}

TEST_F(vulkan_oracle, dense_cluster_long_rows) {
    // Every point is a neighbor of every other: rows of 1199 entries from 8 cells, sorted on
    // the device by index and by distance.
    grid_options o;
    o.cell_size = 0.25;
    const auto pts = uniform_points<float, 3>(1200, 0, 0.5, 22);
    check_device<3>(ctx(), pts, 1.0f, o, {}, depth::basic);
}

TEST_F(vulkan_oracle, empty_and_single_point) {
    for (grid_kind kind : all_kinds) {
        grid_options o;
        o.kind = kind;
        grid<3> g(ctx());
        g.build(std::span<const float>(), 1.0f, o);
        EXPECT_EQ(g.size(), 0u);
        EXPECT_TRUE(g.count_neighbors().empty());
        EXPECT_EQ(g.neighbor_lists().rows(), 0u);
        EXPECT_EQ(g.nearest(3).rows(), 0u);
        const std::vector<float> one{1.0f, 2.0f, 3.0f};
        g.build(one, 1.0f, o);
        EXPECT_EQ(g.count_neighbors(), std::vector<std::uint32_t>{0});
        list_options self;
        self.self = true;
        self.distances = true;
        const auto l = g.neighbor_lists(self);
        ASSERT_EQ(l.rows(), 1u);
        ASSERT_EQ(l.size(), 1u);
        EXPECT_EQ(l.indices[0], 0u);
        EXPECT_EQ(l.distances[0], 0.0f);
        EXPECT_EQ(g.neighbor_lists().size(), 0u);
    }
}

TEST_F(vulkan_oracle, multi_level_scan) {
    // An explicit domain far larger than the points: 1.4M cells, a three-level scan.
    const auto pts = uniform_points<float, 3>(600, 0, 6, 11);
    grid_options o;
    o.kind = grid_kind::uniform;
    o.domain_min = {-50, -50, -50};
    o.domain_max = {60, 60, 60};
    grid<3> g(ctx());
    g.build(pts, 1.0f, o);
    EXPECT_GT(g.slot_count(), 1024u * 1024u);
    check_device_grid<3>(g, pts, 1.0f, {}, {}, depth::basic);
}

}  // namespace
}  // namespace frnn::vulkan::test
