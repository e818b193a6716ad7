// The cell sweep compiled for the "avx2" instruction-set level (see sweep.hpp).
// Every header is included before the target region, so that only this level's own code
// (namespace below) is compiled for it; library and standard templates keep the default target.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "core/sweep.hpp"

#pragma GCC push_options
#pragma GCC target("avx2,popcnt,bmi,bmi2")
#define FRNN_SWEEP_NS avx2
#define FRNN_SWEEP_BYTES 32
#include "core/sweep_impl.hpp"
#pragma GCC pop_options
