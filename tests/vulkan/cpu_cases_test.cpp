// The float cases of the CPU oracle suite (tests/oracle: random_sets, adversarial and periodic
// tests), same point sets, seeds, radii, grid kinds and cell sizes, run on the device with the
// same checker, and its double cases converted to float. Not run here: the large sets
// (450K-600K points, minutes of brute force on lavapipe's host), thread invariance and bad
// input (CPU-only options; the device's errors are in api_test.cpp).
#include <gtest/gtest.h>

#include <cmath>

#include "oracle/point_sets.hpp"
#include "oracle_check.hpp"
#include "vulkan_env.hpp"

namespace frnn::vulkan::test {
namespace {

using namespace frnn::test;

class vulkan_cpu_cases : public vulkan_test {
protected:
    /// Each kind x cell size r, r/2, r/3, r/4 on one set: full depth at cell r, basic below.
    template <int D>
    void every_grid(const std::vector<float>& pts, float r, const std::vector<float>& queries,
                    const grid_options& base = {},
                    std::vector<grid_kind> kinds = {grid_kind::automatic, grid_kind::uniform, grid_kind::hashed},
                    std::vector<double> fractions = {1.0, 0.5, 1.0 / 3, 0.25}) {
        for (grid_kind kind : kinds) {
            for (double f : fractions) {
                grid_options o = base;
                o.kind = kind;
                o.cell_size = double(r) * f;
                SCOPED_TRACE("kind=" + kind_name(kind) + " cell=r*" + std::to_string(f));
                check_device<D>(ctx(), pts, r, o, queries, depth_for_cell(f));
                if (HasFailure()) return;
            }
        }
    }
};

// random_sets_test.cpp
TEST_F(vulkan_cpu_cases, random_uniform_and_clustered) {
    const auto u2 = uniform_points<float, 2>(500, 0, 10, 11);
    every_grid<2>(u2, 1.0f, query_points<float, 2>(u2, 1.0, 150, {}, 12));
    const auto u3 = uniform_points<float, 3>(500, 0, 8, 12);
    every_grid<3>(u3, 1.5f, query_points<float, 3>(u3, 1.5, 150, {}, 13));
    const auto c2 = clustered_points<float, 2>(500, 6, 1.0, -8, 8, 21);
    every_grid<2>(c2, 0.6f, query_points<float, 2>(c2, 0.6, 150, {}, 22));
    const auto c3 = clustered_points<float, 3>(500, 6, 1.0, -8, 8, 22);
    every_grid<3>(c3, 1.0f, query_points<float, 3>(c3, 1.0, 150, {}, 23));
}

TEST_F(vulkan_cpu_cases, random_domain_smaller_than_data) {
    const auto pts = uniform_points<float, 2>(800, -5, 15, 31);
    grid_options base;
    base.domain_min.assign(2, 2.0);
    base.domain_max.assign(2, 6.5);
    every_grid<2>(pts, 1.2f, query_points<float, 2>(pts, 1.2, 100, {}, 32), base,
                  {grid_kind::automatic, grid_kind::uniform});
}

// The double cases of random_sets_test.cpp and adversarial_test.cpp converted to float (the
// same seeds draw the same values, rounded) and checked against the float reference; cells of
// r and r/4 only, to keep the suite short.
TEST_F(vulkan_cpu_cases, double_cases_in_float) {
    const std::vector<double> ends = {1.0, 0.25};
    const std::vector<grid_kind> kinds = {grid_kind::automatic, grid_kind::uniform, grid_kind::hashed};
    const auto u2 = uniform_points<float, 2>(500, 0, 10, 13);
    every_grid<2>(u2, 1.0f, query_points<float, 2>(u2, 1.0, 150, {}, 14), {}, kinds, ends);
    const auto u3 = uniform_points<float, 3>(500, 0, 8, 14);
    every_grid<3>(u3, 1.5f, query_points<float, 3>(u3, 1.5, 150, {}, 15), {}, kinds, ends);
    const auto c2 = clustered_points<float, 2>(500, 6, 1.0, -8, 8, 23);
    every_grid<2>(c2, 0.6f, query_points<float, 2>(c2, 0.6, 150, {}, 24), {}, kinds, ends);
    const auto c3 = clustered_points<float, 3>(500, 6, 1.0, -8, 8, 24);
    every_grid<3>(c3, 1.0f, query_points<float, 3>(c3, 1.0, 150, {}, 25), {}, kinds, ends);
    auto lattice = [&]<int D>(int side, double step, double origin, float r) {
        SCOPED_TRACE("lattice side=" + std::to_string(side) + " origin=" + std::to_string(origin));
        every_grid<D>(lattice_points<float, D>(side, step, origin), r,
                      lattice_points<float, D>(side, step, origin + step / 2), {}, kinds, ends);
    };
    lattice.operator()<2>(16, 1, 0, 1.0f);
    lattice.operator()<2>(16, 1, -7, 2.0f);
    lattice.operator()<3>(6, 1, 0, 1.0f);
    lattice.operator()<3>(6, 1, -3, 2.0f);
}

// adversarial_test.cpp
TEST_F(vulkan_cpu_cases, lattices_at_exactly_the_radius) {
    auto lattice = [&]<int D>(int side, double step, double origin, float r) {
        SCOPED_TRACE("lattice side=" + std::to_string(side) + " step=" + std::to_string(step));
        every_grid<D>(lattice_points<float, D>(side, step, origin), r,
                      lattice_points<float, D>(side, step, origin + step / 2));
    };
    lattice.operator()<2>(16, 1, 3, 3.0f);
    lattice.operator()<2>(16, 0.5, -4, 1.0f);
    lattice.operator()<3>(6, 1, 5, 2.0f);
    lattice.operator()<3>(6, 0.25, -1, 0.5f);
}

TEST_F(vulkan_cpu_cases, degenerate_sets) {
    {
        SCOPED_TRACE("all points in one cell");
        every_grid<2>(uniform_points<float, 2>(100, -3, -2.9f, 73), 0.5f, uniform_points<float, 2>(30, -4, -2, 74));
    }
    {
        SCOPED_TRACE("duplicates");
        const auto base3 = uniform_points<float, 3>(80, 0, 3, 83);
        every_grid<3>(with_duplicates(base3, 3, 3), 0.6f, query_points<float, 3>(base3, 0.6, 40, {}, 84));
    }
    {
        SCOPED_TRACE("all points identical");
        every_grid<2>(with_duplicates(std::vector<float>{0, 0}, 2, 100), 1.0f, {0, 0, 1, 0, 1, 1});
    }
    {
        SCOPED_TRACE("plane z = -1");
        auto plane = uniform_points<float, 3>(400, -5, 5, 87);
        for (std::size_t i = 2; i < plane.size(); i += 3) plane[i] = -1.0f;
        every_grid<3>(plane, 1.0f, query_points<float, 3>(plane, 1.0, 40, {}, 88));
    }
    {
        SCOPED_TRACE("negative coordinates");
        const auto p2 = clustered_points<float, 2>(400, 3, 0.8, -50, -40, 93);
        every_grid<2>(p2, 0.4f, query_points<float, 2>(p2, 0.4, 60, {}, 94));
    }
}

TEST_F(vulkan_cpu_cases, points_on_cell_boundaries) {
    for (double cell : {1.0, 0.5, 0.25}) {
        SCOPED_TRACE("lattice of cell " + std::to_string(cell));
        every_grid<3>(on_cell_boundaries<float, 3>(200, cell, 10, 103), 1.0f,
                      on_cell_boundaries<float, 3>(50, cell / 2, 12, 104));
    }
}

TEST_F(vulkan_cpu_cases, far_outlier_float_2d) {
    // Outlier first and a neighbor of the outlier one float step (1) away on both axes.
    std::vector<float> p2;
    append_point<float, 2>(p2, -1e7);
    append_point<float, 2>(p2, -1e7 + 1);
    const auto rest = uniform_points<float, 2>(800, -5, 5, 114);
    p2.insert(p2.end(), rest.begin(), rest.end());
    every_grid<2>(p2, 1.5f, {-1e7f, -1e7f, 0, 0}, {}, {grid_kind::automatic, grid_kind::hashed}, {1.0});
}

TEST_F(vulkan_cpu_cases, tiny_inputs) {
    every_grid<2>({}, 0.5f, {0, 0});
    every_grid<2>({-4, 7}, 2.0f, {-4, 7, -2, 7, -1.9f, 7});
    every_grid<3>({1, 1, 1, 1, 1, 4}, 3.0f, {1, 1, 2.5});
}

TEST_F(vulkan_cpu_cases, hash_slot_collisions) {
    const auto sparse = sparse_cells<float, 2>(800, 0.5, 150, 143);
    every_grid<2>(sparse, 0.5f, query_points<float, 2>(sparse, 0.5, 50, {}, 144));
}

// periodic_test.cpp: boxes of exactly 2r, boxes that are not multiples of the cell, integer
// lattices in integer boxes, points on the faces and just outside.
template <int D>
std::vector<float> in_box(std::size_t n, const std::vector<double>& box, std::uint64_t seed) {
    auto pts = uniform_points<float, D>(n, 0, 1, seed);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const float len = float(box[i % D]);
        pts[i] = float(double(pts[i]) * box[i % D]);
        if (pts[i] >= len) pts[i] = std::nextafter(len, 0.0f);
    }
    return pts;
}

TEST_F(vulkan_cpu_cases, periodic_boxes) {
    auto box_case = [&]<int D>(const std::vector<double>& box_in_r, float r, std::size_t n, std::uint64_t seed) {
        grid_options base;
        for (int a = 0; a < D; ++a) base.periodic.push_back(box_in_r[a] * double(r));
        const auto pts = in_box<D>(n, base.periodic, seed);
        SCOPED_TRACE("box of " + std::to_string(box_in_r[0]) + "r");
        every_grid<D>(pts, r, query_points<float, D>(pts, r, 80, base.periodic, seed + 1), base,
                      {grid_kind::automatic});
    };
    box_case.operator()<3>({2, 2, 2}, 0.5f, 300, 62);
    for (const std::vector<double>& b : {std::vector<double>{2.5, 3.7, 2.0}, {3, 3, 3}, {7.3, 5.1, 10}})
        box_case.operator()<2>(b, 0.75f, 200, 64);
}

// mixed_periodic_test.cpp: boxes periodic on some axes only (0 on the open ones), among them
// exactly 2r, points spread past the box on the open axes, and two far outliers there.
TEST_F(vulkan_cpu_cases, periodic_on_some_axes) {
    auto box_case = [&]<int D>(const std::vector<double>& box_in_r, float r, std::size_t n, std::uint64_t seed) {
        grid_options base;
        for (int a = 0; a < D; ++a) base.periodic.push_back(box_in_r[a] * double(r));
        auto pts = uniform_points<float, D>(n, 0, 1, seed);
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const double len = base.periodic[i % D];
            pts[i] = len > 0 ? std::min(float(double(pts[i]) * len), std::nextafter(float(len), 0.0f))
                             : float((double(pts[i]) * 6 - 1) * double(r));
        }
        const auto queries = query_points<float, D>(pts, r, 80, base.periodic, seed + 1);
        for (float far : {-3e4f, 5e4f})
            for (int a = 0; a < D; ++a) pts.push_back(base.periodic[std::size_t(a)] > 0 ? float(r) : far * r);
        SCOPED_TRACE("box " + std::to_string(box_in_r[0]) + "r x " + std::to_string(box_in_r[1]) + "r");
        every_grid<D>(pts, r, queries, base, {grid_kind::automatic});
    };
    box_case.operator()<3>({2, 0, 2}, 0.5f, 300, 66);
    box_case.operator()<3>({0, 0, 4.5}, 0.5f, 300, 67);
    box_case.operator()<3>({3.7, 5.1, 0}, 0.5f, 300, 68);
    box_case.operator()<2>({0, 2.5}, 0.75f, 200, 69);
    box_case.operator()<2>({7.3, 0}, 0.75f, 200, 70);
}

TEST_F(vulkan_cpu_cases, periodic_lattices_and_faces) {
    auto lattice = [&]<int D>(double len, float r) {
        grid_options base;
        base.periodic.assign(D, len);
        SCOPED_TRACE("periodic lattice L=" + std::to_string(len));
        every_grid<D>(lattice_points<float, D>(int(len), 1.0), r, lattice_points<float, D>(int(len), 1.0, 0.5), base,
                      {grid_kind::automatic}, {1.0, 0.5, 0.25});
    };
    lattice.operator()<2>(9, 3.0f);
    lattice.operator()<3>(4, 2.0f);
    // Faces, the largest float below L, tiny negatives (v + L rounds to L), -0.
    std::vector<float> faces = {0, 0, 10, 6, std::nextafter(10.0f, 0.0f), std::nextafter(6.0f, 0.0f),
                                -1e-17f, -1e-17f, -0.0f, 3, 9.5f, 5.5f, 0.5f, 0.5f, 10, 0,
                                std::nextafter(10.0f, 0.0f), -1e-7f};
    grid_options base;
    base.periodic = {10, 6};
    every_grid<2>(faces, 1.0f, query_points<float, 2>(faces, 1.0, 30, base.periodic, 91), base,
                  {grid_kind::automatic}, {1.0, 0.25});
}

}  // namespace
}  // namespace frnn::vulkan::test
