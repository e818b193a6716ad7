// The generators follow bench/README.md: sizes, bounds, dimension, determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "frnn/bench/workloads.hpp"
#include "expect_error.hpp"
#include "frnn/error.hpp"

namespace fb = frnn::bench;

using frnn::test::expect_error;

TEST(BenchWorkloads, ListParsing) {
    EXPECT_EQ(fb::parse_workload_list("all"),
              (std::vector<std::string>{"W1", "W2", "W3", "W4", "W5", "W7", "W8"}));
    EXPECT_EQ(fb::parse_workload_list("w2, W1,W2"), (std::vector<std::string>{"W2", "W1"}));
    EXPECT_THROW(fb::parse_workload_list("W6"), frnn::error);  // the simulation's, not the bench's
    EXPECT_THROW(fb::parse_workload_list("W1,"), frnn::error);
}

// W7 is W2's points; its radii lie in the range asked, drawn alike every time.
TEST(BenchWorkloads, RadiiOfW7) {
    const auto& w7 = fb::find_workload("W7");
    EXPECT_EQ(fb::generate<float>(w7, 5000), fb::generate<float>(fb::find_workload("W2"), 5000));
    const auto radii = fb::point_radii<float>(5000, 0.2, 2.0, 44);
    ASSERT_EQ(radii.size(), 5000u);
    for (float r : radii) EXPECT_TRUE(r >= 0.2f && r <= 2.0f) << r;
    EXPECT_EQ(radii, fb::point_radii<float>(5000, 0.2, 2.0, 44));
    EXPECT_NE(radii, fb::point_radii<float>(5000, 0.2, 2.0, 45));
}

TEST(BenchWorkloads, DefaultSizesAreThoseOfTheTable) {
    const auto& w1 = fb::find_workload("W1");
    std::vector<std::size_t> counts, sides;
    for (auto n : w1.sizes) counts.push_back(fb::point_count(w1, n)), sides.push_back(fb::lattice_side(w1, n));
    EXPECT_EQ(counts, (std::vector<std::size_t>{32768, 262144, 1000000, 4096000}));
    EXPECT_EQ(sides, (std::vector<std::size_t>{32, 64, 100, 160}));
    const auto& w2 = fb::find_workload("W2");
    EXPECT_EQ(w2.sizes, counts);  // "N as W1"
    const auto& w4 = fb::find_workload("W4");
    EXPECT_EQ(fb::point_count(w4, w4.sizes.at(0)), 1000000u);
    EXPECT_EQ(fb::lattice_side(w4, w4.sizes.at(0)), 1000u);
    const auto& w5 = fb::find_workload("W5");
    EXPECT_EQ(fb::point_count(w5, w5.sizes.at(0)), 1000001u);
    EXPECT_EQ(fb::point_count(fb::find_workload("W3"), 1000000), 1000000u);
}

TEST(BenchWorkloads, LatticeCountsRoundToTheNearestLattice) {
    const auto& w1 = fb::find_workload("W1");
    const auto& w4 = fb::find_workload("W4");
    const auto& w5 = fb::find_workload("W5");
    EXPECT_EQ(fb::point_count(w1, 1), 1u);
    EXPECT_EQ(fb::point_count(w1, 1000), 1000u);
    EXPECT_EQ(fb::point_count(w1, 1165), 1000u);  // 10^3 is 165 away, 11^3 166
    EXPECT_EQ(fb::point_count(w1, 1166), 1331u);
    EXPECT_EQ(fb::lattice_side(w1, 1166), 11u);
    EXPECT_EQ(fb::point_count(w4, 50), 49u);
    EXPECT_EQ(fb::point_count(w4, 57), 64u);
    EXPECT_EQ(fb::lattice_side(w4, 57), 8u);
    EXPECT_EQ(fb::point_count(w5, 1), 2u);  // side 1 and the outlier
    EXPECT_EQ(fb::point_count(w5, 1000), 1001u);
    EXPECT_EQ(fb::point_count(fb::find_workload("W2"), 1166), 1166u);
    EXPECT_EQ(fb::lattice_side(fb::find_workload("W2"), 1166), 0u);
    EXPECT_EQ(fb::side_count(w1, 7), 343u);
    EXPECT_EQ(fb::side_count(w4, 7), 49u);
    EXPECT_EQ(fb::side_count(w5, 7), 344u);
    for (std::size_t side : {1u, 2u, 9u, 160u, 1000u}) EXPECT_EQ(fb::lattice_side(w4, fb::side_count(w4, side)), side);
}

TEST(BenchWorkloads, CountsOfNoneOrTooManyPointsAreErrors) {
    const auto& w1 = fb::find_workload("W1");
    expect_error([&] { (void)fb::point_count(w1, 0); }, {"workload W1: N = 0 gives no points"});
    expect_error([&] { (void)fb::point_count(w1, 5'000'000'000); }, {"more than 2^32 - 2"});
    expect_error([&] { (void)fb::side_count(w1, 0); }, {"workload W1: lattice side 0 gives no points"});
    expect_error([&] { (void)fb::side_count(w1, 5000); }, {"more than 2^32 - 2"});
    expect_error([&] { (void)fb::side_count(fb::find_workload("W2"), 5); }, {"W2 is not a lattice"});
}

TEST(BenchWorkloads, LatticeIsJitteredByAtMostATenth) {
    const auto& w = fb::find_workload("W1");
    const auto p = fb::generate<double>(w, 343);
    ASSERT_EQ(p.size(), 7u * 7 * 7 * 3);
    double max_jitter = 0;
    for (std::size_t i = 0; i < 343; ++i) {
        const double lattice[3] = {double(i % 7), double(i / 7 % 7), double(i / 49)};
        for (int a = 0; a < 3; ++a) max_jitter = std::max(max_jitter, std::abs(p[i * 3 + a] - lattice[a]));
    }
    EXPECT_LE(max_jitter, 0.1);
    EXPECT_GT(max_jitter, 0.05);  // really jittered
}

TEST(BenchWorkloads, SameSeedSamePoints) {
    for (const auto& w : fb::all_workloads()) {
        const std::size_t n = 300;  // lattices round: W1 343, W4 289, W5 344, W8 4 * 4^3
        const auto a = fb::generate<float>(w, n), b = fb::generate<float>(w, n);
        EXPECT_EQ(a, b) << w.id;
        EXPECT_EQ(a.size(), fb::point_count(w, n) * std::size_t(w.dim)) << w.id;
        const std::size_t expected = w.id == "W1" ? 343u : w.id == "W4" ? 289u : w.id == "W5" ? 344u : w.id == "W8" ? 256u : n;
        EXPECT_EQ(a.size() / std::size_t(w.dim), expected);
        const auto d = fb::generate<double>(w, n);
        for (std::size_t k = 0; k < a.size(); ++k) ASSERT_EQ(a[k], float(d[k])) << w.id << " " << k;
    }
}

// A slice drawn alone (a rank's share of `frnn query --generate`) holds the same values as
// that part of the whole set, for both generators in 2D and 3D, empty slices included.
TEST(BenchWorkloads, SlicesDrawnAloneAreThePartsOfTheWhole) {
    for (int dim : {2, 3}) {
        const std::size_t side = 7, lattice_count = dim == 3 ? 343 : 49, count = 500;
        const auto lattice = fb::jittered_lattice<double>(side, dim, 5);
        const auto cube = fb::uniform_cube<double>(count, dim, 5);
        ASSERT_EQ(lattice.size(), lattice_count * std::size_t(dim));
        for (std::size_t parts : {1, 3, 4, 64}) {
            std::vector<double> lattice_joined, cube_joined;
            for (std::size_t k = 0; k < parts; ++k) {
                const std::size_t lb = lattice_count * k / parts, le = lattice_count * (k + 1) / parts;
                const auto l = fb::jittered_lattice<double>(side, dim, 5, lb, le);
                const auto c = fb::uniform_cube<double>(count, dim, 5, count * k / parts, count * (k + 1) / parts);
                lattice_joined.insert(lattice_joined.end(), l.begin(), l.end());
                cube_joined.insert(cube_joined.end(), c.begin(), c.end());
            }
            EXPECT_EQ(lattice_joined, lattice) << dim << "D, " << parts << " slices";
            EXPECT_EQ(cube_joined, cube) << dim << "D, " << parts << " slices";
        }
        EXPECT_TRUE(fb::uniform_cube<double>(count, dim, 5, 200, 200).empty());
    }
}

// W8: LAMMPS's LJ benchmark lattice at its density, inside its periodic cube, and an fcc
// lattice: every atom's nearest neighbor near a / sqrt(2), no closer than the jitter allows.
TEST(BenchWorkloads, MdLatticeAtDensity08442InsideItsBox) {
    const auto& w = fb::find_workload("W8");
    EXPECT_EQ(fb::point_count(w, 32000), 32000u);
    EXPECT_EQ(fb::point_count(w, 864000), 864000u);
    EXPECT_EQ(fb::lattice_side(w, 864000), 60u);
    EXPECT_EQ(fb::point_count(w, 600), 500u);  // 4 * 5^3, nearer than 4 * 6^3
    const std::size_t n = 4 * 6 * 6 * 6;
    const auto p = fb::generate<double>(w, n);
    const double box = fb::periodic_box(w, n), a = fb::fcc_lattice_constant();
    EXPECT_NEAR(double(n) / (box * box * box), 0.8442, 1e-12);
    for (double x : p) ASSERT_TRUE(x >= 0 && x < box) << x;
    for (std::size_t i = 0; i < n; ++i) {
        double nearest = box;
        for (std::size_t j = 0; j < n; ++j) {
            if (j == i) continue;
            double d2 = 0;
            for (int k = 0; k < 3; ++k) {
                double d = p[3 * j + k] - p[3 * i + k];
                d -= box * std::nearbyint(d / box);
                d2 += d * d;
            }
            nearest = std::min(nearest, std::sqrt(d2));
        }
        // Each coordinate moves at most 0.05 a: a pair's distance at most 0.1 sqrt(3) a.
        ASSERT_NEAR(nearest, a / std::sqrt(2.0), 0.1 * std::sqrt(3.0) * a) << i;
    }
}

TEST(BenchWorkloads, UniformCubeHasDensityOne) {
    const auto p = fb::generate<double>(fb::find_workload("W2"), 8000);
    const double side = 20;  // 8000^(1/3)
    double lo = 1e9, hi = -1e9, sum = 0;
    for (double x : p) lo = std::min(lo, x), hi = std::max(hi, x), sum += x;
    EXPECT_GE(lo, 0);
    EXPECT_LT(hi, side);
    EXPECT_NEAR(sum / double(p.size()), side / 2, 0.3);  // mean of 24000 uniforms
}

TEST(BenchWorkloads, ClustersHaveSigmaTwo) {
    const auto p = fb::generate<double>(fb::find_workload("W3"), 64 * 200);
    // Points i and i + 64 share a blob; their differences have variance 2 sigma^2 = 8.
    double sum2 = 0;
    std::size_t m = 0;
    for (std::size_t i = 0; i + 64 < p.size() / 3; ++i)
        for (int a = 0; a < 3; ++a, ++m) sum2 += std::pow(p[(i + 64) * 3 + a] - p[i * 3 + a], 2);
    EXPECT_NEAR(sum2 / double(m), 8.0, 0.4);
}

TEST(BenchWorkloads, PlaneIs2DAndOutlierIsLast) {
    const auto plane = fb::generate<float>(fb::find_workload("W4"), 100);
    EXPECT_EQ(plane.size(), 200u);
    const auto w5 = fb::generate<double>(fb::find_workload("W5"), 126);
    const auto w1 = fb::generate<double>(fb::find_workload("W1"), 125);
    ASSERT_EQ(w5.size(), w1.size() + 3);
    EXPECT_TRUE(std::equal(w1.begin(), w1.end(), w5.begin()));
    EXPECT_EQ(w5[w5.size() - 1], 1e7);
}

TEST(BenchWorkloads, MotionIsSmallAndNotZero) {
    const auto p = fb::generate<float>(fb::find_workload("W1"), 216);
    const auto q = fb::moved_copy<float>(p);
    ASSERT_EQ(p.size(), q.size());
    double biggest = 0;
    std::size_t moved = 0;
    for (std::size_t k = 0; k < p.size(); ++k) {
        biggest = std::max(biggest, std::abs(double(q[k]) - double(p[k])));
        moved += q[k] != p[k];
    }
    EXPECT_LE(biggest, 0.0501);
    EXPECT_GT(moved, p.size() * 9 / 10);
}

#include "frnn/bench/runner.hpp"

TEST(BenchWorkloads, SizesForAllOrForOneWorkload) {
    fb::config cfg;
    fb::parse_sizes("", cfg);
    fb::parse_sides("", cfg);
    EXPECT_EQ(fb::sizes_for(cfg, "W2"), fb::find_workload("W2").sizes);
    EXPECT_EQ(fb::sizes_for(cfg, "W5"), (std::vector<std::size_t>{1000001}));
    // Point counts: lattices round (W4: 31^2 = 961 and 32^2 = 1024 around 1000), repeats go.
    fb::parse_sizes("1000,w2=1000,343,W2=1000,W2=27,1001", cfg);
    EXPECT_EQ(fb::sizes_for(cfg, "W1"), (std::vector<std::size_t>{1000, 343}));
    EXPECT_EQ(fb::sizes_for(cfg, "W2"), (std::vector<std::size_t>{1000, 27}));
    EXPECT_EQ(fb::sizes_for(cfg, "W3"), (std::vector<std::size_t>{1000, 343, 1001}));
    EXPECT_EQ(fb::sizes_for(cfg, "W4"), (std::vector<std::size_t>{1024, 361}));
    // Sides add to the counts of the same reach; one workload's requests win over the rest.
    fb::parse_sides("4,W1=5", cfg);
    EXPECT_EQ(fb::sizes_for(cfg, "W1"), (std::vector<std::size_t>{125}));
    EXPECT_EQ(fb::sizes_for(cfg, "W4"), (std::vector<std::size_t>{1024, 361, 16}));
    EXPECT_EQ(fb::sizes_for(cfg, "W5"), (std::vector<std::size_t>{1001, 344, 65}));
    EXPECT_EQ(fb::sizes_for(cfg, "W2"), (std::vector<std::size_t>{1000, 27}));
    for (const char* bad : {"x", "8,", "W9=4", "W1=", "-3", "4.5"}) {
        fb::config c;
        EXPECT_THROW(fb::parse_sizes(bad, c), frnn::error) << bad;
        EXPECT_THROW(fb::parse_sides(bad, c), frnn::error) << bad;
    }
    fb::config c;
    expect_error([&] { (void)fb::parse_sides("W1=4,W3=5", c); }, {"--side: W3 is not a lattice workload"});
    EXPECT_TRUE(c.workload_sides.empty());  // nothing taken from a rejected list
    fb::parse_sizes("0", c);
    expect_error([&] { (void)fb::sizes_for(c, "W1"); }, {"N = 0"});
}
