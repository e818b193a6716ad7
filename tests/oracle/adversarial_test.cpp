// Adversarial point sets: exact distances r on integer lattices, one cell, duplicates, negative
// coordinates, points on cell faces, far outliers, empty and tiny inputs, hash-slot collisions.
#include <gtest/gtest.h>

#include "oracle/oracle_check.hpp"
#include "oracle/point_sets.hpp"

namespace frnn::test {
namespace {

constexpr grid_kind kinds[] = {grid_kind::automatic, grid_kind::uniform, grid_kind::hashed};

/// Every kind x cell size r, r/2, r/3, r/4 on one set.
template <class T, int D>
void every_grid(const std::vector<T>& pts, T r, const std::vector<T>& queries,
                const grid_options& base = {}) {
    for (auto kind : kinds) {
        for (double f : {1.0, 0.5, 1.0 / 3, 0.25}) {
            grid_options opt = base;
            opt.kind = kind;
            opt.cell_size = double(r) * f;
            SCOPED_TRACE("kind=" + kind_name(kind) + " cell=r*" + std::to_string(f));
            check_all<T, D>(pts, r, opt, queries, depth_for_cell(f));
        }
    }
}

// Integer radius on an integer lattice: distances are exact, so the pairs at exactly r decide
// whether the comparison is <= (required) or <.
template <class T, int D>
void lattice_case(int side, double step, double origin, double radius) {
    const auto pts = lattice_points<T, D>(side, step, origin);
    const auto queries = lattice_points<T, D>(side, step, origin + step / 2);
    SCOPED_TRACE("lattice side=" + std::to_string(side) + " step=" + std::to_string(step) +
                 " origin=" + std::to_string(origin) + " r=" + std::to_string(radius));
    every_grid<T, D>(pts, T(radius), queries);
}

TEST(OracleAdversarial, LatticeAtExactlyRadius2D) {
    lattice_case<double, 2>(16, 1, 0, 1);
    lattice_case<double, 2>(16, 1, -7, 2);
    lattice_case<float, 2>(16, 1, 3, 3);
    lattice_case<float, 2>(16, 0.5, -4, 1);  // step 0.5 and r = 2 steps: still exact
}

TEST(OracleAdversarial, LatticeAtExactlyRadius3D) {
    lattice_case<double, 3>(6, 1, 0, 1);
    lattice_case<double, 3>(6, 1, -3, 2);
    lattice_case<float, 3>(6, 1, 5, 2);
    lattice_case<float, 3>(6, 0.25, -1, 0.5);
}

// The lattice count is also physics: an interior point of a unit lattice with r = 2 has the
// lattice vectors of length <= 2 as neighbors.
TEST(OracleAdversarial, LatticeInteriorCountFromGeometry) {
    const int side = 9;
    const auto pts = lattice_points<double, 3>(side, 1.0, -4.0);
    int expected = -1;
    for (int x = -2; x <= 2; ++x)
        for (int y = -2; y <= 2; ++y)
            for (int z = -2; z <= 2; ++z) expected += x * x + y * y + z * z <= 4;
    for (auto kind : kinds) {
        grid_options opt;
        opt.kind = kind;
        grid<double, 3> g(pts, 2.0, opt);
        const auto c = g.count_neighbors();
        const std::size_t centre = (4 * side + 4) * side + 4;  // the point at the origin
        EXPECT_EQ(int(c[centre]), expected) << kind_name(kind);
    }
}

TEST(OracleAdversarial, AllPointsInOneCell) {
    every_grid<double, 3>(uniform_points<double, 3>(100, 5, 5.2, 71), 1.0,
                          uniform_points<double, 3>(30, 4, 6, 72));
    every_grid<float, 2>(uniform_points<float, 2>(100, -3, -2.9f, 73), 0.5f,
                         uniform_points<float, 2>(30, -4, -2, 74));
}

TEST(OracleAdversarial, Duplicates) {
    const auto base = uniform_points<double, 2>(120, 0, 6, 81);
    every_grid<double, 2>(with_duplicates(base, 2, 4), 0.7, query_points<double, 2>(base, 0.7, 40, {}, 82));
    const auto base3 = uniform_points<float, 3>(80, 0, 3, 83);
    every_grid<float, 3>(with_duplicates(base3, 3, 3), 0.6f, query_points<float, 3>(base3, 0.6, 40, {}, 84));
}

// All points identical: a bounding box of zero extent.
TEST(OracleAdversarial, AllPointsIdentical) {
    std::vector<double> one = {1.5, -2.5, 3.25};
    every_grid<double, 3>(with_duplicates(one, 3, 100), 0.5, {1.5, -2.5, 3.25, 1.5, -2.0, 3.25, 9, 9, 9});
    std::vector<float> zero = {0, 0};
    every_grid<float, 2>(with_duplicates(zero, 2, 100), 1.0f, {0, 0, 1, 0, 1, 1});
}

// Degenerate extents: all points on one line or one plane.
TEST(OracleAdversarial, FlatSets) {
    auto line = uniform_points<double, 3>(300, 0, 20, 85);
    for (std::size_t i = 0; i < line.size(); ++i)
        if (i % 3 != 0) line[i] = 4.0;  // y = z = 4
    every_grid<double, 3>(line, 0.5, query_points<double, 3>(line, 0.5, 40, {}, 86));
    auto plane = uniform_points<float, 3>(400, -5, 5, 87);
    for (std::size_t i = 2; i < plane.size(); i += 3) plane[i] = -1.0f;  // z = -1
    every_grid<float, 3>(plane, 1.0f, query_points<float, 3>(plane, 1.0, 40, {}, 88));
}

TEST(OracleAdversarial, NegativeCoordinates) {
    const auto pts = uniform_points<double, 3>(500, -1000, -993, 91);
    every_grid<double, 3>(pts, 1.2, query_points<double, 3>(pts, 1.2, 60, {}, 92));
    const auto p2 = clustered_points<float, 2>(400, 3, 0.8, -50, -40, 93);
    every_grid<float, 2>(p2, 0.4f, query_points<float, 2>(p2, 0.4, 60, {}, 94));
}

// Coordinates that are exact multiples of the cell size: points on faces, edges and corners,
// at distance exactly r from each other, with the bounding box starting on a cell face.
TEST(OracleAdversarial, PointsOnCellBoundaries) {
    for (double cell : {1.0, 0.5, 0.25}) {
        SCOPED_TRACE("lattice of cell " + std::to_string(cell));
        const auto pts = on_cell_boundaries<double, 2>(300, cell, 24, 101);
        every_grid<double, 2>(pts, 1.0, on_cell_boundaries<double, 2>(50, cell / 2, 30, 102));
        const auto p3 = on_cell_boundaries<float, 3>(200, cell, 10, 103);
        every_grid<float, 3>(p3, 1.0f, on_cell_boundaries<float, 3>(50, cell / 2, 12, 104));
    }
}

// A user domain whose faces are cell faces, with points exactly on domain_min and domain_max.
TEST(OracleAdversarial, PointsOnDomainFaces) {
    auto pts = on_cell_boundaries<double, 3>(400, 1.0, 10, 105);  // in [-5, 5]
    for (double v : {-5.0, 5.0, 0.0}) append_point<double, 3>(pts, v);
    grid_options base;
    base.domain_min = {-5, -5, -5};
    base.domain_max = {5, 5, 5};
    every_grid<double, 3>(pts, 1.0, {5, 5, 5, -5, -5, -5, 6, 5, 5, 5.5, 0, 0}, base);
    base.domain_min = {-3, -3, -3};  // points outside the domain on the low side
    base.domain_max = {2, 2, 2};
    every_grid<double, 3>(pts, 2.0, {5, 5, 5, -5, -5, -5, 6, 5, 5}, base);
}

// One point at 1e7: the automatic choice must be the hashed grid, and everything stays exact.
TEST(OracleAdversarial, FarOutlier) {
    auto pts = uniform_points<double, 3>(600, 0, 9, 111);
    append_point<double, 3>(pts, 1e7);
    const auto queries = query_points<double, 3>(uniform_points<double, 3>(50, 0, 10, 112), 1.0, 40, {}, 113);
    for (auto kind : {grid_kind::automatic, grid_kind::hashed}) {
        for (double cell : {1.0, 0.5, 0.25}) {
            grid_options opt;
            opt.kind = kind;
            opt.cell_size = cell;
            opt.threads = 1;
            SCOPED_TRACE("kind=" + kind_name(kind) + " cell=" + std::to_string(cell));
            grid<double, 3> g(pts, 1.0, opt);
            EXPECT_EQ(g.kind(), grid_kind::hashed);
            check_grid<double, 3>(g, pts, 1.0, {}, queries, depth_for_cell(cell));
        }
    }
    // Float, negative side, outlier first and a neighbor of the outlier.
    // (float spacing at 1e7 is 1, so the neighbor is one unit away on both axes).
    std::vector<float> p2;
    p2.reserve(2 * 802);
    append_point<float, 2>(p2, -1e7);
    append_point<float, 2>(p2, -1e7 + 1);
    const auto rest = uniform_points<float, 2>(800, -5, 5, 114);
    p2.insert(p2.end(), rest.begin(), rest.end());
    grid<float, 2> g2(p2, 1.5f);
    EXPECT_EQ(g2.kind(), grid_kind::hashed);
    check_grid<float, 2>(g2, p2, 1.5f, {}, std::vector<float>{-1e7f, -1e7f, 0, 0});
    // A uniform grid with a user domain puts the outlier in a border cell.
    grid_options opt;
    opt.kind = grid_kind::uniform;
    opt.domain_min = {0, 0, 0};
    opt.domain_max = {10, 10, 10};
    check_all<double, 3>(pts, 1.0, opt, queries);
}

// A few far outliers (at most one in 1024 points): the automatic choice is a uniform grid over
// the bulk, with the outliers folded into its border cells; outliers near each other must still
// find each other. More outliers than that: the hashed grid.
TEST(OracleAdversarial, FewFarOutliersFoldIntoAUniformGridOverTheBulk) {
    auto pts = uniform_points<double, 3>(6000, 0, 9, 121);
    for (double dx : {0.0, 0.5, 0.9}) pts.insert(pts.end(), {1e6 + dx, 1e6, 1e6});
    pts.insert(pts.end(), {-1e7, 5, 5, 5, 5, 3e5});  // 5 outliers in 6005 points
    const auto queries = query_points<double, 3>(uniform_points<double, 3>(50, 0, 10, 122), 1.0, 40, {}, 123);
    for (double cell : {1.0, 0.5}) {
        grid_options opt;
        opt.cell_size = cell;
        SCOPED_TRACE("cell=" + std::to_string(cell));
        grid<double, 3> g(pts, 1.0, opt);
        EXPECT_EQ(g.kind(), grid_kind::uniform);
        EXPECT_LT(g.slot_count(), 4 * 6005u);
        const std::vector<double> far{1e6 + 0.2, 1e6, 1e6, -1e7, 5, 5, 5, 5, 3e5 - 0.5};
        check_grid<double, 3>(g, pts, 1.0, {}, far, cell == 1.0 ? depth::full : depth::basic);
    }
    for (int k = 0; k < 20; ++k) pts.insert(pts.end(), {1e6 + 10.0 * k, -1e6, 0});
    grid<double, 3> g(pts, 1.0);
    EXPECT_EQ(g.kind(), grid_kind::hashed);
    check_grid<double, 3>(g, pts, 1.0, {}, queries, depth::basic);
}

TEST(OracleAdversarial, EmptyInput) {
    every_grid<double, 3>({}, 1.0, {0, 0, 0, 1, 2, 3});
    every_grid<float, 2>({}, 0.5f, {0, 0});
    grid<double, 2> g(std::vector<double>{}, 1.0);
    EXPECT_EQ(g.size(), 0u);
    EXPECT_EQ(g.neighbor_lists().offsets, buffer<std::uint64_t>{0});
    EXPECT_TRUE(g.count_neighbors().empty());
}

TEST(OracleAdversarial, SinglePoint) {
    every_grid<double, 3>({1, 2, 3}, 1.0, {1, 2, 3, 1.5, 2, 3, 2, 2, 3, 2.1, 2, 3});
    every_grid<float, 2>({-4, 7}, 2.0f, {-4, 7, -2, 7, -1.9f, 7});
}

TEST(OracleAdversarial, VerySmallN) {
    // Two points at exactly r, then 3 and 5 random points.
    every_grid<double, 2>({0, 0, 3, 4}, 5.0, {0, 0, 1.5, 2, 8, 4});
    every_grid<float, 3>({1, 1, 1, 1, 1, 4}, 3.0f, {1, 1, 2.5});
    for (std::size_t n : {3u, 5u, 7u}) {
        SCOPED_TRACE("n=" + std::to_string(n));
        const auto pts = uniform_points<double, 3>(n, 0, 2, 120 + n);
        every_grid<double, 3>(pts, 1.0, uniform_points<double, 3>(10, -1, 3, 130 + n));
    }
}

// Hashed grids with far more occupied or visited cells than table slots: stencil cells that share
// a slot must not give duplicates, probing must not lose cells.
TEST(OracleAdversarial, HashSlotCollisions) {
    // 20 points, each in its own r/4 cell: 729 stencil cells for a table sized from N = 20.
    {
        const auto pts = uniform_points<double, 3>(20, 0, 2, 141);
        every_grid<double, 3>(pts, 1.0, uniform_points<double, 3>(20, -1, 3, 142));
    }
    // Small clusters exactly 2^12 cells apart along x: a hash linear in the cell coordinates
    // modulo a power-of-two table sends them all to one slot.
    for (int stride_log2 : {8, 12, 16}) {
        SCOPED_TRACE("stride 2^" + std::to_string(stride_log2));
        const double stride = double(1 << stride_log2);
        std::vector<double> pts;
        for (int c = 0; c < 60; ++c)
            for (int k = 0; k < 5; ++k)
                for (double v : {c * stride + 0.1 + 0.15 * k, 0.5 + 0.1 * k, 0.3})
                    pts.push_back(v);
        for (double f : {1.0, 0.25}) {
            grid_options opt;
            opt.kind = grid_kind::hashed;
            opt.cell_size = f;
            SCOPED_TRACE("cell " + std::to_string(f));
            check_all<double, 3>(pts, 1.0, opt, {0.2, 0.6, 0.3, stride + 0.5, 0.5, 0.3});
        }
    }
    // Many sparse cells: birthday collisions in any table of O(N) slots.
    const auto sparse = sparse_cells<float, 2>(800, 0.5, 150, 143);
    every_grid<float, 2>(sparse, 0.5f, query_points<float, 2>(sparse, 0.5, 50, {}, 144));
}

}  // namespace
}  // namespace frnn::test
