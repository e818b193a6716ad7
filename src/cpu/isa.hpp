// Instruction-set levels of the distance kernels, and the choice of one at run time.
#pragma once
#include <string_view>

namespace frnn::detail {

enum class isa { base, avx2, avx512 };

std::string_view isa_name(isa level);
/// Whether the build has kernels for `level` and the CPU can run them.
bool isa_available(isa level);
/// The level in use, chosen once: the widest available, capped by FRNN_SIMD when set.
isa active_isa();

}  // namespace frnn::detail
