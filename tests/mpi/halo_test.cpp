// halo::gather_positions against the ghosts the whole point set predicts: each rank must hold
// exactly the particles, and periodic images of particles, that lie within reach of its
// sub-domain (its own particles unshifted excepted), at their owners' coordinates shifted by
// whole boxes; after the owners move, the same ghosts at the moved coordinates; a wrong size on
// one rank throws on every rank.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "frnn/mpi/decomposition.hpp"
#include "frnn/mpi/halo.hpp"
#include "mpi/mpi_check.hpp"
#include "oracle/point_sets.hpp"

namespace frnn::test {
namespace {

/// A ghost as its global id and its (shifted) coordinates, and the image it must be.
template <class T, int D>
using ghost_key = std::pair<std::uint64_t, std::array<T, D>>;
template <int D>
using image_t = std::array<int, D>;

/// Coordinates of particle i of `points` shifted by `image` box lengths, as the halo must give
/// them: the shift added in double, rounded once to T.
template <class T, int D>
std::array<T, D> shifted(const std::vector<T>& points, std::size_t i, const image_t<D>& image,
                         const std::vector<double>& box) {
    std::array<T, D> y;
    for (std::size_t a = 0; a < D; ++a)
        y[a] = image[a] == 0 ? points[i * D + a] : T(double(points[i * D + a]) + image[a] * box[a]);
    return y;
}

/// Every (id, image) that this rank must receive, computed from the whole set: each image (each
/// shift in {-1, 0, 1} on every periodic axis) within `reach` of this rank's box, except this
/// rank's own particles unshifted.
template <class T, int D>
std::map<ghost_key<T, D>, image_t<D>> expected_ghosts(const std::vector<T>& points, const std::vector<int>& owner,
                                                      const mpi::decomposition<T, D>& cuts,
                                                      const std::vector<double>& box, double reach) {
    const int rank = world_rank();
    const auto& lower = cuts.lower(rank);
    const auto& upper = cuts.upper(rank);
    std::map<ghost_key<T, D>, image_t<D>> out;
    const int images = D == 2 ? 9 : 27;
    for (std::size_t i = 0; i < owner.size(); ++i)
        for (int code = 0; code < images; ++code) {
            image_t<D> image{};
            bool possible = true, unshifted = true;
            for (std::size_t a = 0, rest = std::size_t(code); a < D; ++a, rest /= 3) {
                image[a] = int(rest % 3) - 1;
                possible &= image[a] == 0 || (!box.empty() && box[a] > 0);  // open axes have no images
                unshifted &= image[a] == 0;
            }
            if (!possible || (unshifted && owner[i] == rank)) continue;
            double d2 = 0;
            for (std::size_t a = 0; a < D; ++a) {
                const double y = double(points[i * D + a]) + (image[a] ? image[a] * box[a] : 0.0);
                const double d = y < lower[a] ? lower[a] - y : y > upper[a] ? y - upper[a] : 0.0;
                d2 += d * d;
            }
            if (d2 <= reach * reach) out[{i, shifted<T, D>(points, i, image, box)}] = image;
        }
    return out;
}

/// Builds a halo over `points` (each rank holding the particles its sub-domain owns) and checks
/// gather_positions against expected_ghosts, before and after every particle moves.
template <class T, int D>
void expect_ghosts_of_the_whole_set(const std::vector<T>& points, const std::vector<double>& box, double cell,
                                    double reach) {
    const std::size_t n = points.size() / D;
    std::vector<T> start;
    std::vector<std::uint64_t> start_ids;
    slice<T, D>(points, false, start, start_ids);
    const mpi::decomposition<T, D> cuts(MPI_COMM_WORLD, start, cell, box);
    const int rank = world_rank();
    std::vector<int> owner(n);
    std::vector<T> coords;
    std::vector<std::uint64_t> ids;
    for (std::size_t i = 0; i < n; ++i) {
        owner[i] = cuts.owner(&points[i * D]);
        if (owner[i] != rank) continue;
        ids.push_back(i);
        coords.insert(coords.end(), points.begin() + std::ptrdiff_t(i * D), points.begin() + std::ptrdiff_t(i * D + D));
    }
    const mpi::halo<T, D> h(MPI_COMM_WORLD, cuts, coords, reach);
    const auto expected = expected_ghosts<T, D>(points, owner, cuts, box, reach);
    // Not a vacuous check: some rank expects ghosts.
    int total = int(expected.size());
    MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    if (!box.empty() || world_size() > 1) {
        EXPECT_GT(total, 0);
    }

    EXPECT_EQ(h.local_size(), ids.size());
    const std::size_t local = ids.size(), all = local + h.ghost_size();
    // Ghost slots start as NaN and a bad id: nothing stale can pass.
    std::vector<T> x(all * D, std::numeric_limits<T>::quiet_NaN());
    std::copy(coords.begin(), coords.end(), x.begin());
    std::vector<std::uint64_t> gid(all, ~std::uint64_t(0));
    std::copy(ids.begin(), ids.end(), gid.begin());
    h.gather(std::span<std::uint64_t>(gid));  // labels the ghosts (gather itself: exchange_test.cpp)
    h.gather_positions(std::span<T>(x));
    EXPECT_TRUE(std::equal(coords.begin(), coords.end(), x.begin())) << "local coordinates changed";

    // The same (id, position) multiset, each ghost with the image expected for it.
    std::vector<image_t<D>> image_of(all);
    std::size_t unexpected = 0, wrong_image = 0, out_of_order = 0;
    std::map<ghost_key<T, D>, int> seen;
    std::string first_problem;
    for (std::size_t g = local; g < all; ++g) {
        ghost_key<T, D> key{gid[g], {}};
        std::copy(x.begin() + std::ptrdiff_t(g * D), x.begin() + std::ptrdiff_t(g * D + D), key.second.begin());
        if (std::any_of(key.second.begin(), key.second.end(), [](T v) { return std::isnan(v); })) {
            if (first_problem.empty()) first_problem = "ghost " + std::to_string(g - local) + " was not filled";
            ++unexpected;
            continue;
        }
        ++seen[key];
        const auto it = expected.find(key);
        if (it == expected.end()) {
            if (first_problem.empty()) first_problem = "unexpected ghost: particle " + std::to_string(gid[g]);
            ++unexpected;
            continue;
        }
        image_of[g] = it->second;
        for (std::size_t a = 0; a < D; ++a) wrong_image += h.ghost_images()[(g - local) * D + a] != it->second[a];
        // Ghosts come grouped by owner rank, in rank order.
        if (g > local && gid[g - 1] < n) out_of_order += owner[gid[g - 1]] > owner[gid[g]];
    }
    std::size_t missing = 0, doubled = 0;
    for (const auto& entry : expected) {
        const auto it = seen.find(entry.first);
        missing += it == seen.end();
        doubled += it != seen.end() && it->second > 1;
        if (it == seen.end() && first_problem.empty())
            first_problem = "missing ghost: particle " + std::to_string(entry.first.first);
    }
    EXPECT_EQ(unexpected, 0u) << first_problem;
    EXPECT_EQ(missing, 0u) << first_problem;
    EXPECT_EQ(doubled, 0u);
    EXPECT_EQ(wrong_image, 0u);
    EXPECT_EQ(out_of_order, 0u);

    // A step within the skin: every owner moves, the plan stays; the ghosts follow, shifted alike.
    std::vector<T> moved = points;
    for (std::size_t i = 0; i < n; ++i) moved[i * D + i % D] += T(0.01 * (double(i % 5) - 2));
    for (std::size_t k = 0; k < local; ++k)
        for (std::size_t a = 0; a < D; ++a) x[k * D + a] = moved[ids[k] * D + a];
    std::fill(x.begin() + std::ptrdiff_t(local * D), x.end(), std::numeric_limits<T>::quiet_NaN());
    h.gather_positions(std::span<T>(x));
    std::size_t wrong = 0;
    for (std::size_t g = local; g < all; ++g) {
        if (gid[g] >= n) continue;  // reported above
        const std::array<T, D> want = shifted<T, D>(moved, gid[g], image_of[g], box);
        for (std::size_t a = 0; a < D; ++a) wrong += !(x[g * D + a] == want[a]);
    }
    EXPECT_EQ(wrong, 0u) << "ghost coordinates after the owners moved";

    // One value too many on the last rank only: every rank throws the same error.
    std::vector<T> one_more(all * D + (rank == world_size() - 1 ? 1 : 0));
    expect_collective_error([&] { h.gather_positions(std::span<T>(one_more)); }, "gather: array has");
}

TEST(MpiHalo, GatherPositionsPeriodicBoxDouble3d) {
    expect_ghosts_of_the_whole_set<double, 3>(uniform_points<double, 3>(1200, 0, 8, 51), {8, 8, 8}, 0.6, 0.75);
}

// No images on an open domain: the ghosts are the neighboring ranks' particles, as they are.
TEST(MpiHalo, GatherPositionsOpenDomainFloat2d) {
    expect_ghosts_of_the_whole_set<float, 2>(clustered_points<float, 2>(900, 3, 1.0, -2, 6, 52), {}, 0.5, 0.6);
}

// Periodic in x and z, open in y: images are shifted along the periodic axes only.
TEST(MpiHalo, GatherPositionsMixedPeriodicFloat3d) {
    expect_ghosts_of_the_whole_set<float, 3>(uniform_points<float, 3>(1000, 0, 6, 53), {6, 0, 6}, 0.5, 0.7);
}

}  // namespace
}  // namespace frnn::test
