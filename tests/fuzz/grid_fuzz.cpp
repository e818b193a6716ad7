// Differential fuzzing of the core: a grid built from the fuzzer's points, radius (or radii),
// box and options answers exactly as the brute-force oracle, at one and two threads; a build
// may refuse its input with frnn::error, which both thread counts must then do. Verlet lists
// over the same points, then over moved points, give the oracle's neighbors too.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <span>
#include <vector>

#include "frnn/brute_force.hpp"
#include "frnn/error.hpp"
#include "frnn/grid.hpp"
#include "frnn/verlet_lists.hpp"
#include "grid_case.hpp"

namespace frnn::fuzz {
namespace {

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

/// Whether Verlet lists give the oracle's neighbors at `at`.
template <class T, int D>
bool verlet_matches(const verlet_lists<T, D>& v, const std::vector<T>& at, T radius, std::span<const double> box) {
    const csr<T> want = brute_force_lists<T, D>(at, at, radius, true, box);
    std::vector<std::uint32_t> row;
    for (std::size_t i = 0; i < at.size() / D; ++i) {
        row.clear();
        v.for_each_neighbor(i, [&](std::uint32_t j, T) { row.push_back(j); });
        if (!std::equal(row.begin(), row.end(), want.row(i).begin(), want.row(i).end())) return false;
    }
    return true;
}

/// Verlet lists at the points, then at the moved points (kept or rebuilt); a refused update
/// leaves the lists of the points before it.
template <class T, int D>
void check_verlet_lists(const grid_case<T, D>& c) {
    const std::span<const double> box(c.options.periodic);
    std::optional<verlet_lists<T, D>> v;
    try {
        v.emplace(c.radius, c.skin, c.options);
        v->update(c.points);
    } catch (const error&) {
        return;
    }
    if (!verlet_matches(*v, c.points, c.radius, box)) fail("Verlet lists differ from the brute-force oracle");
    std::vector<T> moved = c.points;
    for (std::size_t i = 0; i < moved.size(); ++i) moved[i] += c.moves[i];
    try {
        v->update(moved);
    } catch (const error&) {
        if (!verlet_matches(*v, c.points, c.radius, box)) fail("a refused Verlet update changed the lists");
        return;
    }
    if (!verlet_matches(*v, moved, c.radius, box)) fail("Verlet lists after a move differ from the brute-force oracle");
}

template <class T, int D>
void run(fuzz_input& in) {
    const grid_case<T, D> c = decode_grid_case<T, D>(in);
    if (std::getenv("FRNN_FUZZ_PRINT")) print(c);
    const auto& points = c.points;
    const auto& radii = c.radii;
    const auto& queries = c.queries;
    const auto& query_radii = c.query_radii;
    const auto& o = c.options;
    const auto radius = c.radius;
    const bool own_radii = c.per_point;
    const std::size_t n = points.size() / D;

    const auto one = build<T, D>(points, radius, radii, o, 1);
    const auto two = build<T, D>(points, radius, radii, o, 2);
    if (one.has_value() != two.has_value()) fail("a build refused its input at one thread count only");
    if (!one) return;
    reached_checks();

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
        if (!half_rows_match(lists, one->neighbor_lists(half)))
            fail("half rows differ from the full rows' entries past the point");
    }

    // Query points of their own (anywhere, far ones included), with their own radii on a
    // grid of radii.
    std::optional<csr<T>> answer;
    try {
        answer = own_radii ? one->query(queries, query_radii, lo) : one->query(queries, lo);
    } catch (const error&) {
        return;  // a non-finite query point, or a query radius that is not positive or too large
    }
    const csr<T> want = own_radii ? brute_force_lists<T, D>(queries, query_radii, points, radii, o.rule, grid_radius, false, box)
                                  : brute_force_lists<T, D>(queries, points, radius, false, box);
    if (!same(*answer, want, true)) fail("query rows differ from the brute-force oracle");

    // The k nearest, ordered by squared distance in search space (ties by index).
    const distance_test<T, D> test(grid_radius, one->search_scale(), box);
    auto from = [&](const std::vector<T>& xs) {
        return [&](std::size_t i, std::uint32_t j) { return test.scaled_distance_squared(&xs[i * D], &points[std::size_t(j) * D]); };
    };
    if (!same(one->nearest(c.k, lo), nearest_rows(lists, c.k, from(points)), true))
        fail("k nearest differ from the brute-force oracle's");
    const csr<T> nearest_to_queries =
        own_radii ? one->query_nearest(queries, query_radii, c.k, lo) : one->query_nearest(queries, c.k, lo);
    if (!same(nearest_to_queries, nearest_rows(want, c.k, from(queries)), true))
        fail("k nearest of query points differ from the brute-force oracle's");
    if (!own_radii) check_verlet_lists(c);
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
