// A failed build leaves the device grid as it was (issue 23.3): after each kind of rejected
// rebuild the grid still answers every query path as brute force does over its old points, with
// its old size, kind, cell count, radius and scale.
#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>

#include "oracle/point_sets.hpp"
#include "oracle_check.hpp"
#include "vulkan_env.hpp"

namespace frnn::vulkan::test {
namespace {

using frnn::test::uniform_points;

class vulkan_failed_build : public vulkan_test {};

constexpr float nan = std::numeric_limits<float>::quiet_NaN();
constexpr float inf = std::numeric_limits<float>::infinity();

struct attempt {
    std::string name, expected;  ///< expected: a part of the error message
    std::function<void(grid<3>&)> build;
};

// Rebuilds that must fail validation. Host coordinates: `pts` with one bad value; the device
// path: the same through a caller's buffer.
std::vector<attempt> failing_rebuilds(const std::vector<float>& pts, device_buffer& bad_on_device) {
    std::vector<attempt> out;
    auto with = [&](std::size_t at, float v) {
        auto p = pts;
        p[at] = v;
        return p;
    };
    const auto nan_pts = with(7 * 3 + 1, nan), inf_pts = with(11 * 3, -inf);
    const auto bad_device = bad_on_device.view();
    out.push_back({"NaN coordinate", "point 7 has a non-finite", [=](grid<3>& g) { g.build(nan_pts, 1.0f); }});
    out.push_back({"infinite coordinate", "point 11 has a non-finite", [=](grid<3>& g) { g.build(inf_pts, 1.0f); }});
    out.push_back({"NaN on the device", "point 5 has a non-finite",
                   [=](grid<3>& g) { g.build(bad_device, 100, 1.0f); }});
    out.push_back({"caller's buffer too small", "buffer holds", [=](grid<3>& g) { g.build(bad_device, 10000, 1.0f); }});
    out.push_back({"coordinates not a multiple of 3", "multiple of 3",
                   [=](grid<3>& g) { g.build(std::span<const float>(pts).first(7), 1.0f); }});
    for (float r : {0.0f, -1.0f, nan, inf})
        out.push_back({"radius " + std::to_string(r), "radius must be positive", [=](grid<3>& g) { g.build(pts, r); }});
    out.push_back({"radius too small for the coordinates", "too small for coordinates", [=](grid<3>& g) {
                       auto p = pts;
                       p.insert(p.end(), {1e30f, 0, 0});
                       g.build(p, 1e-44f);
                   }});
    out.push_back({"scaled radius on the device", "[2^-49, 2^63)", [=](grid<3>& g) {
                       g.build(bad_device, 5, 1e30f);  // the first 5 points are finite
                   }});
    for (double c : {2.0, 0.2}) {
        grid_options o;
        o.cell_size = c;
        out.push_back({"cell size " + std::to_string(c), "cell_size", [=](grid<3>& g) { g.build(pts, 1.0f, o); }});
    }
    grid_options box;
    box.periodic = {5, 1.5, 5};
    out.push_back({"periodic box below 2r", "twice the radius", [=](grid<3>& g) { g.build(pts, 1.0f, box); }});
    box.periodic = {5, 5};
    out.push_back({"periodic box of 2 lengths", "3 lengths", [=](grid<3>& g) { g.build(pts, 1.0f, box); }});
    grid_options domain;
    domain.domain_min = {0, 0, 0};
    out.push_back({"domain without a maximum", "both domain_min and domain_max",
                   [=](grid<3>& g) { g.build(pts, 1.0f, domain); }});
    domain.domain_max = {1, -1, 1};
    out.push_back({"domain not ordered", "not finite and ordered", [=](grid<3>& g) { g.build(pts, 1.0f, domain); }});
    grid_options huge;
    huge.kind = grid_kind::uniform;
    huge.domain_min = {-1e6, -1e6, -1e6};
    huge.domain_max = {1e6, 1e6, 1e6};
    out.push_back({"uniform grid too large", "use the hashed grid", [=](grid<3>& g) { g.build(pts, 1.0f, huge); }});
    return out;
}

struct snapshot {
    std::size_t size, cells;
    grid_kind kind;
    float radius, scale;
    bool operator==(const snapshot&) const = default;
};
snapshot state_of(const grid<3>& g) { return {g.size(), g.slot_count(), g.kind(), g.radius(), g.search_scale()}; }

// Builds `g` over `pts`, then runs every failing rebuild, checking the message and that the
// grid is unchanged: same state, and the oracle's answers over the old points.
void survives_failed_rebuilds(context& ctx, const std::vector<float>& pts, float r, const grid_options& o) {
    const auto other = uniform_points<float, 3>(100, 0, 4, 2);
    std::vector<float> with_nan = other;
    with_nan[5 * 3 + 2] = nan;
    device_buffer on_device(ctx, with_nan.size() * sizeof(float), "coords with a NaN");
    on_device.upload(with_nan.data(), with_nan.size() * sizeof(float));
    const auto queries = uniform_points<float, 3>(20, -1, 9, 3);

    grid<3> g(ctx);
    g.build(pts, r, o);
    const snapshot before = state_of(g);
    std::size_t tried = 0;
    for (const auto& a : failing_rebuilds(other, on_device)) {
        SCOPED_TRACE(a.name);
        const std::string err = error_of([&] { a.build(g); });
        EXPECT_NE(err.find(a.expected), std::string::npos) << err;
        EXPECT_NE(err.find("vulkan"), std::string::npos) << err;
        EXPECT_TRUE(state_of(g) == before);
        check_device_grid<3>(g, pts, r, o.periodic, queries, depth::basic);
        ++tried;
    }
    EXPECT_EQ(tried, 18u);
}

TEST_F(vulkan_failed_build, uniform_grid_stays) {
    survives_failed_rebuilds(ctx(), uniform_points<float, 3>(300, 0, 8, 1), 1.0f, {});
}

TEST_F(vulkan_failed_build, hashed_grid_with_a_scale_stays) {
    // A radius whose square overflows: the old grid's scale must survive too.
    grid_options o;
    o.kind = grid_kind::hashed;
    const auto pts = uniform_points<float, 3>(200, -3e30, 3e30, 4);
    survives_failed_rebuilds(ctx(), pts, 1e30f, o);
}

TEST_F(vulkan_failed_build, periodic_grid_stays) {
    grid_options o;
    o.periodic = {8, 7, 9};
    survives_failed_rebuilds(ctx(), uniform_points<float, 3>(300, 0, 8, 5), 1.0f, o);
}

}  // namespace
}  // namespace frnn::vulkan::test
