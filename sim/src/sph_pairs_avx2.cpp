// The WCSPH pair passes for the "avx2" level: AVX registers and gathers, no fused multiply-add
// (so the results equal the base level's bit for bit). Every header is included before the
// target region, so only this level's own code is compiled for it.
#include <cmath>
#include <cstring>

#include <immintrin.h>

#include "sph_pairs.hpp"

#pragma GCC push_options
#pragma GCC target("avx2")
#define FRNN_SIM_NS avx2
#define FRNN_SIM_AVX2 1
#include "sph_pairs_impl.hpp"
#pragma GCC pop_options
