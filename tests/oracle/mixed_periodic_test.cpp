// Boxes periodic on some axes only (box length 0 on the open ones): channels and slabs, every
// combination of periodic axes, boxes of exactly 2r, far outliers on the open axes (few, and
// more than the bulk rule folds), points outside [0, L) on the periodic axes, exact lattice
// ties across the faces, and 1, 2 and 4 threads; against the brute-force oracle with the
// minimum image on the periodic axes only.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "frnn/error.hpp"
#include "oracle/independent_oracle.hpp"
#include "oracle/oracle_check.hpp"
#include "oracle/point_sets.hpp"

namespace frnn::test {
namespace {

/// Points uniform in [0, L) on the periodic axes and in [0, open_extent) on the open ones.
template <class T, int D>
std::vector<T> in_channel(std::size_t n, const std::vector<double>& box, double open_extent, std::uint64_t seed) {
    auto pts = uniform_points<T, D>(n, 0, 1, seed);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const double len = box[i % D] > 0 ? box[i % D] : open_extent;
        pts[i] = T(double(pts[i]) * len);
        if (box[i % D] > 0 && pts[i] >= T(len)) pts[i] = std::nextafter(T(len), T(0));
    }
    return pts;
}

std::string describe_box(const std::vector<double>& box) {
    std::string s = "box";
    for (double v : box) {
        s += ' ';
        s += v > 0 ? std::to_string(v) : "open";
    }
    return s;
}

/// The independent oracle once (unless every pair lies at r or beyond: long double cannot judge
/// ties, and a set that decides nothing proves nothing), then check_all for the kinds (a box with a periodic axis is
/// uniform whatever is asked) and cell sizes r, r/2, r/3 and r/4.
template <class T, int D>
void check_box(const std::vector<T>& pts, T r, const std::vector<double>& box, const std::vector<T>& queries,
               bool independent = true) {
    if (independent) expect_independent_pairs<T, D>(pts, r, box);
    for (double f : {1.0, 0.5, 1.0 / 3, 0.25}) {
        for (auto kind : {grid_kind::automatic, grid_kind::hashed}) {
            if (kind == grid_kind::hashed && f != 0.5) continue;
            grid_options opt;
            opt.kind = kind;
            opt.cell_size = double(r) * f;
            opt.periodic = box;
            SCOPED_TRACE(describe_box(box) + " kind=" + kind_name(kind) + " cell=r*" + std::to_string(f));
            check_all<T, D>(pts, r, opt, queries, depth_for_cell(f));
        }
    }
}

template <class T, int D>
void channel_case(const std::vector<double>& box_in_r, double open_in_r, T r, std::size_t n, std::uint64_t seed) {
    std::vector<double> box;
    for (int a = 0; a < D; ++a) box.push_back(box_in_r[a] * double(r));
    const auto pts = in_channel<T, D>(n, box, open_in_r * double(r), seed);
    check_box<T, D>(pts, r, box, query_points<T, D>(pts, double(r), 80, box, seed + 1));
}

// A channel periodic along x between walls in y (and z), and a slab periodic in x and y.
TEST(OracleMixedPeriodic, Channel2D) { channel_case<double, 2>({7.3, 0}, 5.5, 1.0, 400, 401); }
TEST(OracleMixedPeriodic, Channel3D) { channel_case<float, 3>({6.5, 0, 0}, 4.2, 0.5f, 500, 402); }
TEST(OracleMixedPeriodic, Slab3D) { channel_case<double, 3>({5.2, 4.7, 0}, 3.1, 1.0, 500, 403); }

// Every choice of periodic axes in 3D, each periodic axis exactly 2r long (the stencil wraps
// onto the same cells from both sides) or a little longer; the open axes span a few r.
TEST(OracleMixedPeriodic, EveryAxisChoice3D) {
    for (int mask = 1; mask < 7; ++mask) {
        for (double length : {2.0, 3.3}) {
            std::vector<double> box(3, 0.0);
            for (int a = 0; a < 3; ++a)
                if (mask >> a & 1) box[a] = length;
            SCOPED_TRACE("mask " + std::to_string(mask));
            channel_case<float, 3>(box, 4.5, 1.0f, 250, 410 + std::uint64_t(mask));
        }
    }
}

TEST(OracleMixedPeriodic, EveryAxisChoice2D) {
    for (const auto& box : std::vector<std::vector<double>>{{2, 0}, {0, 2}, {3.7, 0}, {0, 5.1}})
        channel_case<double, 2>(box, 6.0, 1.0, 300, 420);
}

// Far outliers on an open axis: the few that the bulk rule folds into the border cells (a
// W5-like set), and more than one in 1024 at growing distances, up to near the type's limit.
template <class T>
void outliers_case(std::size_t outliers, double far, std::uint64_t seed) {
    const std::vector<double> box = {8, 0, 8};
    auto pts = in_channel<T, 3>(3000, box, 6.0, seed);
    std::mt19937_64 rng(seed);
    for (std::size_t k = 0; k < outliers; ++k) {
        const double sign = k % 2 ? -1 : 1;
        const double y = sign * far / double(1 + k / 2);
        for (double v : {std::uniform_real_distribution<double>(0, 8)(rng), y, std::uniform_real_distribution<double>(0, 8)(rng)})
            pts.push_back(T(v));
    }
    // Two outliers within r of each other, far out: a pair the grid must still find.
    for (double dy : {0.0, 0.3}) {
        pts.push_back(T(1)), pts.push_back(T(far * 0.75 + dy)), pts.push_back(T(1));
    }
    auto queries = query_points<T, 3>(pts, 0.5, 60, box, seed + 1);
    for (double y : {far * 0.75, -far, 0.5 * far}) queries.push_back(T(1)), queries.push_back(T(y)), queries.push_back(T(1));
    grid_options opt;
    opt.periodic = box;
    SCOPED_TRACE(std::to_string(outliers) + " outliers to " + std::to_string(far));
    check_all<T, 3>(pts, T(0.5), opt, queries);
    // However far and many, the grid's cells stay within the sparse box's budget.
    const grid<T, 3> g(pts, T(0.5), opt);
    EXPECT_LE(double(g.slot_count()), std::max(8.0 * double(g.size()), 4096.0));
}

TEST(OracleMixedPeriodic, FewFarOutliersOnAnOpenAxis) {
    outliers_case<double>(2, 1e6, 430);
    outliers_case<float>(2, 1e30, 431);
}

TEST(OracleMixedPeriodic, ManyFarOutliersOnAnOpenAxis) {
    outliers_case<double>(40, 1e5, 432);
    outliers_case<double>(40, 1e300, 433);
    outliers_case<float>(40, 3e37, 434);
}

// Points given outside [0, L) on the periodic axes (the minimum-image kernels) and beyond the
// points' span on the open ones.
TEST(OracleMixedPeriodic, PointsOutsideThePeriodicBox) {
    const std::vector<double> box = {0, 6.0, 5.0};
    auto pts = in_channel<double, 3>(600, box, 7.0, 440);
    std::mt19937_64 rng(441);
    for (std::size_t i = 0; i < pts.size(); ++i)
        if (box[i % 3] > 0 && i % 7 == 0) pts[i] += box[i % 3] * double(int(rng() % 5) - 2);
    check_box<double, 3>(pts, 1.0, box, query_points<double, 3>(pts, 1.0, 80, box, 442));
}

// An integer lattice with integer radius: pairs at exactly r across the periodic faces, and
// at exactly r along the open axis, are found once each.
TEST(OracleMixedPeriodic, LatticeTiesAcrossTheFaces) {
    for (double length : {2.0, 5.0}) {
        const auto pts = lattice_points<double, 3>(int(length), 1.0);
        const std::vector<double> box = {length, 0, length};
        check_box<double, 3>(pts, 1.0, box, lattice_points<double, 3>(int(length), 1.0, 0.5), false);
    }
}

// domain_min/domain_max bound the open axes of a box with periodic axes (the periodic ones
// span their box): a domain wider than the points, and one the points overhang (they share the
// border cells); the cells start at the domain's lower bound on the open axis.
TEST(OracleMixedPeriodic, DomainBoundsTheOpenAxes) {
    const std::vector<double> box = {7.3, 0};
    const auto pts = in_channel<double, 2>(500, box, 5.5, 470);
    const auto queries = query_points<double, 2>(pts, 1.0, 80, box, 471);
    for (const auto& [lo, hi] : std::vector<std::pair<double, double>>{{-3, 9}, {1.5, 3.5}}) {
        for (double f : {1.0, 0.5}) {
            grid_options opt;
            opt.periodic = box;
            opt.cell_size = f;
            opt.domain_min = {-100, lo};  // the periodic axis ignores its bounds
            opt.domain_max = {100, hi};
            SCOPED_TRACE("open axis over [" + std::to_string(lo) + ", " + std::to_string(hi) + "], cell r*" + std::to_string(f));
            check_all<double, 2>(pts, 1.0, opt, queries, depth_for_cell(f));
            const grid<double, 2> g(pts, 1.0, opt);
            EXPECT_EQ(g.geometry().origin[1], lo);
            EXPECT_EQ(g.geometry().origin[0], 0.0);
            const auto& geo = g.geometry();  // cells over [lo, hi] on the open axis
            EXPECT_LE(geo.origin[1] + double(geo.dims[1] - 1) * geo.cell[1], hi);
            EXPECT_GE(geo.origin[1] + double(geo.dims[1]) * geo.cell[1], hi);
        }
    }
}

// layout_points lays the cells out as for that many points: a part of a sparse box's points
// gets the whole set's cells (without it, more of them: the sparse rule counts the points
// given), and its lists are still right.
TEST(OracleMixedPeriodic, LayoutPointsFixTheCells) {
    const std::vector<double> box = {60, 50};
    const auto all = in_channel<double, 2>(1000, box, 0, 472);
    const std::vector<double> part(all.begin(), all.begin() + 2 * 100);
    grid_options opt;
    opt.periodic = box;
    const grid<double, 2> whole(all, 0.5, opt);
    const grid<double, 2> alone(part, 0.5, opt);
    opt.layout_points = 1000;
    const grid<double, 2> laid_out(part, 0.5, opt);
    ASSERT_LT(whole.slot_count(), 120u * 100);  // the sparse rule took cells away
    EXPECT_NE(alone.geometry().dims, whole.geometry().dims);
    EXPECT_EQ(laid_out.geometry().dims, whole.geometry().dims);
    EXPECT_EQ(laid_out.geometry().cell, whole.geometry().cell);
    check_all<double, 2>(part, 0.5, opt, query_points<double, 2>(part, 0.5, 40, box, 473), depth::basic);
}

template <class T, int D>
std::vector<csr<T>> outputs_at(const std::vector<T>& pts, T r, grid_options opt, const std::vector<T>& queries) {
    const grid<T, D> g(pts, r, opt);
    std::vector<csr<T>> out;
    list_options lo;
    lo.distances = true;
    out.push_back(g.neighbor_lists(lo));
    out.push_back(g.query(queries, lo));
    lo.half = true;
    out.push_back(g.neighbor_lists(lo));
    lo.half = false;
    lo.order = row_order::distance;
    out.push_back(g.nearest(5, lo));
    return out;
}

// Bit-identical outputs at 1, 2 and 4 threads, and correct at 2 and 3 (slabs of layers swept
// at the same time, with the last axis periodic and open).
TEST(OracleMixedPeriodic, SameAtAnyThreadCount) {
    for (const auto& box : std::vector<std::vector<double>>{{9, 8, 0}, {0, 8, 13.5}}) {
        SCOPED_TRACE(describe_box(box));
        const auto pts = in_channel<float, 3>(12000, box, 10.0, 450);
        const auto queries = query_points<float, 3>(pts, 0.5, 2500, box, 451);
        grid_options opt;
        opt.periodic = box;
        opt.threads = 1;
        const auto ref = outputs_at<float, 3>(pts, 0.5f, opt, queries);
        for (int t : {2, 4}) {
            opt.threads = t;
            expect_identical(outputs_at<float, 3>(pts, 0.5f, opt, queries), ref, std::to_string(t) + " threads");
        }
        for (int t : {2, 3}) {
            opt.threads = t;
            const auto small = in_channel<float, 3>(700, box, 3.0, 452);
            check_all<float, 3>(small, 1.0f, opt, {}, depth::basic);
        }
    }
}

// The error for a short box names the periodic axis that is short, never an open one; a
// negative or non-finite length is refused; all-open boxes are the open grid.
TEST(OracleMixedPeriodic, BoxErrors) {
    const auto pts = in_channel<double, 3>(50, {4, 0, 4}, 3.0, 460);
    auto message = [&](std::vector<double> box, double r) {
        grid_options opt;
        opt.periodic = std::move(box);
        try {
            grid<double, 3>(pts, r, opt);
        } catch (const error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    const std::string short_axis = message({4, 0, 1.5}, 1.0);
    EXPECT_NE(short_axis.find("axis 2"), std::string::npos) << short_axis;
    EXPECT_NE(short_axis.find("smaller than twice the radius"), std::string::npos) << short_axis;
    EXPECT_EQ(message({4, 0, 4}, 1.0), "");  // the open axis is much shorter than 2r: no matter
    const std::string negative = message({4, -2, 4}, 1.0);
    EXPECT_NE(negative.find("axis 1"), std::string::npos) << negative;
    EXPECT_NE(message({4, NAN, 4}, 1.0).find("axis 1"), std::string::npos);
    EXPECT_NE(message({4, 0}, 1.0).find("3 lengths"), std::string::npos);

    grid_options opt;
    opt.periodic = {0, 0, 0};
    opt.kind = grid_kind::hashed;
    const grid<double, 3> open(pts, 1.0, opt);
    EXPECT_FALSE(open.periodic());
    EXPECT_EQ(open.kind(), grid_kind::hashed);
    check_all<double, 3>(pts, 1.0, opt, query_points<double, 3>(pts, 1.0, 40, {}, 461));
}

}  // namespace
}  // namespace frnn::test
