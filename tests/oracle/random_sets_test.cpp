// Random point sets (uniform, clustered; 2D, 3D; float, double) on every grid kind and cell
// size, compared path by path with the brute-force oracle.
#include <gtest/gtest.h>

#include "oracle/oracle_check.hpp"
#include "oracle/point_sets.hpp"

namespace frnn::test {
namespace {

constexpr grid_kind kinds[] = {grid_kind::automatic, grid_kind::uniform, grid_kind::hashed};
constexpr double cell_fractions[] = {1.0, 1.0 / 2, 1.0 / 3, 1.0 / 4};

// Radius and sizes give 20-40 neighbors per point: enough pairs, fast oracle.
template <class T, int D>
void run_all_kinds_and_cells(const std::vector<T>& pts, T r, std::uint64_t seed) {
    check_kinds_and_cells<T, D>(pts, r, query_points<T, D>(pts, r, 150, {}, seed), {1.0, 1.0 / 2, 1.0 / 3, 1.0 / 4});
}

template <class T, int D>
void uniform_case(std::uint64_t seed) {
    const std::size_t n = 500;
    const T r = D == 2 ? T(1) : T(1.5);
    run_all_kinds_and_cells<T, D>(uniform_points<T, D>(n, 0, D == 2 ? 10 : 8, seed), r, seed + 1);
}

template <class T, int D>
void clustered_case(std::uint64_t seed) {
    const std::size_t n = 500;
    // Bounding box about 20 wide: even r/4 cells stay a small dense grid in 3D.
    const T r = D == 2 ? T(0.6) : T(1);
    run_all_kinds_and_cells<T, D>(clustered_points<T, D>(n, 6, 1.0, -8, 8, seed), r, seed + 1);
}

TEST(OracleRandom, UniformFloat2D) { uniform_case<float, 2>(11); }
TEST(OracleRandom, UniformFloat3D) { uniform_case<float, 3>(12); }
TEST(OracleRandom, UniformDouble2D) { uniform_case<double, 2>(13); }
TEST(OracleRandom, UniformDouble3D) { uniform_case<double, 3>(14); }
TEST(OracleRandom, ClusteredFloat2D) { clustered_case<float, 2>(21); }
TEST(OracleRandom, ClusteredFloat3D) { clustered_case<float, 3>(22); }
TEST(OracleRandom, ClusteredDouble2D) { clustered_case<double, 2>(23); }
TEST(OracleRandom, ClusteredDouble3D) { clustered_case<double, 3>(24); }

// A user domain smaller than the data: points outside share the border cells and must still be
// exact, for every cell size.
template <class T, int D>
void small_domain_case(std::uint64_t seed) {
    const auto pts = uniform_points<T, D>(D == 2 ? 800 : 1000, -5, 15, seed);
    const T r = D == 2 ? T(1.2) : T(2);
    const auto queries = query_points<T, D>(pts, r, 100, {}, seed + 1);
    for (auto kind : {grid_kind::automatic, grid_kind::uniform}) {
        for (double f : cell_fractions) {
            grid_options opt;
            opt.kind = kind;
            opt.cell_size = double(r) * f;
            opt.domain_min.assign(D, 2.0);
            opt.domain_max.assign(D, 6.5);
            SCOPED_TRACE("kind=" + kind_name(kind) + " cell=r*" + std::to_string(f));
            check_all<T, D>(pts, r, opt, queries, depth_for_cell(f));
        }
    }
}

TEST(OracleRandom, DomainSmallerThanDataFloat2D) { small_domain_case<float, 2>(31); }
TEST(OracleRandom, DomainSmallerThanDataDouble3D) { small_domain_case<double, 3>(32); }

// A domain that does not even overlap the data, and one much larger than it.
TEST(OracleRandom, DomainDisjointOrLarger) {
    const auto pts = uniform_points<double, 3>(600, 0, 8, 41);
    const double r = 1.1;
    const auto queries = query_points<double, 3>(pts, r, 100, {}, 42);
    grid_options opt;
    opt.kind = grid_kind::uniform;
    opt.domain_min = {20, 20, 20};
    opt.domain_max = {25, 30, 22};
    {
        SCOPED_TRACE("disjoint domain");
        check_all<double, 3>(pts, r, opt, queries);
    }
    opt.domain_min = {-50, -50, -50};
    opt.domain_max = {50, 50, 50};
    {
        SCOPED_TRACE("large domain");
        check_all<double, 3>(pts, r, opt, queries);
    }
}

// rebuild() over new coordinates gives what a fresh build gives, including fewer and more points.
TEST(OracleRandom, RebuildMatchesOracle) {
    for (auto kind : kinds) {
        SCOPED_TRACE("kind=" + kind_name(kind));
        grid_options opt;
        opt.kind = kind;
        opt.cell_size = 0.5;
        const double r = 1.0;
        grid<double, 2> g(uniform_points<double, 2>(700, 0, 10, 51), r, opt);
        for (std::size_t n : {700u, 300u, 900u, 0u, 500u}) {
            SCOPED_TRACE("rebuild n=" + std::to_string(n));
            const auto pts = clustered_points<double, 2>(n, 4, 1.5, -3, 12, 52 + n);
            g.rebuild(pts);
            EXPECT_EQ(g.radius(), r);
            check_grid<double, 2>(g, pts, r, {}, query_points<double, 2>(pts, r, 50, {}, 53), depth::basic);
        }
    }
}

}  // namespace
}  // namespace frnn::test
