// Which vector instructions frnn's distance kernels use.
//
// The kernels are compiled for several x86-64 levels and the widest one this CPU runs is
// chosen at first use, so one binary is fast everywhere. Every level computes bit-identical
// results (no fused multiply-add). Setting the environment variable FRNN_SIMD to "base",
// "avx2" or "avx512" before the first query caps the level (for comparisons and tests); a level
// the CPU or build lacks falls back to the best one available.
#pragma once
#include <string_view>

namespace frnn {

/// The level in use: "avx512", "avx2" or "base" (SSE2 on x86-64, portable code elsewhere).
std::string_view simd_level();
/// Whether this build and CPU can run `level`.
bool simd_supported(std::string_view level);

}  // namespace frnn
