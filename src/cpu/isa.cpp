#include "cpu/isa.hpp"

#include <cstdlib>

#include "frnn/simd.hpp"

namespace frnn::detail {

std::string_view isa_name(isa level) {
    switch (level) {
        case isa::avx512: return "avx512";
        case isa::avx2: return "avx2";
        case isa::base: break;
    }
    return "base";
}

bool isa_available(isa level) {
    if (level == isa::base) return true;
#if defined(FRNN_X86_LEVELS)
    __builtin_cpu_init();
    if (level == isa::avx2) return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
           __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq");
#else
    return false;
#endif
}

isa active_isa() {
    static const isa chosen = [] {
        isa cap = isa::avx512;
        if (const char* env = std::getenv("FRNN_SIMD")) {
            const std::string_view want(env);
            if (want == "base") cap = isa::base;
            else if (want == "avx2") cap = isa::avx2;
        }
        for (isa level : {isa::avx512, isa::avx2}) {
            if (level <= cap && isa_available(level)) return level;
        }
        return isa::base;
    }();
    return chosen;
}

}  // namespace frnn::detail

namespace frnn {

std::string_view simd_level() { return detail::isa_name(detail::active_isa()); }

bool simd_supported(std::string_view level) {
    for (auto l : {detail::isa::base, detail::isa::avx2, detail::isa::avx512}) {
        if (detail::isa_name(l) == level) return detail::isa_available(l);
    }
    return false;
}

}  // namespace frnn
