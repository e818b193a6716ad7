// The generators follow BENCHMARKS.md: sizes, bounds, dimension, determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "frnn/bench/workloads.hpp"
#include "frnn/error.hpp"

namespace fb = frnn::bench;

TEST(BenchWorkloads, ListParsing) {
    EXPECT_EQ(fb::parse_workload_list("all"),
              (std::vector<std::string>{"W1", "W2", "W3", "W4", "W5"}));
    EXPECT_EQ(fb::parse_workload_list("w2, W1,W2"), (std::vector<std::string>{"W2", "W1"}));
    EXPECT_THROW(fb::parse_workload_list("W7"), frnn::error);
    EXPECT_THROW(fb::parse_workload_list("W1,"), frnn::error);
}

TEST(BenchWorkloads, DefaultSizesAreThoseOfTheTable) {
    const auto& w1 = fb::find_workload("W1");
    std::vector<std::size_t> counts;
    for (auto s : w1.sizes) counts.push_back(fb::point_count(w1, s));
    EXPECT_EQ(counts, (std::vector<std::size_t>{32768, 262144, 1000000, 4096000}));
    const auto& w2 = fb::find_workload("W2");
    EXPECT_EQ(w2.sizes, counts);  // "N as W1"
    EXPECT_EQ(fb::point_count(fb::find_workload("W4"), 1000), 1000000u);
    EXPECT_EQ(fb::point_count(fb::find_workload("W5"), 100), 1000001u);
    EXPECT_THROW(fb::point_count(w1, 0), frnn::error);
    EXPECT_THROW(fb::point_count(w1, 5000), frnn::error);  // beyond 32-bit indices
}

TEST(BenchWorkloads, LatticeIsJitteredByAtMostATenth) {
    const auto& w = fb::find_workload("W1");
    const auto p = fb::generate<double>(w, 7);
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
        const std::size_t size = w.size_meaning == "points" ? 500 : 6;
        const auto a = fb::generate<float>(w, size), b = fb::generate<float>(w, size);
        EXPECT_EQ(a, b) << w.id;
        EXPECT_EQ(a.size(), fb::point_count(w, size) * std::size_t(w.dim)) << w.id;
        const auto d = fb::generate<double>(w, size);
        for (std::size_t k = 0; k < a.size(); ++k) ASSERT_EQ(a[k], float(d[k])) << w.id << " " << k;
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
    const auto plane = fb::generate<float>(fb::find_workload("W4"), 10);
    EXPECT_EQ(plane.size(), 200u);
    const auto w5 = fb::generate<double>(fb::find_workload("W5"), 5);
    const auto w1 = fb::generate<double>(fb::find_workload("W1"), 5);
    ASSERT_EQ(w5.size(), w1.size() + 3);
    EXPECT_TRUE(std::equal(w1.begin(), w1.end(), w5.begin()));
    EXPECT_EQ(w5[w5.size() - 1], 1e7);
}

TEST(BenchWorkloads, MotionIsSmallAndNotZero) {
    const auto p = fb::generate<float>(fb::find_workload("W1"), 6);
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
    EXPECT_EQ(fb::sizes_for(cfg, "W2"), fb::find_workload("W2").sizes);
    fb::parse_sizes("8,w2=1000,6,W2=1000,W2=27", cfg);
    EXPECT_EQ(fb::sizes_for(cfg, "W1"), (std::vector<std::size_t>{8, 6}));
    EXPECT_EQ(fb::sizes_for(cfg, "W2"), (std::vector<std::size_t>{1000, 27}));
    for (const char* bad : {"x", "8,", "W9=4", "W1=", "-3", "4.5"}) {
        fb::config c;
        EXPECT_THROW(fb::parse_sizes(bad, c), frnn::error) << bad;
    }
}
