// Extreme float radii on the device (issue 23.1): radii whose square overflows or underflows
// float are searched with the search scale of frnn/search_scale.hpp, exactly as the CPU grid and
// the brute-force oracle do; the point sets are those of tests/oracle/extremes_test.cpp. Every
// query path is held to the oracle by check_device_grid.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "oracle/point_sets.hpp"
#include "oracle_check.hpp"
#include "vulkan_env.hpp"

namespace frnn::vulkan::test {
namespace {

using frnn::test::lattice_points;
using frnn::test::uniform_points;

class vulkan_extremes : public vulkan_test {};

constexpr float fmax = std::numeric_limits<float>::max();
constexpr grid_kind kinds[] = {grid_kind::automatic, grid_kind::uniform, grid_kind::hashed};

std::string text(double v) {
    char s[32];
    std::snprintf(s, sizeof s, "%.9g", v);
    return s;
}

/// Every kind with cells of r and r/4; the full list_options sweep once (automatic, cell r),
/// one value of each option elsewhere. The grid keeps the caller's radius and scales by s.
template <int D>
void every_kind(context& ctx, const std::vector<float>& pts, float r, const std::vector<float>& queries,
                const std::string& what, float expected_scale_side = 0) {
    for (auto kind : kinds) {
        for (double f : {1.0, 0.25}) {
            grid_options o;
            o.kind = kind;
            o.cell_size = f == 1.0 ? 0 : double(r) * f;
            SCOPED_TRACE(what + " kind " + std::to_string(int(kind)) + " cell r*" + text(f));
            const bool full = kind == grid_kind::automatic && f == 1.0;
            grid<D> g(ctx);
            g.build(pts, r, o);
            EXPECT_EQ(g.radius(), r);
            if (expected_scale_side < 0) {
                EXPECT_LT(g.search_scale(), 1.0f);
            }
            if (expected_scale_side > 0) {
                EXPECT_GT(g.search_scale(), 1.0f);
            }
            if (kind != grid_kind::automatic) {
                EXPECT_EQ(g.kind(), kind);
            }
            check_device_grid<D>(g, pts, r, {}, queries, full ? depth::full : depth::basic);
        }
    }
}

/// 80 points over three radii on each side of the origin (at most FLT_MAX), 12 queries.
template <int D>
void scaled_uniform_case(context& ctx, double r, std::uint64_t seed, float side) {
    const double spread = std::min(3 * r, double(fmax));
    const auto pts = uniform_points<float, D>(80, -spread, spread, seed);
    const auto queries = uniform_points<float, D>(12, -spread, spread, seed + 1);
    every_kind<D>(ctx, pts, float(r), queries, std::to_string(D) + "D r=" + text(r), side);
}

TEST_F(vulkan_extremes, huge_radius) {
    for (double r : {1e20, 1e30, 3e38, double(fmax)}) {
        scaled_uniform_case<3>(ctx(), r, 11, -1);
        scaled_uniform_case<2>(ctx(), r, 12, -1);
    }
}

TEST_F(vulkan_extremes, tiny_radius) {
    // 1e-40 and 2^-140 are subnormal floats; 2^-50 is the first radius below the unscaled range.
    for (double r : {0x1p-50, 1e-30, 1e-40, 0x1p-140}) {
        scaled_uniform_case<3>(ctx(), r, 31, 1);
        scaled_uniform_case<2>(ctx(), r, 32, 1);
    }
}

TEST_F(vulkan_extremes, radius_beyond_every_distance) {
    // Every pair is a neighbor: 39 each. Before the scale, 1.8446744e19 and beyond were refused.
    const auto pts = uniform_points<float, 3>(40, -10, 10, 52);
    for (float r : {1.8446744e19f, 1e20f, 1e38f, fmax}) {
        grid<3> g(ctx());
        g.build(pts, r);
        EXPECT_EQ(g.count_neighbors(), std::vector<std::uint32_t>(40, 39u)) << r;
        check_device_grid<3>(g, pts, r, {}, pts, depth::basic);
    }
}

// Lattice pairs within k steps of a side^D lattice, counted on the integer indices (exact).
template <int D>
std::size_t lattice_pairs(int side, int k) {
    const int total = D == 2 ? side * side : side * side * side;
    auto index = [side](int p, int axis) {
        for (int i = 0; i < axis; ++i) p /= side;
        return p % side;
    };
    std::size_t count = 0;
    for (int p = 0; p < total; ++p)
        for (int q = 0; q < total; ++q) {
            int s = 0;
            for (int a = 0; a < D; ++a) s += (index(p, a) - index(q, a)) * (index(p, a) - index(q, a));
            count += p != q && s <= k * k;
        }
    return count;
}

// Exact ties at extreme scales: integer lattices times 2^+-80 and 2^+-120, radius one or two
// steps; the device must find every lattice pair at exactly r.
template <int D>
void lattice_ties(context& ctx, double step) {
    const int side = D == 2 ? 7 : 4;
    const auto pts = lattice_points<float, D>(side, step, -2 * step);
    const auto queries = lattice_points<float, D>(3, step, -step / 2);
    for (int k : {1, 2}) {
        const float r = float(k * step);
        every_kind<D>(ctx, pts, r, queries, "lattice step " + text(step) + " r " + std::to_string(k) + " steps");
        grid<D> g(ctx);
        g.build(pts, r);
        EXPECT_EQ(g.neighbor_lists().size(), lattice_pairs<D>(side, k)) << "step " << step << ", r " << k << " steps";
    }
}

TEST_F(vulkan_extremes, lattice_ties_at_extreme_scales) {
    for (double step : {0x1p80, 0x1p120, 0x1p-80, 0x1p-120}) {
        lattice_ties<3>(ctx(), step);
        lattice_ties<2>(ctx(), step);
    }
}

TEST_F(vulkan_extremes, coordinates_near_largest) {
    // Differences overflow to infinity and count as beyond r.
    auto pts = uniform_points<float, 3>(40, fmax * 0.9, fmax, 61);
    const auto low = uniform_points<float, 3>(40, -double(fmax), -fmax * 0.9, 62);
    pts.insert(pts.end(), low.begin(), low.end());
    every_kind<3>(ctx(), pts, 3e37f, uniform_points<float, 3>(10, -double(fmax), fmax, 63), "near largest", -1);
}

TEST_F(vulkan_extremes, far_queries_of_a_scaled_up_grid) {
    // r = 1e-30: s is about 2^100, so 1e20 and -3e38 overflow when scaled: no neighbors, as in
    // the oracle (infinite differences). The last query lies among the points.
    const auto pts = uniform_points<float, 3>(60, -3e-30, 3e-30, 71);
    const std::vector<float> far = {1e20f, 0, 0, -3e38f, 1e-30f, 0, fmax, fmax, fmax, 1e-30f, 0, 0};
    for (auto kind : kinds) {
        grid_options o;
        o.kind = kind;
        grid<3> g(ctx());
        g.build(pts, 1e-30f, o);
        EXPECT_GT(g.search_scale(), 0x1p90f);
        const auto counts = g.query_counts(far);
        ASSERT_EQ(counts.size(), 4u);
        for (std::size_t q = 0; q < 3; ++q) EXPECT_EQ(counts[q], 0u) << int(kind) << " query " << q;
        EXPECT_GT(counts[3], 0u);
        check_device_grid<3>(g, pts, 1e-30f, {}, far, depth::basic);
    }
}

TEST_F(vulkan_extremes, periodic_at_extreme_scales) {
    // The CPU suite's sets: boxes of 10 r by 12 r, the box scaled with the points; cells of r
    // (every list option) and r/2.
    const std::pair<double, double> cases[] = {{1e30, 1.0}, {1e30, 0.5}, {1e-30, 1.0}, {1e-30, 0.5}};
    for (const auto& [r, cell] : cases) {
        SCOPED_TRACE("periodic r=" + text(r) + " cell r*" + text(cell));
        grid_options o;
        o.periodic = {10 * r, 12 * r};
        o.cell_size = cell == 1.0 ? 0 : r * cell;
        const auto pts = uniform_points<float, 2>(150, 0, 10 * r, 91);
        grid<2> g(ctx());
        g.build(pts, float(r), o);
        EXPECT_NE(g.search_scale(), 1.0f);
        check_device_grid<2>(g, pts, float(r), o.periodic, uniform_points<float, 2>(20, -5 * r, 15 * r, 92),
                             cell == 1.0 ? depth::full : depth::basic);
    }
}

TEST_F(vulkan_extremes, callers_buffer_refuses_a_scaled_radius) {
    // A buffer_view is read in place, so a radius that needs a scale is refused with the
    // radius and the range named; one inside the range builds.
    const auto pts = uniform_points<float, 3>(200, -3e10, 3e10, 81);
    device_buffer coords(ctx(), pts.size() * sizeof(float), "coords");
    coords.upload(pts.data(), pts.size() * sizeof(float));
    grid<3> g(ctx());
    for (float r : {1e20f, 1e-30f}) {
        const std::string err = error_of([&] { g.build(coords.view(), 200, r); });
        EXPECT_NE(err.find("radius " + text(r)), std::string::npos) << err;
        EXPECT_NE(err.find("[2^-49, 2^63)"), std::string::npos) << err;
        EXPECT_NE(err.find("host"), std::string::npos) << err;
        EXPECT_EQ(g.size(), 0u);
    }
    g.build(coords.view(), 200, 1e10f);
    EXPECT_EQ(g.search_scale(), 1.0f);
    check_device_grid<3>(g, pts, 1e10f, {}, {}, depth::basic);
    // From the host the same huge radius works.
    g.build(pts, 1e20f);
    check_device_grid<3>(g, pts, 1e20f, {}, {}, depth::basic);
}

TEST_F(vulkan_extremes, radius_too_small_for_the_coordinates) {
    // r^2 would stay subnormal at any scale that keeps 1e30 finite: refused as on the CPU.
    std::vector<float> pts = {0, 0, 0, 1e30f, 0, 0};
    grid<3> g(ctx());
    const std::string err = error_of([&] { g.build(pts, 1e-44f); });
    EXPECT_NE(err.find("vulkan::grid::build: radius"), std::string::npos) << err;
    EXPECT_NE(err.find("too small for coordinates"), std::string::npos) << err;
}

}  // namespace
}  // namespace frnn::vulkan::test
