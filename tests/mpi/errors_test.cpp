// Bad input on one rank makes every rank throw the same frnn::error, naming what and where;
// nothing hangs.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "frnn/mpi/domain.hpp"
#include "mpi/mpi_check.hpp"
#include "oracle/point_sets.hpp"

namespace frnn::test {
namespace {

using T = float;
constexpr int D = 2;

TEST(MpiErrors, RanksDisagreeingOnTheRadius) {
    if (world_size() < 2) GTEST_SKIP() << "needs two ranks";
    const T radius = world_rank() == 1 ? T(0.3) : T(0.2);
    expect_collective_error([&] { mpi::domain<T, D> d(MPI_COMM_WORLD, radius); }, "rank 1: radius");
}

TEST(MpiErrors, RanksDisagreeingOnTheBox) {
    if (world_size() < 2) GTEST_SKIP() << "needs two ranks";
    mpi::domain_options o;
    o.periodic = {4, world_rank() == world_size() - 1 ? 5.0 : 4.0};
    expect_collective_error([&] { mpi::domain<T, D> d(MPI_COMM_WORLD, T(0.2), o); },
                            "rank " + std::to_string(world_size() - 1) + ": radius, skin, imbalance threshold and periodic box");
}

TEST(MpiErrors, BoxTooSmallForTheRadiusAndSkin) {
    mpi::domain_options o;
    o.periodic = {4, 1};
    o.skin = 0.1;
    expect_collective_error([&] { mpi::domain<T, D> d(MPI_COMM_WORLD, T(0.5), o); }, "periodic box length 1");
}

TEST(MpiErrors, MoreRanksThanParticles) {
    if (world_size() < 2) GTEST_SKIP() << "needs two ranks";
    // One particle fewer than ranks, on the first ranks.
    std::vector<T> coords;
    std::vector<std::uint64_t> ids;
    if (world_rank() < world_size() - 1) {
        coords = {T(world_rank()), 0};
        ids = {std::uint64_t(world_rank())};
    }
    mpi::domain<T, D> d(MPI_COMM_WORLD, T(0.5));
    expect_collective_error([&] { d.balance(coords, ids); }, "more ranks");
}

TEST(MpiErrors, NanOnOneRank) {
    std::vector<T> points = uniform_points<T, D>(40, 0, 2, 51);
    std::vector<T> coords;
    std::vector<std::uint64_t> ids;
    slice<T, D>(points, false, coords, ids);
    const int last = world_size() - 1;
    if (world_rank() == last) coords[3] = std::numeric_limits<T>::quiet_NaN();
    mpi::domain<T, D> d(MPI_COMM_WORLD, T(0.5));
    expect_collective_error([&] { d.balance(coords, ids); },
                            "rank " + std::to_string(last) + ": particle 1 has a non-finite coordinate on axis 1");
}

// balance wraps particles into the box; build takes them as balance left them.
TEST(MpiErrors, PointOutsideThePeriodicBoxAtBuild) {
    std::vector<T> coords{1, 1, 2, 2};
    std::vector<std::uint64_t> ids{std::uint64_t(2 * world_rank()), std::uint64_t(2 * world_rank() + 1)};
    if (world_rank() == 0) coords[2] = 4.5;
    mpi::domain_options o;
    o.periodic = {4, 4};
    mpi::domain<T, D> d(MPI_COMM_WORLD, T(0.5), o);
    d.balance(coords, ids);
    for (T x : coords) EXPECT_TRUE(x >= 0 && x < 4) << x;
    // Every rank with particles moves its first one a box up.
    if (!coords.empty()) coords[0] += 4;
    expect_collective_error([&] { d.build(coords, ids); }, "particle 0 lies outside the periodic box [0, 4");
}

TEST(MpiErrors, FieldOfTheWrongSizeOnOneRank) {
    std::vector<T> points = uniform_points<T, D>(200, 0, 4, 52);
    std::vector<T> coords;
    std::vector<std::uint64_t> ids;
    slice<T, D>(points, false, coords, ids);
    mpi::domain<T, D> d(MPI_COMM_WORLD, T(0.5));
    const mpi::distributor& moved = d.balance(coords, ids);
    d.build(coords, ids);
    std::vector<double> field(d.local_size() + d.ghost_size() + (world_rank() == 0 ? 1 : 0));
    expect_collective_error([&] { d.halo().gather(std::span<double>(field)); }, "rank 0: gather: array has");
    expect_collective_error([&] { d.halo().scatter_add(std::span<double>(field)); }, "rank 0: scatter_add: array has");
    std::vector<int> before(moved.local_size() + (world_rank() == 0 ? 2 : 0));
    expect_collective_error([&] { (void)moved.migrate(std::span<const int>(before)); }, "rank 0: migrate: field has");
    // Rows that do not cover the values.
    std::vector<std::uint64_t> offsets(moved.local_size() + 1, 0), out_offsets;
    std::vector<int> values(world_rank() == 0 ? 1 : 0), out_values;
    expect_collective_error([&] { moved.migrate(std::span<const std::uint64_t>(offsets), std::span<const int>(values), out_offsets, out_values); },
                            "rank 0: migrate: row offsets run from 0 to 0, expected 0 to 1");
}

TEST(MpiErrors, BuildWithParticlesOutsideThisRanksSubDomain) {
    if (world_size() < 2) GTEST_SKIP() << "needs two ranks";
    std::vector<T> points = uniform_points<T, D>(100, 0, 4, 53);
    std::vector<T> coords;
    std::vector<std::uint64_t> ids;
    slice<T, D>(points, false, coords, ids);
    mpi::domain<T, D> d(MPI_COMM_WORLD, T(0.5));
    d.balance(coords, ids);
    // Rank 0 passes, in place of its first particle, the first of all points that another rank
    // owns (every rank holds all points, and every rank owns some of them).
    const std::size_t n = points.size() / D;
    std::size_t foreign = 0;
    while (foreign < n && d.cuts().owner(&points[foreign * D]) == 0) ++foreign;
    ASSERT_LT(foreign, n) << "rank 0 owns every point";
    ASSERT_FALSE(ids.empty()) << "rank " << world_rank() << " owns no particle";
    if (world_rank() == 0) std::copy_n(&points[foreign * D], D, coords.begin());
    expect_collective_error([&] { d.build(coords, ids); }, "rank 0: build: particle");
}

}  // namespace
}  // namespace frnn::test
