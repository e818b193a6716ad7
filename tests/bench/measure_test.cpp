// The bench's memory accounting: what a baseline's lists took while it ran must not stay
// resident into the next method's peak RSS.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "frnn/bench/measure.hpp"
#include "frnn/bench/nanoflann_baseline.hpp"
#include "frnn/bench/workloads.hpp"

namespace {

std::size_t resident_bytes() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmRSS:", 0) == 0) return std::stoull(line.substr(6)) * 1024;
    return 0;
}

}  // namespace

TEST(measure, baseline_lists_built_by_threads_go_back_to_the_system) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer's allocator holds freed memory in quarantine";
#else
    namespace fb = frnn::bench;
    const fb::workload& w = fb::find_workload("W1");
    const auto points = fb::generate<float>(w, 262144);  // side 64, 28 neighbors each
    const fb::nanoflann_baseline<float, 3> tree(points, float(w.radius));
    fb::reset_peak_rss();
    const std::size_t before = resident_bytes();
    ASSERT_GT(before, 0u) << "no VmRSS in /proc/self/status";
    for (int round = 0; round < 2; ++round) {
        const auto lists = tree.neighbor_lists(2);  // 2 threads, about 14 MiB of ids each
        ASSERT_EQ(lists.rows(), points.size() / 3);
        ASSERT_GT(lists.indices.size(), 20u * lists.rows());
    }
    fb::reset_peak_rss();
    EXPECT_LT(resident_bytes(), before + (8u << 20));
#endif
}
