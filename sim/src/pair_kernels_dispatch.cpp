// Picks the pair kernels (viscoelastic, WCSPH) of the widest level this CPU runs.
#include "frnn/simd.hpp"
#include "sph_pairs.hpp"
#include "viscoelastic_pairs.hpp"

namespace frnn::sim::detail {
namespace {

/// Whether the AVX2 kernels run for `level` (empty: the widest this CPU and FRNN_SIMD allow).
bool use_avx2([[maybe_unused]] std::string_view level) {
#if defined(FRNN_SIM_X86_LEVELS)
    if (level.empty()) level = frnn::simd_level();  // "avx512" includes AVX2
    return level != "base" && frnn::simd_supported("avx2");
#else
    return false;
#endif
}

}  // namespace

template <int D>
viscoelastic_pair_kernels<D> viscoelastic_pairs_for(std::string_view level) {
#if defined(FRNN_SIM_X86_LEVELS)
    if (use_avx2(level)) return avx2::viscoelastic_pairs<D>();
#endif
    return base::viscoelastic_pairs<D>();
}
template viscoelastic_pair_kernels<2> viscoelastic_pairs_for<2>(std::string_view);
template viscoelastic_pair_kernels<3> viscoelastic_pairs_for<3>(std::string_view);

template <int D>
sph_pair_kernels<D> sph_pairs_for(std::string_view level) {
#if defined(FRNN_SIM_X86_LEVELS)
    if (use_avx2(level)) return avx2::sph_pairs<D>();
#endif
    return base::sph_pairs<D>();
}
template sph_pair_kernels<2> sph_pairs_for<2>(std::string_view);
template sph_pair_kernels<3> sph_pairs_for<3>(std::string_view);

}  // namespace frnn::sim::detail
