// Every oracle point set, searched across the ranks, gives exactly the single-process pairs
// (as global ids, with the oracle's distances bit for bit), however the particles start out
// (spread over the ranks, or all on rank 0) and for float and double, 2D and 3D.
#include <gtest/gtest.h>

#include <cmath>
#include <iterator>

#include "frnn/mpi/domain.hpp"
#include "mpi/mpi_check.hpp"
#include "oracle/point_sets.hpp"

namespace frnn::test {
namespace {

template <class P>
class MpiSearch : public ::testing::Test {};
template <class T_, int D_>
struct kind {
    using T = T_;
    static constexpr int D = D_;
};
using kinds = ::testing::Types<kind<float, 2>, kind<float, 3>, kind<double, 2>, kind<double, 3>>;
TYPED_TEST_SUITE(MpiSearch, kinds);

/// The distributed pairs of this rank's particles, with distances.
template <class T, int D>
std::vector<pair_t<T>> distributed_pairs(const mpi::domain<T, D>& domain) {
    const csr<T> lists = domain.neighbor_lists(true);
    std::vector<pair_t<T>> out;
    for (std::size_t i = 0; i < lists.rows(); ++i)
        for (std::uint64_t k = lists.offsets[i]; k < lists.offsets[i + 1]; ++k)
            out.emplace_back(domain.ids()[i], domain.ids()[lists.indices[k]], lists.distances[k]);
    std::sort(out.begin(), out.end());
    return out;
}

/// The first pair in one list and not the other, for the failure message.
template <class T>
std::string first_difference(const std::vector<pair_t<T>>& found, const std::vector<pair_t<T>>& expected) {
    std::vector<pair_t<T>> extra, missing;
    std::set_difference(found.begin(), found.end(), expected.begin(), expected.end(), std::back_inserter(extra));
    std::set_difference(expected.begin(), expected.end(), found.begin(), found.end(), std::back_inserter(missing));
    auto show = [](const char* what, const std::vector<pair_t<T>>& v) {
        if (v.empty()) return std::string();
        return std::string("; ") + std::to_string(v.size()) + " " + what + ", first (" + std::to_string(std::get<0>(v[0])) +
               ", " + std::to_string(std::get<1>(v[0])) + ") at " + std::to_string(double(std::get<2>(v[0])));
    };
    return show("extra", extra) + show("missing", missing);
}

/// Distributes `points`, searches (with `threads` per rank), and compares with the oracle on
/// every rank.
template <class T, int D>
void check_set(const std::vector<T>& points, T radius, const std::vector<double>& periodic, const char* name,
               int threads = 1) {
    SCOPED_TRACE(name);
    for (bool all_on_rank0 : {false, true}) {
        SCOPED_TRACE(all_on_rank0 ? "all on rank 0" : "spread over the ranks");
        std::vector<T> coords;
        std::vector<std::uint64_t> ids;
        slice<T, D>(points, all_on_rank0, coords, ids);
        mpi::domain_options options;
        options.periodic = periodic;
        options.skin = 0.1 * double(radius);
        options.threads = threads;
        mpi::domain<T, D> domain(MPI_COMM_WORLD, radius, options);
        domain.balance(coords, ids);
        for (std::size_t i = 0; i < coords.size() && !periodic.empty(); ++i) {
            const double length = periodic[i % D];
            if (length > 0 && !(coords[i] >= 0 && double(coords[i]) < length)) {
                ADD_FAILURE() << "balance left coordinate " << i << " = " << coords[i] << " outside [0, " << length << ")";
                break;
            }
        }
        domain.build(coords, ids);
        expect_partition(ids, points.size() / D);
        const auto expected = reference_pairs<T, D>(points, radius, periodic, ids);
        const auto found = distributed_pairs(domain);
        EXPECT_EQ(found.size(), expected.size());
        EXPECT_TRUE(found == expected) << "pairs differ from the single-process oracle" << first_difference(found, expected);
        // global_pairs() reports the same pairs, ids only.
        const auto pairs = domain.global_pairs();
        EXPECT_EQ(pairs.size(), expected.size());
        for (std::size_t k = 0; k < std::min(pairs.size(), expected.size()); ++k)
            if (pairs[k][0] != std::get<0>(expected[k]) || pairs[k][1] != std::get<1>(expected[k])) {
                ADD_FAILURE() << "global pair " << k << " differs";
                break;
            }
    }
}

/// n points uniform in `box`, [0, L) on each periodic axis (rounding that lands on L is folded
/// back to 0) and [0, 6) on each open axis (length 0).
template <class T, int D>
std::vector<T> points_in_box(std::size_t n, const std::vector<double>& box, std::uint64_t seed) {
    std::vector<T> points = uniform_points<T, D>(n, 0, 1, seed);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const double length = box[i % D] > 0 ? box[i % D] : 6.0;
        points[i] = T(points[i] * length);
        if (box[i % D] > 0 && double(points[i]) >= length) points[i] = 0;
    }
    return points;
}

TYPED_TEST(MpiSearch, RandomSets) {
    using T = typename TypeParam::T;
    constexpr int D = TypeParam::D;
    const std::size_t n = D == 2 ? 1200 : 1500;
    check_set<T, D>(uniform_points<T, D>(n, 0, 10, 11), T(D == 2 ? 0.4 : 1.0), {}, "uniform");
    check_set<T, D>(clustered_points<T, D>(n, 5, 0.4, 0, 10, 12), T(0.2), {}, "clustered");
}

TYPED_TEST(MpiSearch, PeriodicBoxes) {
    using T = typename TypeParam::T;
    constexpr int D = TypeParam::D;
    const std::vector<double> box = D == 2 ? std::vector<double>{8, 6} : std::vector<double>{8, 6, 7};
    check_set<T, D>(points_in_box<T, D>(D == 2 ? 900 : 1200, box, 21), T(1.1), box, "uniform in a box");
    // A lattice whose spacing is the radius: pairs at exactly r, across the box's faces too.
    const int side = D == 2 ? 12 : 7;
    check_set<T, D>(lattice_points<T, D>(side, 1.0), T(1), std::vector<double>(D, side), "periodic lattice at exactly r");
}

// Pairs a few units in the last place beyond and within r, across the faces too: periodic
// ghosts are candidates a little beyond r (their shifted coordinates round), and the lists
// drop those the single-process test rejects. Two threads decide rows in cell order.
TYPED_TEST(MpiSearch, PeriodicPairsAtTheRadius) {
    using T = typename TypeParam::T;
    constexpr int D = TypeParam::D;
    const std::vector<double> box = D == 2 ? std::vector<double>{8, 6} : std::vector<double>{8, 6, 7};
    const T r = T(1.1);
    std::vector<T> points = points_in_box<T, D>(D == 2 ? 1500 : 2000, box, 27);
    const std::size_t n = points.size() / D;
    for (std::size_t p = 0; p < n; p += 2) {
        const int axis = int(p / 2 % D);
        const double factor = p % 4 == 0 ? 1 + 5e-7 : 1 - 5e-7;
        std::vector<T> partner(points.begin() + std::ptrdiff_t(p * D), points.begin() + std::ptrdiff_t(p * D + D));
        const std::size_t a = std::size_t(axis);
        partner[a] = T(std::fmod(double(partner[a]) + double(r) * factor, box[a]));
        points.insert(points.end(), partner.begin(), partner.end());
    }
    check_set<T, D>(points, r, box, "pairs at the radius, 2 threads", 2);
    check_set<T, D>(points, r, box, "pairs at the radius, 1 thread", 1);
}

// Particles outside the box, as an MD code's are after they crossed a face: balance wraps
// them as the single-process grid does (frnn/periodic_wrap.hpp), and the pairs are the
// oracle's, which wraps too. Some lie one to three boxes out, some 10^6 boxes out.
TYPED_TEST(MpiSearch, PeriodicBoxesWithParticlesOutside) {
    using T = typename TypeParam::T;
    constexpr int D = TypeParam::D;
    const std::vector<double> box = D == 2 ? std::vector<double>{8, 6} : std::vector<double>{8, 6, 7};
    std::vector<T> points = points_in_box<T, D>(D == 2 ? 900 : 1200, box, 23);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const std::size_t p = i / D;
        const double boxes = p % 50 == 0 ? 1e6 : p % 5 == 0 ? double(int(p % 7) - 3) : 0.0;
        points[i] = T(double(points[i]) + boxes * box[i % D]);
    }
    check_set<T, D>(points, T(1.1), box, "particles outside the box");
    std::vector<double> channel = box;
    channel[1] = 0;
    for (std::size_t i = 1; i < points.size(); i += D) points[i] = T(std::fmod(std::abs(double(points[i])), 6.0));
    check_set<T, D>(points, T(1.1), channel, "particles outside a channel periodic but on y");
}

// Periodic on some axes only (0 on the open ones): a channel with a far outlier on its open
// axis, and a lattice at exactly r across the periodic faces.
TYPED_TEST(MpiSearch, PeriodicOnSomeAxes) {
    using T = typename TypeParam::T;
    constexpr int D = TypeParam::D;
    const std::vector<double> box = D == 2 ? std::vector<double>{8, 0} : std::vector<double>{8, 0, 7};
    std::vector<T> points = points_in_box<T, D>(D == 2 ? 900 : 1200, box, 25);
    for (double y : {1e6, -1e6, 1e6 + 0.25}) {
        for (int a = 0; a < D; ++a) points.push_back(T(a == 1 ? y : 1.0));
    }
    check_set<T, D>(points, T(1.1), box, "channel");
    const int side = D == 2 ? 12 : 7;
    std::vector<double> lattice_box(D, double(side));
    lattice_box[0] = 0;
    check_set<T, D>(lattice_points<T, D>(side, 1.0), T(1), lattice_box, "lattice periodic but on x");
}

TYPED_TEST(MpiSearch, AdversarialSets) {
    using T = typename TypeParam::T;
    constexpr int D = TypeParam::D;
    // Far outliers: the sub-domains reach to infinity.
    std::vector<T> outliers = uniform_points<T, D>(600, 0, 5, 31);
    append_point<T, D>(outliers, 1e6);
    append_point<T, D>(outliers, -1e6);
    append_point<T, D>(outliers, 1e6 + 0.25);
    check_set<T, D>(outliers, T(0.5), {}, "far outliers");
    check_set<T, D>(with_duplicates(uniform_points<T, D>(250, 0, 4, 32), D, 3), T(0.5), {}, "duplicates");
    check_set<T, D>(lattice_points<T, D>(D == 2 ? 20 : 8, 1.0), T(1), {}, "lattice at exactly r");
    // Points exactly on cell faces, where the cuts between sub-domains lie.
    check_set<T, D>(on_cell_boundaries<T, D>(800, 0.5, 16, 33), T(0.5), {}, "on cell faces");
    // Every point in one cell: the cuts leave ranks without particles.
    check_set<T, D>(with_duplicates(uniform_points<T, D>(3, 0.1, 0.2, 34), D, 4), T(0.5), {}, "one cell");
}

}  // namespace
}  // namespace frnn::test
