// Differential fuzzing of the core: a grid built from the fuzzer's points, radius (or radii),
// box and options answers exactly as the brute-force oracle, at one and two threads; a build
// may refuse its input with frnn::error, which both thread counts must then do.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <span>
#include <vector>

#include "frnn/brute_force.hpp"
#include "frnn/error.hpp"
#include "frnn/grid.hpp"
#include "fuzz_input.hpp"

namespace frnn::fuzz {
namespace {

template <class T>
bool same(const csr<T>& a, const csr<T>& b, bool distances) {
    if (a.offsets.size() != b.offsets.size() || a.indices.size() != b.indices.size()) return false;
    if (!std::equal(a.offsets.begin(), a.offsets.end(), b.offsets.begin())) return false;
    if (!std::equal(a.indices.begin(), a.indices.end(), b.indices.begin())) return false;
    // Distances bit for bit: the oracle computes them with the grid's formula.
    return !distances || (a.distances.size() == b.distances.size() &&
                          (a.distances.empty() ||
                           std::memcmp(a.distances.data(), b.distances.data(), a.distances.size() * sizeof(T)) == 0));
}

template <class T, int D>
std::optional<grid<T, D>> build(std::span<const T> points, T radius, std::span<const T> radii, grid_options o, int threads) {
    o.threads = threads;
    try {
        if (radii.empty()) return grid<T, D>(points, radius, o);
        return grid<T, D>(points, radii, o);
    } catch (const error&) {
        return std::nullopt;
    }
}

/// The decoded case, for a person reading a finding (FRNN_FUZZ_PRINT=1).
template <class T, int D>
void print(const std::vector<T>& points, T radius, const std::vector<T>& radii, const grid_options& o) {
    std::fprintf(stderr, "%s %dD, %zu points, kind %d, rule %d, cell %.17g, radius %.17g\n", sizeof(T) == 4 ? "float" : "double",
                D, points.size() / D, int(o.kind), int(o.rule), o.cell_size, double(radius));
    for (double b : o.periodic) std::fprintf(stderr, "  box %.17g\n", b);
    for (std::size_t i = 0; i < points.size() / D; ++i) {
        std::fprintf(stderr, "  %zu:", i);
        for (int a = 0; a < D; ++a) std::fprintf(stderr, " %.17g", double(points[i * D + a]));
        if (!radii.empty()) std::fprintf(stderr, "  r %.17g", double(radii[i]));
        std::fprintf(stderr, "\n");
    }
}

template <class T, int D>
void run(fuzz_input& in) {
    const std::size_t n = in.below(40);
    const T scale = in.scale<T>(std::is_same_v<T, float> ? 130 : 1030);
    const bool own_radii = in.flag();
    grid_options o;
    o.kind = grid_kind(in.below(3));
    o.rule = in.flag() ? radius_rule::symmetric : radius_rule::gather;
    const T radius = in.value<T>(scale);
    std::vector<T> radii;
    if (own_radii)
        for (std::size_t i = 0; i < n; ++i) radii.push_back(in.value<T>(scale));
    if (in.flag())
        for (int a = 0; a < D; ++a) o.periodic.push_back(in.flag() ? 0.0 : double(in.value<T>(scale)));
    if (!own_radii) {
        const double fraction[] = {0, 1, 0.5, 1.0 / 3, 0.25};
        o.cell_size = fraction[in.below(5)] * double(radius);
    }
    std::vector<T> points(n * D);
    for (auto& v : points) v = in.value<T>(scale);
    if (std::getenv("FRNN_FUZZ_PRINT")) print<T, D>(points, radius, radii, o);

    const auto one = build<T, D>(points, radius, radii, o, 1);
    const auto two = build<T, D>(points, radius, radii, o, 2);
    if (one.has_value() != two.has_value()) fail("a build refused its input at one thread count only");
    if (!one) return;

    const std::span<const double> box(o.periodic);
    const T grid_radius = one->radius();
    const csr<T> expected = own_radii ? brute_force_lists<T, D>(points, radii, points, radii, o.rule, grid_radius, true, box)
                                      : brute_force_lists<T, D>(points, points, radius, true, box);
    list_options lo;
    lo.distances = true;
    lo.order = row_order::index;
    const csr<T> lists = one->neighbor_lists(lo);
    if (!same(lists, expected, true)) fail("lists differ from the brute-force oracle");
    if (!same(two->neighbor_lists(lo), lists, true)) fail("lists differ between one and two threads");

    // Counts are the row sizes; half rows the entries past the point's own index.
    const auto counts = one->count_neighbors();
    for (std::size_t i = 0; i < n; ++i)
        if (counts[i] != lists.offsets[i + 1] - lists.offsets[i]) fail("a count differs from its row's size");
    if (!own_radii || o.rule == radius_rule::symmetric) {
        list_options half;
        half.half = true;
        half.order = row_order::index;
        const csr<T> h = one->neighbor_lists(half);
        for (std::size_t i = 0; i < n; ++i) {
            std::vector<std::uint32_t> want;
            for (auto k = lists.offsets[i]; k < lists.offsets[i + 1]; ++k)
                if (lists.indices[k] > i) want.push_back(lists.indices[k]);
            if (h.offsets[i + 1] - h.offsets[i] != want.size() ||
                !std::equal(want.begin(), want.end(), h.indices.begin() + std::ptrdiff_t(h.offsets[i])))
                fail("half rows differ from the full rows' entries past the point");
        }
    }

    // Query points of their own (anywhere, far ones included), with their own radii on a
    // grid of radii.
    const std::size_t m = in.below(8);
    std::vector<T> queries(m * D), query_radii;
    for (auto& v : queries) v = in.value<T>(scale);
    for (std::size_t q = 0; own_radii && q < m; ++q) query_radii.push_back(in.value<T>(scale));
    std::optional<csr<T>> answer;
    try {
        answer = own_radii ? one->query(queries, query_radii, lo) : one->query(queries, lo);
    } catch (const error&) {
        return;  // a non-finite query point, or a query radius that is not positive or too large
    }
    const csr<T> want = own_radii ? brute_force_lists<T, D>(queries, query_radii, points, radii, o.rule, grid_radius, false, box)
                                  : brute_force_lists<T, D>(queries, points, radius, false, box);
    if (!same(*answer, want, true)) fail("query rows differ from the brute-force oracle");
}

}  // namespace
}  // namespace frnn::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    frnn::fuzz::fuzz_input in(data, size);
    switch (in.below(4)) {
        case 0: frnn::fuzz::run<float, 2>(in); break;
        case 1: frnn::fuzz::run<float, 3>(in); break;
        case 2: frnn::fuzz::run<double, 2>(in); break;
        default: frnn::fuzz::run<double, 3>(in); break;
    }
    return 0;
}
