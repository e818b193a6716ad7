// Picks the viscoelastic pair kernels of the widest level this CPU runs.
#include "frnn/simd.hpp"
#include "viscoelastic_pairs.hpp"

namespace frnn::sim::detail {

template <int D>
viscoelastic_pair_kernels<D> viscoelastic_pairs_for(std::string_view level) {
#if defined(FRNN_SIM_X86_LEVELS)
    if (level.empty()) level = frnn::simd_level();  // "avx512" includes AVX2
    if (level != "base" && frnn::simd_supported("avx2")) return avx2::viscoelastic_pairs<D>();
#else
    (void)level;
#endif
    return base::viscoelastic_pairs<D>();
}
template viscoelastic_pair_kernels<2> viscoelastic_pairs_for<2>(std::string_view);
template viscoelastic_pair_kernels<3> viscoelastic_pairs_for<3>(std::string_view);

}  // namespace frnn::sim::detail
