// The bench's memory accounting: what one method freed must not stay resident into the next
// method's peak RSS.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "frnn/bench/measure.hpp"

namespace {

std::size_t resident_bytes() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmRSS:", 0) == 0) return std::stoull(line.substr(6)) * 1024;
    return 0;
}

// Grows lists by push_back in worker threads, as the baselines' row builder does, and frees
// them there.
void grow_lists_in_threads() {
    std::vector<std::thread> workers;
    for (int t = 0; t < 2; ++t)
        workers.emplace_back([] {
            for (int round = 0; round < 2; ++round) {
                std::vector<std::uint32_t> ids;
                for (std::uint32_t i = 0; i < (6u << 20); ++i) ids.push_back(i);
                ASSERT_EQ(ids[12345], 12345u);
            }
        });
    for (auto& w : workers) w.join();
}

}  // namespace

TEST(measure, memory_freed_by_worker_threads_goes_back_to_the_system) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer's allocator holds freed memory in quarantine";
#else
    frnn::bench::map_large_blocks_alone();
    frnn::bench::reset_peak_rss();
    const std::size_t before = resident_bytes();
    ASSERT_GT(before, 0u) << "no VmRSS in /proc/self/status";
    grow_lists_in_threads();  // 2 x 2 x 24 MiB at the largest
    frnn::bench::reset_peak_rss();
    EXPECT_LT(resident_bytes(), before + (8u << 20));
#endif
}
