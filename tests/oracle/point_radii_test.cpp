// A radius per point: gather (|x_i - x_j| <= r_i) and symmetric (<= max(r_i, r_j)) against the
// brute-force oracle on every query path (lists, counts, callbacks, k nearest, queries with
// radii of their own), uniform and hashed grids, cells of the largest radius and smaller,
// periodic and mixed boxes, wide spreads of radii, exact ties, extreme scales, any thread
// count; and the errors for bad radii.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <string>

#include "frnn/error.hpp"
#include "oracle/oracle_check.hpp"
#include "oracle/point_sets.hpp"

namespace frnn::test {
namespace {

/// n radii uniform in [lo, hi] (seeded).
template <class T>
std::vector<T> radii_between(std::size_t n, double lo, double hi, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<T> out(n);
    for (auto& r : out) r = T(std::uniform_real_distribution<double>(lo, hi)(rng));
    return out;
}

template <class T>
T largest(const std::vector<T>& v) {
    T m = 0;
    for (T x : v) m = std::max(m, x);
    return m;
}

/// Builds with radii and runs check_grid (queries with radii of their own).
template <class T, int D>
void check_radii(const std::vector<T>& pts, const std::vector<T>& radii, grid_options opt, const std::vector<T>& queries,
                 const std::vector<T>& query_radii, depth level) {
    if (opt.threads == 0) opt.threads = 1;
    grid<T, D> g;
    try {
        g.build(pts, radii, opt);
    } catch (const std::exception& e) {
        ADD_FAILURE() << "build threw: " << e.what();
        return;
    }
    EXPECT_TRUE(g.has_point_radii());
    EXPECT_EQ(g.radius(), pts.empty() ? T(1) : largest(radii));
    radii_spec<T> spec;
    spec.data = radii;
    spec.queries = query_radii;
    spec.rule = opt.rule;
    check_grid<T, D>(g, pts, g.radius(), opt.periodic, queries, level, spec);
}

/// Every rule, kind and cell size (the largest radius, half and a quarter of it).
template <class T, int D>
void radii_case(const std::vector<T>& pts, const std::vector<T>& radii, const std::vector<T>& queries,
                const grid_options& base = {}) {
    const T big = largest(radii);
    const auto query_radii = radii_between<T>(queries.size() / D, double(big) / 20, double(big), 7);
    for (auto rule : {radius_rule::gather, radius_rule::symmetric}) {
        for (auto kind : {grid_kind::automatic, grid_kind::hashed}) {
            for (double f : {1.0, 0.5, 0.25}) {
                grid_options opt = base;
                opt.rule = rule;
                opt.kind = kind;
                opt.cell_size = double(big) * f;
                SCOPED_TRACE(std::string(to_string(rule)) + " kind=" + kind_name(kind) + " cell=R*" + std::to_string(f));
                check_radii<T, D>(pts, radii, opt, queries, query_radii, depth_for_cell(f));
            }
        }
    }
}

TEST(OraclePointRadii, UniformSpread4x3D) {
    const auto pts = uniform_points<double, 3>(700, 0, 8, 501);
    radii_case<double, 3>(pts, radii_between<double>(700, 0.25, 1.0, 502), query_points<double, 3>(pts, 1.0, 60, {}, 503));
}

TEST(OraclePointRadii, ClusteredSpread10x2D) {
    const auto pts = clustered_points<float, 2>(800, 6, 1.0, -10, 10, 504);
    radii_case<float, 2>(pts, radii_between<float>(800, 0.08, 0.8, 505), query_points<float, 2>(pts, 0.8, 60, {}, 506));
}

TEST(OraclePointRadii, PeriodicAndMixedBoxes) {
    for (const std::vector<double>& box : {std::vector<double>{6, 5, 7}, std::vector<double>{6, 0, 7}}) {
        grid_options opt;
        opt.periodic = box;
        auto pts = uniform_points<float, 3>(600, 0, 1, 507);
        for (std::size_t i = 0; i < pts.size(); ++i)
            pts[i] = box[i % 3] > 0 ? std::min(float(pts[i] * box[i % 3]), std::nextafter(float(box[i % 3]), 0.0f))
                                    : pts[i] * 4.0f;
        SCOPED_TRACE(box[1] > 0 ? "periodic" : "mixed");
        radii_case<float, 3>(pts, radii_between<float>(600, 0.3, 1.5, 508), query_points<float, 3>(pts, 1.5, 60, box, 509),
                             opt);
    }
}

// Integer lattice, radii 1 and 2 (and queries of radius 1): many pairs at exactly r_i, and in
// the symmetric rule at exactly max(r_i, r_j).
TEST(OraclePointRadii, LatticeTiesAtEachRadius) {
    const auto pts = lattice_points<double, 3>(6, 1.0);
    std::vector<double> radii(pts.size() / 3);
    for (std::size_t i = 0; i < radii.size(); ++i) radii[i] = i % 3 == 0 ? 2.0 : 1.0;
    radii_case<double, 3>(pts, radii, lattice_points<double, 3>(6, 1.0, 0.5));
}

// One radius for every point: the same lists as the fixed-radius grid, under both rules.
TEST(OraclePointRadii, EqualRadiiAreTheFixedRadiusSearch) {
    const auto pts = uniform_points<float, 3>(2000, 0, 10, 510);
    const std::vector<float> radii(2000, 0.9f);
    const grid<float, 3> fixed(pts, 0.9f);
    list_options o;
    o.distances = true;
    o.order = row_order::index;
    const csr<float> want = fixed.neighbor_lists(o);
    for (auto rule : {radius_rule::gather, radius_rule::symmetric}) {
        grid_options opt;
        opt.rule = rule;
        const csr<float> got = grid<float, 3>(pts, radii, opt).neighbor_lists(o);
        EXPECT_EQ(got.offsets, want.offsets);
        EXPECT_EQ(got.indices, want.indices);
        EXPECT_EQ(got.distances, want.distances);
    }
}

// A grid of one radius answers queries of radii up to it (gather).
TEST(OraclePointRadii, QueryRadiiOnAFixedRadiusGrid) {
    const auto pts = uniform_points<double, 2>(900, 0, 12, 511);
    const auto queries = query_points<double, 2>(pts, 1.0, 80, {}, 512);
    grid_options opt;
    opt.threads = 1;
    for (double f : {1.0, 0.5}) {
        opt.cell_size = f;
        const grid<double, 2> g(pts, 1.0, opt);
        radii_spec<double> spec;
        const auto qr = radii_between<double>(queries.size() / 2, 0.05, 1.0, 513);
        spec.queries = qr;
        check_grid<double, 2>(g, pts, 1.0, {}, queries, depth::basic, spec);
    }
}

// Extreme scales: radii whose squares leave the type's range (the scaled search), with a
// spread of 4 among them.
TEST(OraclePointRadii, ExtremeRadii) {
    for (double unit : {1e-30, 1e30}) {
        auto pts = uniform_points<float, 3>(300, 0, 6, 514);
        for (auto& v : pts) v = float(double(v) * unit);
        auto radii = radii_between<float>(300, 0.25, 1.0, 515);
        for (auto& r : radii) r = float(double(r) * unit);
        auto queries = query_points<float, 3>(pts, unit, 30, {}, 516);
        queries.resize(queries.size() - 3);  // not the far point at -1e6: beyond 1e30's scale
        SCOPED_TRACE("unit " + std::to_string(unit));
        for (auto rule : {radius_rule::gather, radius_rule::symmetric}) {
            grid_options opt;
            opt.rule = rule;
            opt.cell_size = double(largest(radii)) / 2;
            check_radii<float, 3>(pts, radii, opt, queries, radii_between<float>(30, 0.1 * unit, 0.9 * unit, 517),
                                  depth::basic);
        }
    }
}

template <class T, int D>
std::vector<csr<T>> outputs_of(const grid<T, D>& g, const std::vector<T>& queries, const std::vector<T>& query_radii) {
    std::vector<csr<T>> out;
    list_options o;
    o.distances = true;
    out.push_back(g.neighbor_lists(o));
    out.push_back(g.query(queries, query_radii, o));
    o.half = true;
    out.push_back(g.neighbor_lists(o));
    o.half = false;
    o.order = row_order::distance;
    out.push_back(g.nearest(4, o));
    csr<T> counts;
    for (auto c : g.count_neighbors()) counts.indices.push_back(c);
    out.push_back(counts);
    return out;
}

// Bit-identical at 1, 2 and 4 threads; 20,000 points so that sweeps split into chunks.
TEST(OraclePointRadii, SameAtAnyThreadCount) {
    const auto pts = uniform_points<float, 3>(20000, 0, 20, 518);
    const auto radii = radii_between<float>(20000, 0.2, 1.0, 519);
    const auto queries = query_points<float, 3>(pts, 1.0, 3000, {}, 520);
    const auto query_radii = radii_between<float>(queries.size() / 3, 0.1, 1.0, 521);
    for (auto rule : {radius_rule::gather, radius_rule::symmetric}) {
        grid_options opt;
        opt.rule = rule;
        opt.cell_size = 0.5;
        opt.threads = 1;
        const auto ref = outputs_of<float, 3>(grid<float, 3>(pts, radii, opt), queries, query_radii);
        for (int t : {2, 4}) {
            opt.threads = t;
            expect_identical(outputs_of<float, 3>(grid<float, 3>(pts, radii, opt), queries, query_radii), ref,
                             std::to_string(t) + " threads");
        }
    }
}

// rebuild keeps the radii; a new build with one radius drops them.
TEST(OraclePointRadii, RebuildKeepsTheRadii) {
    const auto pts = uniform_points<double, 3>(400, 0, 5, 522);
    const auto radii = radii_between<double>(400, 0.2, 0.8, 523);
    grid<double, 3> g(pts, radii);
    const auto moved = uniform_points<double, 3>(400, 0, 5, 524);
    g.rebuild(moved);
    ASSERT_TRUE(g.has_point_radii());
    radii_spec<double> spec;
    spec.data = radii;
    check_grid<double, 3>(g, moved, g.radius(), {}, {}, depth::basic, spec);
    g.build(moved, 0.5);
    EXPECT_FALSE(g.has_point_radii());
    EXPECT_TRUE(g.point_radii().empty());
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const error& e) {
        return e.what();
    }
    return "";
}

// A bad radius names its index; the grid is left as it was; fixed-radius queries on a grid of
// radii, and bad query radii, are refused.
TEST(OraclePointRadii, BadRadii) {
    const auto pts = uniform_points<double, 3>(50, 0, 5, 525);
    grid<double, 3> g(pts, 1.0);
    const auto before = g.neighbor_lists();
    auto with = [&](std::size_t i, double v) {
        std::vector<double> r(50, 0.5);
        r[i] = v;
        return error_of([&] { g.build(pts, r); });
    };
    EXPECT_NE(with(17, NAN).find("radius 17"), std::string::npos);
    EXPECT_NE(with(3, 0.0).find("radius 3"), std::string::npos);
    EXPECT_NE(with(49, -1.0).find("radius 49"), std::string::npos);
    EXPECT_NE(with(0, INFINITY).find("radius 0"), std::string::npos);
    EXPECT_NE(error_of([&] { g.build(pts, std::vector<double>(49, 0.5)); }).find("49 values for 50 points"),
              std::string::npos);
    EXPECT_FALSE(g.has_point_radii());
    EXPECT_EQ(g.neighbor_lists().indices, before.indices);

    const grid<double, 3> radii_grid(pts, std::vector<double>(50, 0.5));
    const std::vector<double> q = {1, 1, 1, 2, 2, 2};
    EXPECT_NE(error_of([&] { radii_grid.query(q); }).find("radius per point"), std::string::npos);
    EXPECT_NE(error_of([&] { radii_grid.query_counts(q); }).find("radius per point"), std::string::npos);
    EXPECT_NE(error_of([&] { radii_grid.for_each_neighbor_of({1.0, 1.0, 1.0}, [](auto, auto) {}); }).find("radius per point"),
              std::string::npos);
    EXPECT_NE(error_of([&] { radii_grid.query(q, std::vector<double>{0.1}); }).find("1 values for 2 query points"),
              std::string::npos);
    EXPECT_NE(error_of([&] { radii_grid.query(q, std::vector<double>{0.1, 0.6}); }).find("query radius 1"),
              std::string::npos);
    EXPECT_NE(error_of([&] { radii_grid.query(q, std::vector<double>{NAN, 0.1}); }).find("query radius 0"),
              std::string::npos);
}

}  // namespace
}  // namespace frnn::test
