// The WCSPH pair passes on the base x86-64 level (SSE2), and portable elsewhere.
#include <cmath>
#include <cstring>

#if defined(__SSE__)
#include <immintrin.h>
#endif

#include "sph_pairs.hpp"

#define FRNN_SIM_NS base
#include "sph_pairs_impl.hpp"
