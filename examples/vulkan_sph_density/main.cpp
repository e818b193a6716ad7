// SPH density on a Vulkan device with a user shader that loops over neighbors through
// frnn/grid.glsl, checked against the same sum on the CPU with frnn::grid.
// Usage: vulkan_sph_density [points per axis, default 24]. Exit code 0 when they agree, 1 when
// they differ, 2 on an error, 77 when there is no Vulkan device.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <vector>

#include "frnn/grid.hpp"
#include "frnn/vulkan.hpp"
#include "sph_density_spirv.hpp"

int main(int argc, char** argv) try {
    const int side = argc > 1 ? std::atoi(argv[1]) : 24;
    const float spacing = 1.0f, h = 2.0f, mass = 1.0f;
    // Jittered lattice: the uniform-density fluid of SPH.
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<float> jitter(-0.1f, 0.1f);
    std::vector<float> pos;
    for (int z = 0; z < side; ++z)
        for (int y = 0; y < side; ++y)
            for (int x = 0; x < side; ++x)
                for (int v : {x, y, z}) pos.push_back(v * spacing + jitter(rng));
    const std::size_t n = pos.size() / 3;

    std::unique_ptr<frnn::vulkan::context> device;
    try {
        device = std::make_unique<frnn::vulkan::context>();
    } catch (const frnn::error& e) {
        std::fprintf(stderr, "vulkan_sph_density: skipped, no Vulkan device: %s\n", e.what());
        return 77;
    }
    frnn::vulkan::context& ctx = *device;
    frnn::vulkan::grid<3> g(ctx);
    g.build(pos, h);
    frnn::vulkan::device_buffer density(ctx, n * sizeof(float), "densities");
    frnn::vulkan::kernel sph(ctx, sph_density_spirv(), 1, 8);
    const float push[2] = {mass, h};
    const frnn::vulkan::buffer_view out[] = {density.view()};
    sph.run(g, out, (n + 63) / 64, std::as_bytes(std::span(push)));
    const auto rho = density.download_as<float>();

    // The same sum on the CPU, in double.
    frnn::grid<float, 3> cpu(pos, h);
    const double poly6 = 315.0 / (64.0 * M_PI * std::pow(double(h), 9));
    double worst = 0;
    for (std::size_t i = 0; i < n; ++i) {
        double sum = std::pow(double(h) * h, 3);  // the particle itself
        cpu.for_each_neighbor(i, [&](std::uint32_t, float d2) { sum += std::pow(double(h) * h - d2, 3); });
        const double expected = mass * poly6 * sum;
        worst = std::max(worst, std::abs(rho[i] - expected) / expected);
    }
    std::printf("%zu particles on %s: max relative density difference GPU vs CPU %.2e\n", n,
                ctx.info().name.c_str(), worst);
    return worst < 1e-4 ? 0 : 1;
} catch (const std::exception& e) {
    std::fprintf(stderr, "vulkan_sph_density: %s\n", e.what());
    return 2;
}
