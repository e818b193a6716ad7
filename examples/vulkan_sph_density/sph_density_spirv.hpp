// The SPIR-V of sph_density.comp, compiled by glslc and embedded at build time
// (frnn_embed_spirv in the CMake files).
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>

namespace frnn::spirv {
extern const std::uint32_t sph_density[];
extern const std::size_t sph_density_words;
}  // namespace frnn::spirv

inline std::span<const std::uint32_t> sph_density_spirv() {
    return {frnn::spirv::sph_density, frnn::spirv::sph_density_words};
}
