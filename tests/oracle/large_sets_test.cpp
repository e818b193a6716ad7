// Sets too large for the brute-force oracle on every point: the build's scatter of input in
// random order changes strategy beyond the last-level cache (records of several MiB), so these
// sets check the structure whole (permutation, stable cells, thread invariance) and the
// neighbors of a sample of points against the oracle.
#include <gtest/gtest.h>

#include <random>

#include "oracle/oracle_check.hpp"
#include "oracle/point_sets.hpp"

namespace frnn::test {
namespace {

template <class T, int D>
void large_case(const std::vector<T>& pts, T r, grid_options opt, std::uint64_t seed) {
    const std::size_t n = pts.size() / D;
    // A sample of the points as queries: the oracle scans all points for each.
    std::mt19937_64 rng(seed);
    std::vector<std::uint32_t> sample(300);
    for (auto& i : sample) i = std::uint32_t(rng() % n);
    std::vector<T> qs;
    for (auto i : sample) qs.insert(qs.end(), pts.begin() + std::ptrdiff_t(i) * D, pts.begin() + std::ptrdiff_t(i + 1) * D);
    const rows_t<T> want = reference_rows<T, D>(qs, pts, r, false, opt.periodic);

    opt.threads = 1;
    const grid<T, D> one(pts, r, opt);
    ASSERT_EQ((check_structure<T, D>(one, pts)), "");
    for (int threads : {2, 3}) {
        opt.threads = threads;
        const grid<T, D> g(pts, r, opt);
        ASSERT_TRUE(std::equal(g.sorted_to_original().begin(), g.sorted_to_original().end(),
                               one.sorted_to_original().begin()))
            << threads << " threads: another order than at 1 thread";
    }
    list_options o;
    o.distances = true;
    EXPECT_EQ(compare_csr<T>(one.query(qs, o), want, true, row_order::none), "");
    const auto counts = one.count_neighbors();
    for (std::size_t q = 0; q < sample.size(); ++q) {
        std::size_t others = 0;
        for (const auto& e : want[q]) others += e.j != sample[q];
        ASSERT_EQ(counts[sample[q]], others) << "point " << sample[q];
    }
}

// 450,000 points of 16-byte records (7.2 MB), uniform: the uniform grid.
TEST(OracleLarge, UniformFloat3D) {
    large_case<float, 3>(uniform_points<float, 3>(450000, 0, 76, 301), 1.0f, {}, 302);
}

// Clusters: uneven buckets, empty space; the automatic choice and the hashed grid.
TEST(OracleLarge, ClusteredFloat3D) {
    const auto pts = clustered_points<float, 3>(450000, 40, 3.0, -100, 100, 303);
    large_case<float, 3>(pts, 0.5f, {}, 304);
    grid_options hashed;
    hashed.kind = grid_kind::hashed;
    large_case<float, 3>(pts, 0.5f, hashed, 305);
}

// 400,000 points of 24-byte records in a periodic box.
TEST(OracleLarge, PeriodicDouble2D) {
    grid_options opt;
    opt.periodic = {600, 500};
    auto pts = uniform_points<double, 2>(400000, 0, 1, 306);
    for (std::size_t i = 0; i < pts.size(); ++i) pts[i] *= opt.periodic[i % 2];
    large_case<double, 2>(pts, 1.0, opt, 307);
}

// 600,000 points of 12-byte records in the plane.
TEST(OracleLarge, UniformFloat2D) {
    large_case<float, 2>(uniform_points<float, 2>(600000, 0, 800, 308), 1.0f, {}, 309);
}

// Adversarial for the buckets: two crowded spots far apart, the input alternating between
// them (no point in the cell of the one before). The first spot is one cell: one bucket
// holds half the points.
// Too many pairs for the oracle: the structure only, at 1 to 3 threads.
TEST(OracleLarge, TwoCrowdedSpotsAlternating) {
    std::vector<float> pts(450000 * 3);
    std::mt19937_64 rng(310);
    std::uniform_real_distribution<float> u(0.0f, 0.5f);
    for (std::size_t i = 0; i < pts.size(); ++i) pts[i] = u(rng) + ((i / 3) % 2 ? 40.0f : 0.0f);
    std::vector<std::uint32_t> first;
    for (int threads : {1, 2, 3}) {
        grid_options opt;
        opt.threads = threads;
        const grid<float, 3> g(pts, 1.0f, opt);
        ASSERT_EQ((check_structure<float, 3>(g, pts)), "") << threads << " threads";
        ASSERT_LE(g.occupied_slots(), 16u);
        const auto perm = g.sorted_to_original();
        if (first.empty()) first.assign(perm.begin(), perm.end());
        ASSERT_TRUE(std::equal(first.begin(), first.end(), perm.begin())) << threads << " threads";
    }
}

}  // namespace
}  // namespace frnn::test
