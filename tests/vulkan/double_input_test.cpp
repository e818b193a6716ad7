// Double input on the device (issue 23.1): search() over doubles answers in double, the CPU's
// pairs and distances exactly, or refuses with the backend and the precision named. Checked with
// the CPU oracle's reference rows and compare_csr, in double.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "oracle/point_sets.hpp"
#include "oracle_check.hpp"
#include "vulkan_env.hpp"

namespace frnn::vulkan::test {
namespace {

using namespace frnn::test;

class vulkan_double : public vulkan_test {
protected:
    // Every list option of the caller's numbering, k nearest and queries, against the oracle.
    template <int D>
    void check(const std::vector<double>& pts, double r, const std::vector<double>& queries,
               const grid_options& o = {}) {
        const std::vector<std::uint32_t> id = [&] {
            std::vector<std::uint32_t> v(pts.size() / D);
            for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::uint32_t(i);
            return v;
        }();
        const auto ref = reference_rows<double, D>(pts, pts, r, true, o.periodic);
        for (const list_options& l : all_list_options()) {
            if (l.space == index_space::sorted) continue;
            const auto got = search(ctx(), std::span<const double>(pts), D, r, o, l);
            const auto want = expected_self_rows<double>(ref, id, id, l);
            const std::string msg = compare_csr<double>(got.lists, want, l.distances, l.order);
            ASSERT_EQ(msg, "") << describe(l);
        }
        list_options l;
        l.distances = true;
        for (std::size_t k : {std::size_t(1), std::size_t(3)}) {
            const auto got = search(ctx(), std::span<const double>(pts), D, r, o, l, {}, k);
            ASSERT_EQ(compare_csr<double>(got.lists, expected_self_rows<double>(ref, id, id, l), true,
                                          row_order::distance, k),
                      "")
                << "nearest " << k;
        }
        const auto qref = reference_rows<double, D>(queries, pts, r, false, o.periodic);
        for (std::size_t k : {std::size_t(0), std::size_t(2)}) {
            const auto got = search(ctx(), std::span<const double>(pts), D, r, o, l, queries, k);
            ASSERT_EQ(compare_csr<double>(got.lists, qref, true, row_order::index, k), "") << "queries k=" << k;
        }
    }

    // The call fails with frnn::error naming the backend, the precision and `detail`.
    void refused(const std::function<void()>& call, const std::string& detail) {
        try {
            call();
            ADD_FAILURE() << "no error; expected one about " << detail;
        } catch (const frnn::error& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find("vulkan"), std::string::npos) << m;
            EXPECT_NE(m.find("double"), std::string::npos) << m;
            EXPECT_NE(m.find("float"), std::string::npos) << m;
            EXPECT_NE(m.find(detail), std::string::npos) << m;
        }
    }
};

TEST_F(vulkan_double, huge_coordinates_and_radius) {
    // |x| ~ 1e30, r = 5e29: converted to float, d * d overflows and every pair passed.
    const auto pts = uniform_points<double, 3>(300, -1e30, 1e30, 41);
    const auto got = search(ctx(), std::span<const double>(pts), 3, 5e29);
    EXPECT_LT(got.lists.size(), 300u * 299u / 2);
    check<3>(pts, 5e29, uniform_points<double, 3>(40, -1.2e30, 1.2e30, 42));
    check<2>(uniform_points<double, 2>(300, -3e38, 3e38, 43), 4e37, uniform_points<double, 2>(30, -3e38, 3e38, 44));
}

TEST_F(vulkan_double, radii_whose_float_square_leaves_the_range) {
    // The float candidate search runs with the search scale (r^2 overflows or underflows in
    // float); the answer is still the double oracle's. Radii beyond float are refused.
    check<3>(uniform_points<double, 3>(200, -3e35, 3e35, 53), 1e35, uniform_points<double, 3>(20, -3e35, 3e35, 54));
    check<2>(uniform_points<double, 2>(200, -3e-30, 3e-30, 55), 1e-30,
             uniform_points<double, 2>(20, -3e-30, 3e-30, 56));
    const auto pts = uniform_points<double, 3>(20, 0, 5, 57);
    refused([&] { search(ctx(), std::span<const double>(pts), 3, 1e300); }, "beyond the float range");
}

TEST_F(vulkan_double, ties_decided_in_double) {
    // Spacing 0.1 is not a float: pairs at exactly 2 and 3 steps are decided by double rounding.
    const auto l3 = lattice_points<double, 3>(7, 0.1, -0.3);
    check<3>(l3, 0.2, lattice_points<double, 3>(4, 0.1, -0.25));
    check<3>(l3, std::sqrt(0.02), lattice_points<double, 3>(3, 0.1, 0.05));
    const auto l2 = lattice_points<double, 2>(20, 0.3, 1e3);
    check<2>(l2, 0.9, lattice_points<double, 2>(5, 0.3, 1e3 + 0.15));
}

TEST_F(vulkan_double, random_and_periodic_sets) {
    const auto c3 = clustered_points<double, 3>(600, 5, 1.0, -8, 8, 45);
    check<3>(c3, 1.0, query_points<double, 3>(c3, 1.0, 60, {}, 46));
    grid_options hashed;
    hashed.kind = grid_kind::hashed;
    hashed.cell_size = 0.5;
    check<3>(c3, 1.0, query_points<double, 3>(c3, 1.0, 60, {}, 47), hashed);
    grid_options periodic;
    periodic.periodic = {7.3, 5.1};
    auto p2 = uniform_points<double, 2>(500, -2, 9, 48);  // some outside the box, wrapped
    check<2>(p2, 1.0, query_points<double, 2>(p2, 1.0, 40, periodic.periodic, 49), periodic);
    periodic.periodic = {0, 5.1};  // periodic in y only
    check<2>(p2, 1.0, query_points<double, 2>(p2, 1.0, 40, periodic.periodic, 50), periodic);
    // Points and queries 10^9 boxes out: wrapped in double before the float copy, so the
    // rounding bound is the box's and the search stays on the device.
    periodic.periodic = {7.3, 5.1};
    auto far = uniform_points<double, 2>(500, 0, 5, 53);
    auto far_queries = query_points<double, 2>(far, 1.0, 40, periodic.periodic, 54);
    for (std::size_t i = 0; i < 100; ++i) far[i] += 1e9 * periodic.periodic[i % 2] * (i % 4 < 2 ? 1 : -1);
    for (std::size_t i = 0; i < 20; ++i) far_queries[i] -= 1e9 * periodic.periodic[i % 2];
    check<2>(far, 1.0, far_queries, periodic);
}

TEST_F(vulkan_double, refusals_name_the_backend_and_the_precision) {
    std::vector<double> pts = uniform_points<double, 3>(20, 0, 5, 50);
    pts[3 * 3 + 1] = 1e39;
    refused([&] { search(ctx(), std::span<const double>(pts), 3, 1.0); }, "data point 3 has coordinate");
    // At 1e7 float steps are 1: a radius of 1e-3 cannot be decided from float candidates.
    auto far = uniform_points<double, 3>(20, 1e7, 1e7 + 1, 51);
    refused([&] { search(ctx(), std::span<const double>(far), 3, 1e-3); }, "more than the radius");
    list_options sorted;
    sorted.space = index_space::sorted;
    refused([&] { search(ctx(), std::span<const double>(far), 3, 1.0, {}, sorted); }, "index_space::sorted");
    grid_options box;
    box.periodic = {2, 2, 2};  // exactly 2r: the widened float radius does not fit
    const auto in_box = uniform_points<double, 3>(20, 0, 2, 52);
    refused([&] { search(ctx(), std::span<const double>(in_box), 3, 1.0, box); }, "widened float radius");
    pts[3 * 3 + 1] = std::nan("");
    refused([&] { search(ctx(), std::span<const double>(pts), 3, 1.0); }, "point 3 has a non-finite");
}

}  // namespace
}  // namespace frnn::vulkan::test
