// The viscoelastic pair passes on the base x86-64 level (SSE2), and portable elsewhere.
#include <cmath>
#include <cstring>

#if defined(__SSE__)
#include <immintrin.h>
#endif

#include "viscoelastic_pairs.hpp"

#define FRNN_SIM_NS base
#include "viscoelastic_pairs_impl.hpp"
