// Bad input: every case throws frnn::error with a message saying what and where, never crashes
// (these tests also run under address + undefined sanitizers).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <limits>
#include <optional>
#include <string>

#include "oracle/oracle_check.hpp"
#include "oracle/point_sets.hpp"

namespace frnn::test {
namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

/// `f` must throw frnn::error whose message contains every one of `parts` (case-insensitive).
template <class F>
void expect_error(F&& f, std::vector<std::string> parts, const std::string& what) {
    try {
        f();
        ADD_FAILURE() << what << ": no frnn::error thrown";
    } catch (const frnn::error& e) {
        const std::string msg = lower(e.what());
        for (const auto& p : parts)
            EXPECT_NE(msg.find(lower(p)), std::string::npos)
                << what << ": message \"" << e.what() << "\" does not mention \"" << p << "\"";
    } catch (const std::exception& e) {
        ADD_FAILURE() << what << ": threw a type other than frnn::error: " << e.what();
    }
}

constexpr grid_kind kinds[] = {grid_kind::automatic, grid_kind::uniform, grid_kind::hashed};

template <class T, int D>
void non_finite_case() {
    const T bad_values[] = {std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::infinity(),
                            -std::numeric_limits<T>::infinity()};
    for (auto kind : kinds) {
        for (T bad : bad_values) {
            for (int axis = 0; axis < D; ++axis) {
                auto pts = uniform_points<T, D>(600, 0, 10, 301);
                pts[137 * D + axis] = bad;           // the first bad point
                pts[512 * D + (D - 1 - axis)] = bad; // a later one
                grid_options opt;
                opt.kind = kind;
                const std::string what = "kind=" + kind_name(kind) + " value=" + std::to_string(bad) +
                                         " axis=" + std::to_string(axis);
                expect_error([&] { grid<T, D> g(pts, T(1), opt); }, {"137"}, what + " build");
                grid<T, D> g(uniform_points<T, D>(600, 0, 10, 302), T(1), opt);
                expect_error([&] { g.rebuild(pts); }, {"137"}, what + " rebuild");
            }
        }
    }
}

TEST(OracleBadInput, NonFiniteCoordinatesFloat2D) { non_finite_case<float, 2>(); }
TEST(OracleBadInput, NonFiniteCoordinatesDouble3D) { non_finite_case<double, 3>(); }

TEST(OracleBadInput, Radius) {
    const auto pts = uniform_points<double, 3>(100, 0, 5, 311);
    for (double r : {0.0, -0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
                     std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}) {
        expect_error([&] { grid<double, 3> g(pts, r); }, {"radius"}, "radius " + std::to_string(r));
    }
    const auto pf = uniform_points<float, 2>(100, 0, 5, 312);
    expect_error([&] { grid<float, 2> g(pf, -2.0f); }, {"radius"}, "float radius -2");
    expect_error([&] { grid<float, 2> g(pf, std::numeric_limits<float>::quiet_NaN()); }, {"radius"},
                 "float radius NaN");
    // Valid on an empty set too: the radius is checked regardless of N.
    expect_error([&] { grid<float, 2> g(std::vector<float>{}, 0.0f); }, {"radius"}, "empty, radius 0");
}

TEST(OracleBadInput, CellSize) {
    const auto pts = uniform_points<double, 2>(100, 0, 5, 321);
    for (auto kind : kinds) {
        for (double f : {1.5, 1.0001, 0.2, 0.24, -0.5, std::numeric_limits<double>::quiet_NaN(),
                         std::numeric_limits<double>::infinity()}) {
            grid_options opt;
            opt.kind = kind;
            opt.cell_size = 2.0 * f;
            expect_error([&] { grid<double, 2> g(pts, 2.0, opt); }, {"cell"},
                         "kind=" + kind_name(kind) + " cell=r*" + std::to_string(f));
        }
    }
}

TEST(OracleBadInput, PeriodicBox) {
    const auto pts = uniform_points<double, 3>(100, 0, 1.5, 331);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    // (A length of 0 is no error: it leaves that axis open, see mixed_periodic_test.cpp.)
    const std::vector<std::vector<double>> boxes = {
        {1.99, 10, 10}, {10, 10, 1.5}, {10, 10}, {10, 10, 10, 10}, {10}, {10, -4, 10},
        {10, nan, 10}, {10, 10, std::numeric_limits<double>::infinity()}};
    for (auto kind : kinds) {
        for (const auto& box : boxes) {
            grid_options opt;
            opt.kind = kind;
            opt.periodic = box;
            // Appended piece by piece: g++ 12 warns falsely (-Wrestrict) on "..." + string here.
            std::string what = "kind=";
            what += kind_name(kind);
            what += " box";
            for (double v : box) {
                what += ' ';
                what += std::to_string(v);
            }
            expect_error([&] { grid<double, 3> g(pts, 1.0, opt); }, {"periodic"}, what);
        }
    }
    grid_options opt2;
    opt2.periodic = {3, 3, 3};
    expect_error([&] { grid<float, 2> g(uniform_points<float, 2>(10, 0, 1, 332), 1.0f, opt2); },
                 {"periodic"}, "3 lengths for 2D");
}

TEST(OracleBadInput, CoordsNotMultipleOfDimension) {
    expect_error([] { grid<double, 3> g(std::vector<double>(10, 0.0), 1.0); }, {"10"}, "10 values in 3D");
    expect_error([] { grid<float, 2> g(std::vector<float>(7, 0.0f), 1.0f); }, {"7"}, "7 values in 2D");
    grid<double, 3> g(uniform_points<double, 3>(50, 0, 2, 341), 1.0);
    expect_error([&] { g.rebuild(std::vector<double>(301, 0.0)); }, {"301"}, "rebuild with 301 values");
    expect_error([&] { (void)g.query(std::vector<double>(5, 0.0)); }, {"5"}, "query with 5 values");
    expect_error([&] { (void)g.query_counts(std::vector<double>(4, 0.0)); }, {"4"}, "query_counts with 4 values");
    expect_error([&] { (void)g.query_nearest(std::vector<double>(8, 0.0), 2); }, {"8"},
                 "query_nearest with 8 values");
}

// list_options::rows: at most the number of points, and not for queries.
TEST(OracleBadInput, ListRows) {
    grid<float, 3> g(uniform_points<float, 3>(50, 0, 2, 342), 1.0f);
    list_options o;
    o.rows = 51;
    expect_error([&] { (void)g.neighbor_lists(o); }, {"51", "50 points"}, "rows beyond the points");
    expect_error([&] { (void)g.nearest(3, o); }, {"51", "50 points"}, "nearest, rows beyond the points");
    o.rows = 10;
    expect_error([&] { (void)g.query(std::vector<float>{0, 0, 0}, o); }, {"rows", "queries"}, "rows of queries");
}

TEST(OracleBadInput, QueryPointsNotFinite) {
    for (auto kind : kinds) {
        grid_options opt;
        opt.kind = kind;
        grid<double, 3> g(uniform_points<double, 3>(300, 0, 5, 351), 1.0, opt);
        grid<float, 2> gf(uniform_points<float, 2>(300, 0, 5, 352), 1.0f, opt);
        for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
            auto q = uniform_points<double, 3>(40, 0, 5, 353);
            q[23 * 3 + 1] = bad;
            q[31 * 3] = bad;
            const std::string what = "kind=" + kind_name(kind) + " value " + std::to_string(bad);
            expect_error([&] { (void)g.query(q); }, {"23"}, what + " query");
            expect_error([&] { (void)g.query_counts(q); }, {"23"}, what + " query_counts");
            expect_error([&] { (void)g.query_nearest(q, 3); }, {"23"}, what + " query_nearest");
            expect_error([&] { g.for_each_neighbor_of({1, bad, 1}, [](std::uint32_t, double) {}); }, {},
                         what + " for_each_neighbor_of");
            auto qf = uniform_points<float, 2>(40, 0, 5, 354);
            qf[23 * 2] = float(bad);
            expect_error([&] { (void)gf.query(qf); }, {"23"}, what + " float query");
        }
    }
}

// Cell coordinates beyond the range of the integer keys: handled exactly, or rejected with one
// of the grid's documented limits (the hashed grid's 2^52 cells from the origin, the explicit
// uniform grid's cell budget); never a crash or a wrong pair.
template <class T, int D>
void huge_case(std::vector<T> pts, T r, grid_kind kind, double cell_fraction, const std::string& what) {
    grid_options opt;
    opt.kind = kind;
    opt.cell_size = double(r) * cell_fraction;
    SCOPED_TRACE(what + " kind=" + kind_name(kind) + " cell=r*" + std::to_string(cell_fraction));
    std::optional<grid<T, D>> g;
    try {
        g.emplace(pts, r, opt);
    } catch (const frnn::error& e) {
        const std::string msg = e.what();
        EXPECT_TRUE(msg.find("2^52 cells") != std::string::npos ||
                    (kind == grid_kind::uniform && msg.find("uniform grid over this domain") != std::string::npos))
            << msg;
        return;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "threw a type other than frnn::error: " << e.what();
        return;
    }
    // At most the uniform grid's budget of max(2^24, 64 N) cells of 4 bytes, plus the points.
    EXPECT_LE(g->memory_bytes(), (std::size_t(64) << 20) + 512 * (pts.size() / D)) << "memory of the grid";
    check_grid<T, D>(*g, pts, r, {}, std::vector<T>(pts.begin(), pts.begin() + D));
}

TEST(OracleBadInput, CellCoordinateOverflow) {
    for (auto kind : kinds) {
        for (double f : {1.0, 0.25}) {
            huge_case<double, 3>({0, 0, 0, 0.5, 0, 0, 1e300, 0, 0}, 1.0, kind, f, "1e300");
            huge_case<double, 3>({0, 0, 0, 0.5, 0, 0, 0, -1e300, 0}, 1.0, kind, f, "-1e300");
            huge_case<double, 2>({1e300, 1e300, 1e300, 1e300}, 1.0, kind, f, "two points at 1e300");
            huge_case<double, 2>({0, 0, 9.2e18, 0, 9.2e18, 0.5}, 1.0, kind, f, "9.2e18 (near int64 max)");
            huge_case<double, 2>({0, 0, -9.3e18, 0, -9.3e18, 0.5}, 1.0, kind, f, "-9.3e18 (past int64 min)");
            huge_case<double, 2>({0, 0, 4.6e18, 0, 4.6e18, 0.5}, 1.0, kind, f, "4.6e18");
            huge_case<float, 3>({0, 0, 0, 1e30f, 0, 0, 1e30f, 0, 0}, 1e-3f, kind, f, "float 1e30, r 1e-3");
            huge_case<float, 2>({3e38f, -3e38f, 0, 0}, 1.0f, kind, f, "float 3e38");
            huge_case<double, 3>({0, 0, 0, 1e-300, 0, 0}, 1e-300, kind, f, "tiny radius 1e-300");
            // Found by the grid fuzzer: an automatic (or explicit) uniform grid of 2^30 cells
            // for three points (8 GB), two of them apart by 2^30 cells, one beyond the keys.
            huge_case<float, 3>({0, 0, 0, 0x1p30f, 0, 0, 0x1p60f, 0, 0}, 1.0f, kind, f, "2^30 and 2^60 cells");
            huge_case<float, 2>({1.5e-30f, 0, 0, 0, 0, 0}, 3.857e-39f, kind, f, "1.5e-30 with r 3.9e-39");
        }
    }
}

TEST(OracleBadInput, IndexOutOfRange) {
    grid<double, 2> g(uniform_points<double, 2>(50, 0, 2, 361), 0.5);
    expect_error([&] { g.for_each_neighbor(50, [](std::uint32_t, double) {}); }, {"50"}, "for_each_neighbor(50)");
    expect_error([&] { g.for_each_neighbor_sorted(1000, [](std::uint32_t, double) {}); }, {"1000"},
                 "for_each_neighbor_sorted(1000)");
    std::vector<double> wrong(49);
    expect_error([&] { g.reorder(std::span<double>(wrong)); }, {"49"}, "reorder 49 values");
    expect_error([&] { g.restore_order(std::span<double>(wrong)); }, {"49"}, "restore_order 49 values");
    grid<double, 2> empty(std::vector<double>{}, 0.5);
    expect_error([&] { empty.for_each_neighbor(0, [](std::uint32_t, double) {}); }, {}, "empty grid, point 0");
}

TEST(OracleBadInput, Domain) {
    const auto pts = uniform_points<double, 3>(100, 0, 5, 371);
    const std::vector<std::pair<std::vector<double>, std::vector<double>>> bad = {
        {{0, 0, 0}, {}},         {{}, {5, 5, 5}},           {{0, 0}, {5, 5}},
        {{0, 0, 0}, {5, 5, 5, 5}}, {{0, 6, 0}, {5, 5, 5}},
        {{0, std::numeric_limits<double>::quiet_NaN(), 0}, {5, 5, 5}}};
    for (const auto& [lo, hi] : bad) {
        grid_options opt;
        opt.kind = grid_kind::uniform;
        opt.domain_min = lo;
        opt.domain_max = hi;
        expect_error([&] { grid<double, 3> g(pts, 1.0, opt); }, {"domain"},
                     "domain_min " + std::to_string(lo.size()) + " values, domain_max " +
                         std::to_string(hi.size()));
    }
}

TEST(OracleBadInput, GridKindNames) {
    for (auto kind : kinds) EXPECT_EQ(parse_grid_kind(to_string(kind)), kind);
    EXPECT_EQ(parse_grid_kind("hashed"), grid_kind::hashed);
    expect_error([] { (void)parse_grid_kind("octree"); }, {"octree"}, "parse_grid_kind(octree)");
    expect_error([] { (void)parse_grid_kind(""); }, {}, "parse_grid_kind(empty)");
}

}  // namespace
}  // namespace frnn::test
