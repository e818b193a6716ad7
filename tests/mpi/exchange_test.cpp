// gather, scatter_add and migrate against serial references computed from the global ids; the
// non-blocking forms with work in between; update() within and beyond the skin; weights.
#include <gtest/gtest.h>


#include "frnn/mpi/decomposition.hpp"
#include "frnn/mpi/domain.hpp"
#include "mpi/mpi_check.hpp"
#include "oracle/point_sets.hpp"

namespace frnn::test {
namespace {

using T = double;
constexpr int D = 3;
constexpr std::size_t n = 1500;
constexpr double radius = 0.8;

/// A distributed domain over a fixed random set in a periodic box (ghosts of images too).
struct fixture {
    std::vector<T> points = uniform_points<T, D>(n, 0, 8, 41);
    std::vector<T> coords;
    std::vector<std::uint64_t> ids;
    mpi::domain<T, D> domain{MPI_COMM_WORLD, T(radius), options()};

    static mpi::domain_options options() {
        mpi::domain_options o;
        o.periodic = {8, 8, 8};
        o.skin = 0.2;
        return o;
    }
    fixture() {
        slice<T, D>(points, false, coords, ids);
        domain.balance(coords, ids);
        domain.build(coords, ids);
    }
};

/// A per-particle value of a particle: 3 components from its id.
std::array<double, 3> value_of(std::uint64_t id) { return {double(id), double(id) * 0.5, -double(id)}; }

TEST(MpiExchange, GatherRefreshesEveryGhostFromItsOwner) {
    fixture f;
    const std::size_t local = f.domain.local_size(), all = local + f.domain.ghost_size();
    std::vector<double> field(all * 3, -1.0);
    for (std::size_t i = 0; i < local; ++i)
        for (std::size_t c = 0; c < 3; ++c) field[i * 3 + c] = value_of(f.domain.ids()[i])[c];
    // Non-blocking: the interior (here a sum over local values) is worked on in between.
    mpi::pending exchange = f.domain.halo().gather_begin(std::span<double>(field), 3);
    double interior = 0;
    for (std::size_t i = 0; i < local * 3; ++i) interior += field[i];
    exchange.finish();
    EXPECT_TRUE(exchange.finished());
    std::size_t wrong = 0;
    for (std::size_t g = local; g < all; ++g)
        for (std::size_t c = 0; c < 3; ++c) wrong += field[g * 3 + c] != value_of(f.domain.ids()[g])[c];
    EXPECT_EQ(wrong, 0u);
    EXPECT_TRUE(std::isfinite(interior));
    // A one-byte type, one per particle.
    std::vector<std::uint8_t> bytes(all, 0);
    for (std::size_t i = 0; i < local; ++i) bytes[i] = std::uint8_t(f.domain.ids()[i] % 251);
    f.domain.halo().gather(std::span<std::uint8_t>(bytes));
    wrong = 0;
    for (std::size_t g = local; g < all; ++g) wrong += bytes[g] != f.domain.ids()[g] % 251;
    EXPECT_EQ(wrong, 0u);
    // Ghosts of the periodic box exist and their positions are their owners' shifted by whole boxes.
    int ghosts = int(f.domain.ghost_size());
    MPI_Allreduce(MPI_IN_PLACE, &ghosts, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    EXPECT_GT(ghosts, 0);
    for (std::size_t g = local; g < all; ++g)
        for (std::size_t a = 0; a < D; ++a) {
            const double owner = f.points[f.domain.ids()[g] * D + a];
            const double position = f.domain.positions()[g * D + a];
            const double boxes = std::nearbyint((position - owner) / 8);
            EXPECT_LE(std::abs(boxes), 1.0);
            EXPECT_EQ(position, owner + boxes * 8);
        }
}

TEST(MpiExchange, ScatterAddSumsPairContributionsAsOneProcessWould) {
    fixture f;
    const std::size_t local = f.domain.local_size(), all = local + f.domain.ghost_size();
    // Each local particle i adds c(i, j) to every neighbor j, ghosts included; integers, so that
    // the sums are exact in any order.
    auto contribution = [](std::uint64_t i, std::uint64_t j) { return double((i * 7 + j * 3) % 13); };
    std::vector<double> sums(all, 0.0);
    const csr<T> lists = f.domain.neighbor_lists();
    for (std::size_t i = 0; i < local; ++i)
        for (std::uint32_t j : lists.row(i)) sums[j] += contribution(f.domain.ids()[i], f.domain.ids()[j]);
    f.domain.halo().scatter_add(std::span<double>(sums));
    // Serial reference: the same over all single-process pairs.
    const std::vector<double> box{8, 8, 8};
    const csr<T> serial = brute_force_lists<T, D>(f.points, f.points, T(radius), true, box);
    std::vector<double> expected(n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
        for (std::uint32_t j : serial.row(i)) expected[j] += contribution(i, j);
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < local; ++i) wrong += sums[i] != expected[f.domain.ids()[i]];
    EXPECT_EQ(wrong, 0u);
}

TEST(MpiExchange, MigrateMovesFixedAndVariableLengthFields) {
    const std::vector<T> points = clustered_points<T, D>(n, 4, 0.8, 0, 10, 42);
    std::vector<T> coords;
    std::vector<std::uint64_t> ids;
    slice<T, D>(points, false, coords, ids);
    // Fields before the move: a velocity from the id, and partner lists of id % 4 entries.
    std::vector<double> velocity;
    std::vector<std::uint64_t> offsets{0}, partners;
    for (std::uint64_t id : ids) {
        for (double v : value_of(id)) velocity.push_back(v);
        for (std::uint64_t k = 1; k <= id % 4; ++k) partners.push_back(id * 10 + k);
        offsets.push_back(partners.size());
    }
    mpi::domain<T, D> domain(MPI_COMM_WORLD, T(radius));
    const mpi::distributor& moved = domain.balance(coords, ids);
    const std::vector<double> new_velocity = moved.migrate(std::span<const double>(velocity), 3);
    std::vector<std::uint64_t> new_offsets, new_partners;
    moved.migrate(std::span<const std::uint64_t>(offsets), std::span<const std::uint64_t>(partners), new_offsets,
                  new_partners);
    expect_partition(ids, n);
    ASSERT_EQ(new_velocity.size(), ids.size() * 3);
    ASSERT_EQ(new_offsets.size(), ids.size() + 1);
    std::size_t wrong = 0;
    int rank = world_rank();
    for (std::size_t i = 0; i < ids.size(); ++i) {
        const std::uint64_t id = ids[i];
        for (std::size_t a = 0; a < D; ++a) wrong += coords[i * D + a] != points[id * D + a];
        for (std::size_t c = 0; c < 3; ++c) wrong += new_velocity[i * 3 + c] != value_of(id)[c];
        wrong += new_offsets[i + 1] - new_offsets[i] != id % 4;
        for (std::uint64_t k = new_offsets[i]; k < std::min(new_offsets[i + 1], new_partners.size()); ++k)
            wrong += new_partners[k] != id * 10 + (k - new_offsets[i]) + 1;
        wrong += domain.cuts().owner(&coords[i * D]) != rank;
    }
    EXPECT_EQ(wrong, 0u);
    EXPECT_EQ(new_offsets.back(), new_partners.size());
}

TEST(MpiExchange, WeightsMoveWithTheirParticlesAndBalanceTheCost) {
    const std::vector<T> points = uniform_points<T, D>(2000, 0, 10, 43);
    std::vector<T> coords;
    std::vector<std::uint64_t> ids;
    slice<T, D>(points, true, coords, ids);
    std::vector<double> weights;
    for (std::uint64_t id : ids) weights.push_back(1.0 + double(id % 3));
    mpi::domain<T, D> domain(MPI_COMM_WORLD, T(0.4));
    domain.balance(coords, ids, &weights);
    std::size_t wrong = 0;
    double mine = 0;
    for (std::size_t i = 0; i < ids.size(); ++i) {
        wrong += weights[i] != 1.0 + double(ids[i] % 3);
        mine += weights[i];
    }
    EXPECT_EQ(wrong, 0u);
    // Cuts fall on cells of 0.4 out of 10: each leaves a few percent of imbalance at most.
    EXPECT_LT(mpi::imbalance(MPI_COMM_WORLD, mine), 0.25);
}

TEST(MpiExchange, UpdateKeepsThePlanWithinHalfTheSkin) {
    fixture f;
    std::vector<T> moved = f.coords;
    // Every particle moves by 0.09 < skin / 2 = 0.1 along a direction from its id; the box is
    // periodic and update() keeps unwrapped coordinates.
    std::vector<T> shifted_points = f.points;
    auto step = [](std::uint64_t id, std::size_t a) { return 0.09 * (a == id % 3 ? 1.0 : 0.0) * (id % 2 ? 1 : -1); };
    for (std::size_t i = 0; i < f.ids.size(); ++i)
        for (std::size_t a = 0; a < D; ++a) moved[i * D + a] += T(step(f.ids[i], a));
    for (std::size_t id = 0; id < n; ++id)
        for (std::size_t a = 0; a < D; ++a) shifted_points[id * D + a] += T(step(id, a));
    const std::size_t ghosts = f.domain.ghost_size();
    EXPECT_TRUE(f.domain.update(moved));
    EXPECT_EQ(f.domain.ghost_size(), ghosts);
    const auto expected = reference_pairs<T, D>(shifted_points, T(radius), std::vector<double>{8, 8, 8}, f.ids);
    const auto pairs = f.domain.global_pairs();
    std::vector<std::array<std::uint64_t, 2>> expected_ids;
    for (const auto& p : expected) expected_ids.push_back({std::get<0>(p), std::get<1>(p)});
    EXPECT_TRUE(pairs == expected_ids) << "pairs after update differ from the oracle";
    // One particle on the last rank moves too far: every rank is told to rebuild.
    if (world_rank() == world_size() - 1 && !moved.empty()) moved[0] += T(0.5);
    EXPECT_FALSE(f.domain.update(moved));
}

TEST(MpiExchange, DecompositionCutsOnTheCellLattice) {
    const std::vector<T> points = uniform_points<T, D>(1000, -3, 7, 44);
    std::vector<T> coords;
    std::vector<std::uint64_t> ids;
    slice<T, D>(points, false, coords, ids);
    const mpi::decomposition<T, D> cuts(MPI_COMM_WORLD, coords, 0.5);
    ASSERT_EQ(cuts.ranks(), world_size());
    for (int r = 0; r < cuts.ranks(); ++r)
        for (std::size_t a = 0; a < D; ++a)
            for (double face : {cuts.lower(r)[a], cuts.upper(r)[a]})
                if (std::isfinite(face)) {
                    EXPECT_EQ(face / 0.5, std::nearbyint(face / 0.5)) << "rank " << r;
                }
    // Every point of the set has the owner whose box holds it, on every rank alike.
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < 1000; ++i) {
        const int q = cuts.owner(&points[i * D]);
        for (std::size_t a = 0; a < D; ++a)
            wrong += !(points[i * D + a] >= cuts.lower(q)[a] && points[i * D + a] < cuts.upper(q)[a]);
    }
    EXPECT_EQ(wrong, 0u);
}

}  // namespace
}  // namespace frnn::test
