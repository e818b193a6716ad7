// Periodic boxes: minimum-image distances, each pair found once per direction, for boxes of
// exactly 2r, non-multiples of the cell size, anisotropic boxes, and exact lattice distances.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/grid_access.hpp"
#include "oracle/independent_oracle.hpp"
#include "oracle/oracle_check.hpp"
#include "oracle/point_sets.hpp"

using frnn::detail::grid_access;  // the grid's traversal internals

namespace frnn::test {
namespace {

/// Uniform points in the box [0, L) per axis (values that round up to L are moved just below).
template <class T, int D>
std::vector<T> in_box(std::size_t n, const std::vector<double>& box, std::uint64_t seed) {
    auto pts = uniform_points<T, D>(n, 0, 1, seed);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const T len = T(box[i % D]);
        pts[i] = T(double(pts[i]) * box[i % D]);
        if (pts[i] >= len) pts[i] = std::nextafter(len, T(0));
    }
    return pts;
}

template <class T, int D>
void periodic_case(const std::vector<double>& box_in_r, T r, std::size_t n, std::uint64_t seed) {
    std::vector<double> box;
    for (int a = 0; a < D; ++a) box.push_back(box_in_r[a] * double(r));
    const auto pts = in_box<T, D>(n, box, seed);
    const auto queries = query_points<T, D>(pts, r, 80, box, seed + 1);
    expect_independent_pairs<T, D>(pts, r, box);
    // Periodic grids are uniform whatever the kind asked for, so one kind per cell size.
    for (auto kind : {grid_kind::automatic, grid_kind::hashed}) {
        for (double f : {1.0, 0.5, 1.0 / 3, 0.25}) {
            if (kind == grid_kind::hashed && f != 0.5) continue;
            grid_options opt;
            opt.kind = kind;
            opt.cell_size = double(r) * f;
            opt.periodic = box;
            SCOPED_TRACE("kind=" + kind_name(kind) + " cell=r*" + std::to_string(f));
            check_all<T, D>(pts, r, opt, queries, depth_for_cell(f));
        }
    }
}

std::string box_name(const std::vector<double>& b) {
    std::string s;
    for (double v : b) s += std::to_string(v) + "r ";
    return s;
}

// Box exactly 2r: stencils wrap onto the same cells from both sides; each pair once.
TEST(OraclePeriodic, BoxExactlyTwoRadii2D) { periodic_case<double, 2>({2, 2}, 1.0, 300, 61); }
TEST(OraclePeriodic, BoxExactlyTwoRadii3D) { periodic_case<float, 3>({2, 2, 2}, 0.5f, 300, 62); }

TEST(OraclePeriodic, BoxesNotMultiplesOfTheCell) {
    const std::vector<std::vector<double>> boxes = {{2.5, 3.7, 2.0}, {3, 3, 3}, {7.3, 5.1, 10}};
    for (const auto& b : boxes) {
        SCOPED_TRACE("box " + box_name(b));
        periodic_case<double, 3>(b, 1.0, 250, 63);
        periodic_case<float, 2>(b, 0.75f, 200, 64);
    }
}

TEST(OraclePeriodic, LargeBoxSparse) { periodic_case<double, 2>({23.3, 17}, 0.5, 800, 65); }

// Integer lattices in integer boxes with integer radius: every distance is exact, pairs at
// exactly r across the faces (and at exactly L/2 when L == 2r) must be found once.
template <class T, int D>
void lattice_case(double box_len, double radius) {
    const int side = int(box_len);
    const auto pts = lattice_points<T, D>(side, 1.0);
    std::vector<double> box(D, box_len);
    const auto queries = lattice_points<T, D>(side, 1.0, 0.5);  // cell-centre points
    for (auto kind : {grid_kind::automatic, grid_kind::hashed}) {
        for (double f : {1.0, 0.5, 0.25}) {
            if (kind == grid_kind::hashed && f != 0.25) continue;
            grid_options opt;
            opt.kind = kind;
            opt.cell_size = radius * f;
            opt.periodic = box;
            SCOPED_TRACE("L=" + std::to_string(box_len) + " r=" + std::to_string(radius) +
                         " kind=" + kind_name(kind) + " cell=r*" + std::to_string(f));
            check_all<T, D>(pts, T(radius), opt, queries, depth_for_cell(f));
        }
    }
}

TEST(OraclePeriodic, LatticeExactDistances) {
    lattice_case<double, 2>(4, 2);  // L == 2r exactly
    lattice_case<double, 2>(5, 2);
    lattice_case<float, 2>(9, 3);
    lattice_case<float, 3>(4, 2);
    lattice_case<double, 3>(7, 2);
}

// Points outside [0, L) or on its faces: the grid wraps them into the box, as the oracle does,
// and finds exactly the oracle's pairs, also for `queries` (default: 30 near the points).
template <class T, int D>
void outside_box_case(std::vector<T> pts, const std::vector<double>& box, T r, const std::string& what,
                      std::vector<T> queries = {}) {
    SCOPED_TRACE(what);
    if (queries.empty()) queries = query_points<T, D>(pts, r, 30, box, 91);
    for (double f : {1.0, 0.25}) {
        grid_options opt;
        opt.periodic = box;
        opt.cell_size = double(r) * f;
        opt.threads = 1;
        const grid<T, D> g(pts, r, opt);
        check_grid<T, D>(g, pts, r, box, queries, depth_for_cell(f));
        // The grid searches a wrapped copy; sorted_coord still gives the points as given.
        for (std::size_t s = 0; s < g.size(); ++s)
            for (int a = 0; a < D; ++a)
                ASSERT_EQ(g.sorted_coord(s, a), pts[std::size_t(g.sorted_to_original()[s]) * D + std::size_t(a)]) << s;
    }
}

TEST(OraclePeriodic, PointsOnAndOutsideTheBox) {
    const std::vector<double> box = {10, 6};
    // Faces, the largest value below L, tiny negatives (v + L rounds to L), -0.
    std::vector<double> faces = {0, 0, 10, 6, std::nextafter(10.0, 0.0), std::nextafter(6.0, 0.0),
                                 -1e-17, -1e-17, -0.0, 3, 9.5, 5.5, 0.5, 0.5, 10, 0};
    outside_box_case<double, 2>(faces, box, 1.0, "faces, double");
    std::vector<float> ffaces(faces.begin(), faces.end());
    ffaces.push_back(std::nextafter(10.0f, 0.0f));
    ffaces.push_back(-1e-7f);
    outside_box_case<float, 2>(ffaces, box, 1.0f, "faces, float");
    // Whole images away: [-2L, 3L).
    auto far = uniform_points<double, 2>(300, -20, 30, 92);
    outside_box_case<double, 2>(far, box, 1.0, "images away");
    outside_box_case<double, 2>({0, 0, 1e300, 0.5}, box, 1.0, "1e300 boxes away");
}

// Float points many boxes out (up to far beyond 2^30 boxes, where float keeps no fraction of a
// box): each is wrapped into the box exactly, so the grid finds the oracle's pairs bit for bit.
// Before wrapping, cells came from a double wrap and distances from a float difference, and
// from about 1e6 boxes out pairs were missed. Queries lie as far out; one axis may be open.
template <int D>
void far_outside_case(double reach_in_boxes, float r, std::vector<double> box, std::uint64_t seed) {
    auto pts = in_box<float, D>(320, box, seed);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> boxes(-reach_in_boxes, reach_in_boxes);
    for (std::size_t i = 0; i < 20; ++i)  // 20 of 320 points far out on every periodic axis
        for (int a = 0; a < D; ++a)
            if (box[a] > 0) pts[i * D + a] = float(double(pts[i * D + a]) + std::round(boxes(rng)) * box[a]);
    auto queries = query_points<float, D>(pts, r, 60, box, seed + 1);
    for (std::size_t q = 0; q < 30; ++q)
        for (int a = 0; a < D; ++a)
            if (box[a] > 0) queries[q * D + a] = float(double(queries[q * D + a]) + std::round(boxes(rng)) * box[a]);
    outside_box_case<float, D>(pts, box, r, "up to " + std::to_string(reach_in_boxes) + " boxes out, r " + std::to_string(r),
                               queries);
}

TEST(OraclePeriodic, FloatPointsFarOutsideTheBox) {
    for (double k : {1e6, 4e6, 1e9, 1e20})
        for (float r : {0.01f, 0.1f, 1.0f}) far_outside_case<2>(k, r, {10, 10}, 131);
    far_outside_case<3>(4e6, 1.0f, {10, 0, 10}, 132);  // y open
    far_outside_case<3>(1e30, 0.5f, {10, 7, 5}, 133);
}

// Points inside a box large enough for stencils that never wrap, and queries whole boxes
// away: the sweep may skip the minimum image for inside points only, never for such queries.
TEST(OraclePeriodic, QueriesImagesAwayFromPointsInside) {
    const std::vector<double> box = {12, 9, 10};
    const auto pts = in_box<double, 3>(2000, box, 95);
    std::vector<double> queries;
    const auto near = query_points<double, 3>(pts, 1.0, 200, box, 96);
    for (std::size_t q = 0; q < near.size() / 3; ++q)
        for (int a = 0; a < 3; ++a) queries.push_back(near[3 * q + a] + double(int(q % 5) - 2) * box[a]);
    for (double f : {1.0, 0.5}) {
        grid_options opt;
        opt.periodic = box;
        opt.cell_size = f;
        grid<double, 3> g(pts, 1.0, opt);
        SCOPED_TRACE("cell " + std::to_string(f));
        check_grid<double, 3>(g, pts, 1.0, box, queries, depth_for_cell(f));
    }
}

// Dense cells at the box's corner, wrapping on every axis: more than 64 points per cell (the
// half-row pair count then sweeps them point by point), in a box that takes the runs' images.
TEST(OraclePeriodic, DenseCellsAcrossTheCorner) {
    const std::vector<double> box = {7, 8, 9};
    auto pts = in_box<double, 3>(100, box, 97);
    const auto corner = uniform_points<double, 3>(700, -0.2, 0.2, 98);  // about 90 per corner cell
    for (std::size_t i = 0; i < corner.size(); ++i) {
        const double len = box[i % 3];
        const double v = corner[i] < 0 ? corner[i] + len : corner[i];
        pts.push_back(v < len ? v : 0.0);
    }
    const auto queries = query_points<double, 3>(pts, 1.0, 30, box, 99);
    for (int threads : {1, 2}) {
        grid_options opt;
        opt.periodic = box;
        opt.threads = threads;
        grid<double, 3> g(pts, 1.0, opt);
        ASSERT_TRUE(grid_access::images_exact(g));
        SCOPED_TRACE("threads " + std::to_string(threads));
        check_grid<double, 3>(g, pts, 1.0, box, queries, depth::basic);
    }
}

// Every point's number of neighbors on a periodic lattice is the same (translation invariance):
// a physics check independent of the oracle.
TEST(OraclePeriodic, LatticeCountsAreUniform) {
    const auto pts = lattice_points<double, 3>(6, 1.0);
    grid_options opt;
    opt.periodic = {6, 6, 6};
    grid<double, 3> g(pts, 2.0, opt);
    const auto c = g.count_neighbors();
    // Minimum images of a 6-periodic lattice: offsets in [-3, 2]^3 with |v| <= 2, v != 0.
    std::uint32_t expected = 0;
    for (int x = -3; x <= 2; ++x)
        for (int y = -3; y <= 2; ++y)
            for (int z = -3; z <= 2; ++z) expected += (x * x + y * y + z * z <= 4) ? 1 : 0;
    expected -= 1;
    for (std::size_t i = 0; i < c.size(); ++i) ASSERT_EQ(c[i], expected) << "point " << i;
}

/// A lattice of `side` points per axis filling the box [0, side * step), each moved by a normal
/// jitter of `jitter` steps (some then lie outside the box).
template <int D>
std::vector<float> jittered_lattice(int side, float step, float jitter, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<float> move(0, jitter * step);
    auto pts = lattice_points<float, D>(side, step, step / 2);
    for (auto& v : pts) v += move(rng);
    return pts;
}

// A sweep of a slab of cell layers sends each candidate run's partner counts to one place, by
// where the run starts: no run of a forward half-stencil may span two layers. With 2 reach + 1
// cells on an axis the last row of one layer and the first row of the next are both in the
// half-stencil, and touching runs once merged across them.
template <int D>
void forward_runs_stay_in_one_layer(double cell) {
    const auto pts = jittered_lattice<D>(8, 0.125f, 0.1f, 71);
    grid_options opt;
    opt.periodic.assign(D, 1.0);
    opt.cell_size = cell;
    const grid<float, D> g(pts, 0.3f, opt);
    const auto& geo = g.geometry();
    for (int a = 0; a < D; ++a) ASSERT_EQ(geo.dims[a], 2 * geo.reach + 1) << "axis " << a;
    const auto starts = grid_access::cell_starts(g);
    const std::size_t per_layer = D == 3 ? std::size_t(geo.dims[0] * geo.dims[1]) : std::size_t(geo.dims[0]);
    auto layer_of = [&](std::uint32_t j) {
        std::size_t layer = 0;
        while (starts[(layer + 1) * per_layer] <= j) ++layer;
        return layer;
    };
    std::vector<detail::candidate_run> runs(512);
    std::vector<detail::run_image> images(512);
    for (std::int64_t z = 0; z < (D == 3 ? geo.dims[2] : 1); ++z)
        for (std::int64_t y = 0; y < geo.dims[1]; ++y)
            for (std::int64_t x = 0; x < geo.dims[0]; ++x) {
                const grid_access::cell c{x, y, z};
                for (auto* imgs : {(detail::run_image*)nullptr, images.data()}) {
                    const std::size_t n = grid_access::forward_runs(g, c, runs.data(), 1, imgs);
                    for (std::size_t k = 0; k < n; ++k)
                        EXPECT_EQ(layer_of(runs[k].begin), layer_of(runs[k].end - 1))
                            << "cell (" << x << ", " << y << ", " << z << "), run " << k << " [" << runs[k].begin << ", "
                            << runs[k].end << ")";
                }
            }
}

TEST(OraclePeriodic, ForwardRunsStayInOneLayer) {
    forward_runs_stay_in_one_layer<3>(0.3);   // radius 0.3 in a box of 1: reach 1, 3 cells per axis
    forward_runs_stay_in_one_layer<3>(0.19);  // reach 2, 5 cells per axis
    forward_runs_stay_in_one_layer<2>(0.3);
    forward_runs_stay_in_one_layer<2>(0.19);
}

// The same boxes at 2 threads, whose slabs are swept at the same time: counts and lists equal
// the brute-force oracle's on jittered lattices (a run spanning two layers made a slab add to
// the next slab's counts while that slab swept them, and pairs were lost).
TEST(OraclePeriodic, BoxesOfTwoReachPlusOneCellsAtTwoThreads) {
    for (std::uint64_t trial = 0; trial < 12; ++trial) {
        const auto pts3 = jittered_lattice<3>(8, 0.125f, 0.1f, 100 + trial);
        grid_options opt;
        opt.threads = 2;
        opt.periodic = {1, 1, 1};
        check_all<float, 3>(pts3, 0.3f, opt, {}, depth::basic);
        const auto pts2 = jittered_lattice<2>(24, 1.0f / 24, 0.1f, 200 + trial);
        opt.periodic = {1, 1};
        check_all<float, 2>(pts2, 0.3f, opt, {}, depth::basic);
    }
}

}  // namespace
}  // namespace frnn::test
