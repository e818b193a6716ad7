// Far outliers beside a bulk of points (issue 23.2): a point at 1e8 made the device lose pairs
// deep in the bulk (its search block grew with |x| and ran past lavapipe's loop limit, cutting
// the loops of the other points of its SIMD group). One outlier from 1e4 to 1e30 and at -1e30,
// several outliers (far duplicates that are each other's neighbors, mixed signs and axes), 2D
// and 3D, automatic, uniform (over the bulk's domain: outliers fold into the border cells) and
// hashed grids, periodic boxes (the outliers wrapped into them); the automatic kind is the
// CPU grid's.
#include <gtest/gtest.h>

#include <cmath>

#include "oracle/point_sets.hpp"
#include "oracle_check.hpp"
#include "vulkan_env.hpp"

namespace frnn::vulkan::test {
namespace {

using namespace frnn::test;

constexpr double outliers[] = {1e4, 1e6, 1e8, 1e12, 1e20, 1e30, -1e30};

class vulkan_outliers : public vulkan_test {
protected:
    // The bulk: uniform in [0, side)^D, r = 1, about 1.2 points per unit volume (the issue's
    // density); queries over it, at the outliers and beside them.
    template <int D>
    void every_kind(const std::vector<float>& pts, double side, const std::vector<float>& far_queries,
                    const std::string& what) {
        auto queries = query_points<float, D>(uniform_points<float, D>(200, 0, side, 3), 1.0, 40, {}, 4);
        queries.insert(queries.end(), far_queries.begin(), far_queries.end());
        for (grid_kind kind : {grid_kind::automatic, grid_kind::uniform, grid_kind::hashed}) {
            grid_options o;
            o.kind = kind;
            if (kind == grid_kind::uniform) {  // over the bulk: a box to the outliers has no cells
                o.domain_min.assign(D, 0.0);
                o.domain_max.assign(D, side);
            }
            SCOPED_TRACE(what + " kind=" + kind_name(kind));
            const grid_kind took = check_device<D>(ctx(), pts, 1.0f, o, queries, depth::basic);
            if (kind == grid_kind::automatic) {  // one policy for both backends (core/kind_policy.hpp)
                try {
                    EXPECT_EQ(took, (frnn::grid<float, D>(pts, 1.0f, o).kind()));
                } catch (const frnn::error& e) {  // the CPU's hashed grid keys 2^52 cells, the device's all
                    EXPECT_NE(std::string(e.what()).find("2^52 cells"), std::string::npos) << e.what();
                    EXPECT_EQ(took, grid_kind::hashed);
                }
            }
            if (HasFailure()) return;
        }
    }

    // The same bulk in a periodic box of its side: the outlier, any number of boxes out, is
    // wrapped into the box exactly (on the device, as the CPU and the oracle do), so the device
    // equals the oracle at every distance.
    template <int D>
    void periodic(const std::vector<float>& pts, double side, const std::string& what) {
        grid_options o;
        o.periodic.assign(D, side);
        SCOPED_TRACE(what + " periodic");
        check_device<D>(ctx(), pts, 1.0f, o, query_points<float, D>(pts, 1.0, 40, o.periodic, 5), depth::basic);
    }
};

// The automatic kind is one policy (core/kind_policy.hpp): the device and the CPU grid choose
// alike on the same points, whichever way the choice goes.
TEST_F(vulkan_outliers, automatic_kind_is_the_cpu_grids) {
    struct set {
        std::vector<float> pts;
        double cell_fraction;
        grid_kind expected;
        const char* what;
    };
    auto with = [](std::vector<float> pts, std::initializer_list<double> far) {
        for (double v : far) append_point<float, 3>(pts, v);
        return pts;
    };
    const auto bulk = uniform_points<float, 3>(3000, 0, 14, 41);
    const std::vector<set> sets = {
        {bulk, 1.0, grid_kind::uniform, "dense box"},
        {uniform_points<float, 3>(3000, 0, 400, 42), 1.0, grid_kind::hashed, "sparse box"},
        {with(bulk, {1e8}), 1.0, grid_kind::uniform, "one far outlier (folded)"},
        {with(bulk, {1e8, -1e8, 2e8, 3e8, 4e8}), 1.0, grid_kind::hashed, "five far outliers (1 in 600)"},
        {uniform_points<float, 3>(3000, 0, 8, 43), 0.25, grid_kind::uniform, "cells of r/4 (budget times 8)"},
    };
    for (const auto& s : sets) {
        grid_options o;
        o.cell_size = s.cell_fraction;
        frnn::grid<float, 3> cpu(s.pts, 1.0f, o);
        grid<3> device(ctx());
        device.build(s.pts, 1.0f, o);
        EXPECT_EQ(cpu.kind(), s.expected) << s.what;
        EXPECT_EQ(device.kind(), cpu.kind()) << s.what;
    }
}

TEST_F(vulkan_outliers, one_outlier_3d) {
    // The case at a third of its size: 1,700 points in [0, 12)^3.
    for (double far : outliers) {
        auto pts = uniform_points<float, 3>(1700, 0, 12, 23);
        append_point<float, 3>(pts, far);
        const std::vector<float> at{float(far), float(far), float(far), float(far), 5, 5};
        every_kind<3>(pts, 12, at, "outlier " + std::to_string(far));
        periodic<3>(pts, 12, "outlier " + std::to_string(far));
        if (HasFailure()) return;
    }
}

TEST_F(vulkan_outliers, one_outlier_2d) {
    for (double far : outliers) {
        auto pts = uniform_points<float, 2>(1500, 0, 35, 24);
        append_point<float, 2>(pts, far);
        every_kind<2>(pts, 35, {float(far), float(far), float(far), 0}, "2D outlier " + std::to_string(far));
        periodic<2>(pts, 35, "2D outlier " + std::to_string(far));
        if (HasFailure()) return;
    }
}

TEST_F(vulkan_outliers, several_outliers) {
    // Far duplicates (each other's neighbors at distance 0), pairs one float step apart at 1e4,
    // mixed signs and single far axes, scattered through the input order.
    auto pts3 = uniform_points<float, 3>(1700, 0, 12, 25);
    const std::vector<float> far3{1e8f, 1e8f, 1e8f,    -1e30f, 1e30f, 0,     1e8f, 1e8f, 1e8f,
                                  1e4f, 1e4f, 1e4f,    1e4f, 1e4f, 10000.001f, 5, 1e20f, 5,
                                  -1e30f, -1e30f, -1e30f, 1e12f, -1e12f, 3, -1e30f, 1e30f, 0};
    for (std::size_t k = 0; k < far3.size() / 3; ++k) {  // every 190th point, all within the bulk
        const std::size_t at = k * 190 * 3;
        ASSERT_LE(at, pts3.size());
        pts3.insert(pts3.begin() + std::ptrdiff_t(at), far3.begin() + std::ptrdiff_t(k * 3),
                    far3.begin() + std::ptrdiff_t(k * 3 + 3));
    }
    every_kind<3>(pts3, 12, far3, "several 3D");
    periodic<3>(pts3, 12, "several 3D");

    auto pts2 = uniform_points<float, 2>(1500, 0, 35, 26);
    const std::vector<float> far2{1e6f, -1e6f, 1e6f, -1e6f, -1e30f, 1e30f, 1e20f, 4, 4, -1e8f, 1e6f, -1e6f};
    pts2.insert(pts2.begin() + 700, far2.begin(), far2.end());
    every_kind<2>(pts2, 35, far2, "several 2D");
    periodic<2>(pts2, 35, "several 2D");
}

}  // namespace
}  // namespace frnn::vulkan::test
