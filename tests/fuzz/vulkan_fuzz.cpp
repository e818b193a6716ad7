// Differential fuzzing of the Vulkan backend on the grid harness's cases (grid_case.hpp, the
// same corpus): a device grid built from float points answers exactly as the brute-force
// oracle, distances bit for bit (lists, counts, half rows, queries); double points go through
// vulkan::search (float candidates, double decisions) and must give the oracle's pairs. The
// device may refuse an input with frnn::error (device limits, or a rounding bound above the
// radius for double input), and refuses a radius per point. Without a Vulkan device the
// harness exits with code 77 (the replay test's skip code).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "frnn/brute_force.hpp"
#include "frnn/error.hpp"
#include "frnn/vulkan.hpp"
#include "grid_case.hpp"

namespace frnn::fuzz {
namespace {

vulkan::context& device() {
    static std::unique_ptr<vulkan::context> ctx = [] {
        try {
            return std::make_unique<vulkan::context>();
        } catch (const error& e) {
            std::fprintf(stderr, "no Vulkan device (%s): skipped\n", e.what());
            std::exit(77);
        }
    }();
    return *ctx;
}

list_options by_index() {
    list_options lo;
    lo.distances = true;
    lo.order = row_order::index;
    return lo;
}

void float_case(const auto& c, auto dim) {
    constexpr int D = decltype(dim)::value;
    if (c.per_point) return;  // the device has one radius: a grid of radii is the CPU's alone
    const auto& points = c.points;
    const auto& queries = c.queries;
    const auto radius = c.radius;
    const std::size_t n = points.size() / D;
    vulkan::grid<D> g(device());
    try {
        g.build(points, radius, c.options);
    } catch (const error&) {
        return;
    }
    reached_checks();
    const std::span<const double> box(c.options.periodic);
    const csr<float> lists = g.neighbor_lists(by_index());
    if (!same(lists, brute_force_lists<float, D>(points, points, radius, true, box), true))
        fail("device lists differ from the brute-force oracle");
    const auto counts = g.count_neighbors();
    for (std::size_t i = 0; i < n; ++i)
        if (counts[i] != lists.offsets[i + 1] - lists.offsets[i]) fail("a device count differs from its row's size");
    list_options half;
    half.half = true;
    half.order = row_order::index;
    if (!half_rows_match(lists, g.neighbor_lists(half)))
        fail("device half rows differ from the full rows' entries past the point");
    std::optional<csr<float>> answer;
    try {
        answer = g.query(queries, by_index());
    } catch (const error&) {
        return;  // a non-finite query point
    }
    const csr<float> want = brute_force_lists<float, D>(queries, points, radius, false, box);
    if (!same(*answer, want, true)) fail("device query rows differ from the brute-force oracle");

    // The k nearest, ordered by squared distance in search space (ties by index).
    const distance_test<float, D> test(radius, g.search_scale(), box);
    auto from = [&](const std::vector<float>& xs) {
        return [&](std::size_t i, std::uint32_t j) { return test.scaled_distance_squared(&xs[i * D], &points[std::size_t(j) * D]); };
    };
    if (!same(g.nearest(c.k, by_index()), nearest_rows(lists, c.k, from(points)), true))
        fail("device k nearest differ from the brute-force oracle's");
    if (!same(g.query_nearest(queries, c.k, by_index()), nearest_rows(want, c.k, from(queries)), true))
        fail("device k nearest of query points differ from the brute-force oracle's");
}

void double_case(const auto& c, auto dim) {
    constexpr int D = decltype(dim)::value;
    if (c.per_point) return;  // one radius on the device
    const auto& points = c.points;
    const auto& queries = c.queries;
    const auto radius = c.radius;
    const std::span<const double> box(c.options.periodic);
    for (bool own : {true, false}) {
        if (!own && queries.empty()) continue;  // the search would list the points' own rows
        std::optional<csr<double>> got;
        try {
            got = vulkan::search(device(), points, D, radius, c.options, by_index(), own ? std::span<const double>() : queries).lists;
        } catch (const error&) {
            continue;
        }
        // The double search decides with the plain squared radius: extreme radii, which the
        // grid and the oracle search scaled, are the CPU's alone (the radius is valid here:
        // the search took it).
        try {
            if (search_scale<double>(radius, largest_magnitude<double>(points, box)) != 1) return;
        } catch (const error&) {
            return;
        }
        const csr<double> want = own ? brute_force_lists<double, D>(points, points, radius, true, box)
                                     : brute_force_lists<double, D>(queries, points, radius, false, box);
        if (!same(*got, want, true)) fail("the device's double search differs from the brute-force oracle");
        reached_checks();
    }
}

}  // namespace
}  // namespace frnn::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace frnn::fuzz;
    fuzz_input in(data, size);
    const std::size_t which = in.below(4);
    auto run = [&](auto value, auto dim) {
        using T = decltype(value);
        constexpr int D = decltype(dim)::value;
        const auto c = decode_grid_case<T, D>(in);
        if (std::getenv("FRNN_FUZZ_PRINT")) print(c);
        if constexpr (std::is_same_v<T, float>) float_case(c, dim);
        else double_case(c, dim);
    };
    using two = std::integral_constant<int, 2>;
    using three = std::integral_constant<int, 3>;
    switch (which) {
        case 0: run(float(), two()); break;
        case 1: run(float(), three()); break;
        case 2: run(double(), two()); break;
        default: run(double(), three()); break;
    }
    return 0;
}
