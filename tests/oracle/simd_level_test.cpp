// The kernel level in use is the one FRNN_SIMD asks for when the CPU has it, and otherwise the
// best one available; the oracle tests then check that level's results.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "frnn/simd.hpp"

namespace {

TEST(SimdLevel, IsAvailableAndHonoursTheRequest) {
    const std::string level(frnn::simd_level());
    // Read by scripts/test_summary.py, which lists the levels the oracle tests ran at.
    std::printf("frnn oracle tests at instruction-set level: %s\n", level.c_str());
    EXPECT_TRUE(frnn::simd_supported(level)) << level;
    EXPECT_TRUE(frnn::simd_supported("base"));
    EXPECT_FALSE(frnn::simd_supported("sse9"));
    const char* want = std::getenv("FRNN_SIMD");
    if (want && frnn::simd_supported(want)) {
        EXPECT_EQ(level, want);
    } else if (!want) {
        // Unrestricted: the widest level available.
        const std::string best = frnn::simd_supported("avx512") ? "avx512" : frnn::simd_supported("avx2") ? "avx2" : "base";
        EXPECT_EQ(level, best);
    }
}

}  // namespace
