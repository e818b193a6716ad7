// grid_geometry, the grid's one account of its cells (frnn/grid_geometry.hpp), against what the
// search does: the cells that cells_within names for a query hold exactly the points the query
// tests (its candidate runs), every neighbor within r lies in one of them, cell_of agrees with
// the cell that holds each point, and a cell's corners enclose its points. Uniform grids (with
// points outside their domain), hashed grids with far outliers and periodic boxes, 2D and 3D,
// float and double.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "core/grid_access.hpp"
#include "frnn/brute_force.hpp"
#include "frnn/grid.hpp"
#include "point_sets.hpp"

using frnn::detail::grid_access;  // the grid's traversal internals

namespace frnn::test {
namespace {

struct geometry_case {
    std::string name;
    grid_options options;
};

// Sorted points whose cell, wrapped into a periodic box, lies in `range` on every axis.
template <class T, int D>
std::set<std::uint32_t> points_in_range(const grid<T, D>& g, const cell_range& range) {
    const auto& geo = g.geometry();
    std::set<std::uint32_t> out;
    for (std::uint32_t s = 0; s < g.size(); ++s) {
        std::array<T, D> p;
        for (int a = 0; a < D; ++a) p[a] = grid_access::search_coord(g, s, a);
        const cell_index c = geo.cell_of(p);
        bool inside = true;
        for (int a = 0; a < D && inside; ++a) {
            if (!geo.periodic) {
                inside = c[a] >= range.first[a] && c[a] <= range.last[a];
                continue;
            }
            const std::int64_t n = geo.dims[a];
            inside = range.last[a] - range.first[a] + 1 >= n ||
                     ((c[a] - range.first[a]) % n + n) % n <= range.last[a] - range.first[a];
        }
        if (inside) out.insert(s);
    }
    return out;
}

template <class T, int D>
void check_geometry(const std::vector<T>& pts, T radius, const geometry_case& gc) {
    SCOPED_TRACE(gc.name);
    const grid<T, D> g(pts, radius, gc.options);
    const auto& geo = g.geometry();
    EXPECT_EQ(geo.kind, g.kind());
    EXPECT_EQ(geo.reach, g.reach());
    EXPECT_EQ(geo.slots, g.slot_count());

    // cell_of against the cell that holds each point, and the cell's corners around it.
    for (std::uint32_t s = 0; s < g.size(); ++s) {
        std::array<T, D> p;
        for (int a = 0; a < D; ++a) p[a] = grid_access::search_coord(g, s, a);
        const cell_index c = geo.cell_of(p);
        if (geo.kind == grid_kind::uniform) {
            const std::size_t slot = geo.slot_of_cell(c);
            ASSERT_LT(slot, geo.slots);
            ASSERT_GE(s, grid_access::cell_starts(g)[slot]) << "point " << s;
            ASSERT_LT(s, grid_access::cell_starts(g)[slot + 1]) << "point " << s;
        } else {
            ASSERT_TRUE(grid_access::hashed_point_in_cell(g, s, c)) << "point " << s;
        }
        const auto bounds = geo.cell_bounds(c);
        const bool in_domain = geo.kind == grid_kind::hashed || geo.periodic ||
                               [&] {
                                   for (int a = 0; a < D; ++a)
                                       if (c[a] == 0 || c[a] == geo.dims[a] - 1) return false;
                                   return true;
                               }();
        if (in_domain && !geo.periodic) {
            for (int a = 0; a < D; ++a) {
                const double x = double(g.sorted_coord(s, a)), slack = 1e-9 * geo.cell[a];
                EXPECT_GE(x, bounds[0][a] - slack) << "point " << s << " axis " << a;
                EXPECT_LE(x, bounds[1][a] + slack) << "point " << s << " axis " << a;
            }
        }
    }

    // For queries over the points' box grown by 2r (or in the periodic box) and one far away:
    // the cells named are the cells searched, and they hold every neighbor.
    const auto queries = query_points<T, D>(pts, double(radius), 60, gc.options.periodic, 9);
    for (std::size_t q = 0; q < queries.size() / D; ++q) {
        std::array<T, D> x;
        for (int a = 0; a < D; ++a) x[a] = queries[q * D + a];
        const std::array<T, D> y = grid_access::search_point(g, x, q);
        const cell_range range = geo.cells_within(y);
        detail::candidate_run runs[detail::max_runs];
        const std::size_t n = grid_access::candidate_runs(g, y, runs);
        std::set<std::uint32_t> searched;
        for (std::size_t k = 0; k < n; ++k)
            for (std::uint32_t j = runs[k].begin; j < runs[k].end; ++j) searched.insert(j);
        ASSERT_EQ(searched, (points_in_range<T, D>(g, range))) << "query " << q;
        g.for_each_neighbor_of(x, [&](std::uint32_t i, T) {
            const std::uint32_t s = g.original_to_sorted()[i];
            EXPECT_TRUE(searched.count(s)) << "query " << q << ": neighbor " << i << " in no cell named";
        });
    }
}

template <class T, int D>
void every_kind() {
    auto pts = uniform_points<T, D>(3000, 0, 20, 5);
    const T r = T(1.3);
    geometry_case uniform{"uniform", {}};
    uniform.options.kind = grid_kind::uniform;
    check_geometry<T, D>(pts, r, uniform);

    geometry_case small{"uniform, cells of r/3, domain inside the points", {}};
    small.options.kind = grid_kind::uniform;
    small.options.cell_size = double(r) / 3;
    small.options.domain_min.assign(D, 4.0);
    small.options.domain_max.assign(D, 15.0);
    check_geometry<T, D>(pts, r, small);

    geometry_case periodic{"periodic", {}};
    periodic.options.periodic.assign(D, 20.0);
    check_geometry<T, D>(pts, r, periodic);

    geometry_case tight{"periodic, 3 cells per axis", {}};
    tight.options.periodic.assign(D, 3 * 1.31);
    check_geometry<T, D>(uniform_points<T, D>(400, 0, 3 * 1.31, 6), r, tight);

    auto far = pts;
    for (int a = 0; a < D; ++a) far.push_back(T(a == 0 ? 1e7 : -3e6));
    for (int a = 0; a < D; ++a) far.push_back(T(1e7));
    geometry_case hashed{"hashed, far outliers", {}};
    hashed.options.kind = grid_kind::hashed;
    check_geometry<T, D>(far, r, hashed);
}

// A periodic box 10^20 radii long: floor(L / cell) is beyond every integer type's range; the
// box gets at most 2^30 cells per axis (then fewer, as a sparse box) and the answer is exact.
TEST(GridGeometry, HugePeriodicBoxHasBoundedCells) {
    auto pts = uniform_points<double, 3>(500, 0, 6, 8);
    grid_options o;
    o.periodic.assign(3, 1e20);
    const grid<double, 3> g(pts, 1.0, o);
    for (int a = 0; a < 3; ++a) {
        EXPECT_GE(g.geometry().dims[a], 1);
        EXPECT_LE(g.geometry().dims[a], std::int64_t(1) << 30);
    }
    EXPECT_LE(g.slot_count(), 4096u);
    const csr<double> expected = brute_force_lists<double, 3>(pts, pts, 1.0, true, o.periodic);
    const auto counts = g.count_neighbors();
    for (std::size_t i = 0; i < counts.size(); ++i)
        ASSERT_EQ(counts[i], expected.offsets[i + 1] - expected.offsets[i]) << "point " << i;
}

TEST(GridGeometry, FloatIn3D) { every_kind<float, 3>(); }
TEST(GridGeometry, FloatIn2D) { every_kind<float, 2>(); }
TEST(GridGeometry, DoubleIn3D) { every_kind<double, 3>(); }
TEST(GridGeometry, DoubleIn2D) { every_kind<double, 2>(); }

}  // namespace
}  // namespace frnn::test
