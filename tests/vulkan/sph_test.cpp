// A user shader (examples/vulkan_sph_density/sph_density.comp) that loops over neighbors with
// frnn/grid.glsl: SPH densities against the same sum on the CPU, reproducible run to run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "frnn/brute_force.hpp"
#include "sph_density_spirv.hpp"
#include "vulkan_env.hpp"

namespace frnn::vulkan::test {
namespace {

class vulkan_user_kernel : public vulkan_test {};

TEST_F(vulkan_user_kernel, sph_density_matches_cpu) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 12.0f);
    std::vector<float> pos(3000 * 3);
    for (auto& v : pos) v = u(rng);
    const std::size_t n = pos.size() / 3;
    const float h = 1.3f, mass = 0.5f;
    // Uniform, hashed and periodic grids: the kernel is specialized for each.
    for (int variant = 0; variant < 3; ++variant) {
        grid_options go;
        go.kind = variant == 1 ? grid_kind::hashed : grid_kind::uniform;
        if (variant == 2) go.periodic = {12, 12, 12};
        grid<3> g(ctx());
        g.build(pos, h, go);
        device_buffer density(ctx(), n * sizeof(float), "densities");
        kernel sph(ctx(), sph_density_spirv(), 1, 8);
        const float push[2] = {mass, h};
        const buffer_view out[] = {density.view()};
        // More groups than needed: the shader must ignore invocations past the last point.
        sph.run(g, out, n / 64 + 2, std::as_bytes(std::span(push)));
        const auto rho = density.download_as<float>();
        sph.run(g, out, n / 64 + 2, std::as_bytes(std::span(push)));
        EXPECT_EQ(density.download_as<float>(), rho) << "densities differ between two runs";

        const auto ref = brute_force_lists<float, 3>(pos, pos, h, false, go.periodic);  // self included
        const double poly6 = 315.0 / (64.0 * M_PI * std::pow(double(h), 9));
        for (std::size_t i = 0; i < n; ++i) {
            double sum = 0;
            for (auto k = ref.offsets[i]; k < ref.offsets[i + 1]; ++k) {
                const double d = ref.distances[k];
                sum += std::pow(double(h) * h - d * d, 3);
            }
            const double expected = mass * poly6 * sum;
            ASSERT_NEAR(rho[i], expected, 1e-4 * expected) << "particle " << i << " variant " << variant;
        }
    }
}

TEST_F(vulkan_user_kernel, split_dispatch_uses_frnn_invocation_index) {
    // Rows of 2 workgroups: frnn_invocation_index() must number invocations across rows.
    context_options o = test_options();
    o.max_groups_per_row = 2;
    context split(o);
    std::mt19937_64 rng(8);
    std::uniform_real_distribution<float> u(0.0f, 8.0f);
    std::vector<float> pos(700 * 3);
    for (auto& v : pos) v = u(rng);
    const float push[2] = {1.0f, 1.2f};
    auto densities = [&](context& c) {
        grid<3> g(c);
        g.build(pos, 1.2f);
        device_buffer out(c, 700 * sizeof(float));
        kernel sph(c, sph_density_spirv(), 1, 8);
        const buffer_view views[] = {out.view()};
        sph.run(g, views, 700 / 64 + 1, std::as_bytes(std::span(push)));  // 11 groups: 6 rows
        return out.download_as<float>();
    };
    const auto a = densities(split), b = densities(ctx());
    EXPECT_EQ(a, b);
    EXPECT_GT(*std::min_element(a.begin(), a.end()), 0.0f);  // every particle written
}

TEST_F(vulkan_user_kernel, rejects_wrong_use) {
    const std::vector<std::uint32_t> garbage{1, 2, 3};
    EXPECT_THROW(kernel(ctx(), garbage, 1), frnn::error);
    kernel sph(ctx(), sph_density_spirv(), 1, 8);
    grid<3> g(ctx());
    g.build(std::vector<float>{0, 0, 0, 1, 0, 0}, 1.5f);
    EXPECT_THROW(sph.run(g, std::span<const buffer_view>(), 1), frnn::error);  // one buffer missing
    // A binding beyond the device limit fails while recording; the context stays usable.
    device_buffer out(ctx(), 2 * sizeof(float));
    buffer_view too_big = out.view();
    too_big.size = ctx().info().max_storage_buffer_range + 4;
    EXPECT_THROW(sph.run(g, std::span<const buffer_view>(&too_big, 1), 1), frnn::error);
    const float push[2] = {1.0f, 1.5f};
    const buffer_view ok = out.view();
    sph.run(g, std::span<const buffer_view>(&ok, 1), 1, std::as_bytes(std::span(push)));
    const auto rho = out.download_as<float>();
    EXPECT_GT(rho[0], 0.0f);
    EXPECT_EQ(rho[0], rho[1]);  // two points at distance 1: the same density
}

}  // namespace
}  // namespace frnn::vulkan::test
