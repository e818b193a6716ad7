// Chooses the sweep kernels of the instruction-set level in use.
#include "core/sweep.hpp"
#include "cpu/isa.hpp"

namespace frnn::detail {

template <class T, int D>
const sweep_kernels<T, D>& sweep_for_cpu() {
#if defined(FRNN_X86_LEVELS)
    switch (active_isa()) {
        case isa::avx512: return avx512::table<T, D>();
        case isa::avx2: return avx2::table<T, D>();
        case isa::base: break;
    }
#endif
    return base::table<T, D>();
}

template const sweep_kernels<float, 2>& sweep_for_cpu<float, 2>();
template const sweep_kernels<float, 3>& sweep_for_cpu<float, 3>();
template const sweep_kernels<double, 2>& sweep_for_cpu<double, 2>();
template const sweep_kernels<double, 3>& sweep_for_cpu<double, 3>();

}  // namespace frnn::detail
